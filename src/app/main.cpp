#include "app/command_line.h"
#include "app/huge_pages.h"

int main(int argc, char** argv) {
  rayes::restartWithHugePages(argv);
  return rayes::runCommandLine(argc, argv);
}
