// The `rayes` command line. Exit codes: 0 success, 2 bad input (arguments, scene, files;
// one message naming the file and place, nothing written at the output paths), 3 a resource
// limit the settings would exceed (ResourceError: the message names the option to change,
// nothing written), 1 anything else (a bug or the machine failing).
#pragma once

namespace CLI {
class App;
}

namespace rayes {
struct RenderArgs;

int runCommandLine(int argc, char** argv);
// Adds the `render` subcommand, every option of `rayes render`, filling `a`; returns it.
// `rayes farm submit` parses its render options with it too.
CLI::App* addRenderCommand(CLI::App& app, RenderArgs& a);
}
