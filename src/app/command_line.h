// The `rayes` command line. Exit codes: 0 success, 2 bad input (arguments, scene, files;
// one message naming the file and place, nothing written at the output paths), 3 a resource
// limit the settings would exceed (ResourceError: the message names the option to change,
// nothing written), 1 anything else (a bug or the machine failing).
#pragma once

namespace rayes {
int runCommandLine(int argc, char** argv);
}
