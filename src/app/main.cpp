#include "app/allocator_settings.h"
#include "app/command_line.h"
#include "app/huge_pages.h"

int main(int argc, char** argv) {
  rayes::restartWithHugePages(argv);
  rayes::returnLargeBlocksWhenFreed();
  return rayes::runCommandLine(argc, argv);
}
