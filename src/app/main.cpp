#include "app/command_line.h"

int main(int argc, char** argv) { return rayes::runCommandLine(argc, argv); }
