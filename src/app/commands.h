// The subcommands of the `rayes` command line, each from its parsed arguments; both return the
// exit code and throw InputError for bad input (command_line.cpp turns it into exit code 2).
#pragma once
#include <string>
#include <vector>
#include "app/render_args.h"

namespace rayes {

// `rayes merge`'s arguments.
struct MergeArgs {
  std::vector<std::string> parts, outputs;
  std::string stats;
  bool quiet = false;
};

// `rayes compile`'s arguments.
struct CompileArgs {
  std::string scene, out;
  bool quiet = false;
};

// `rayes report`'s arguments.
struct ReportArgs {
  std::vector<std::string> stats;
  std::string out;
  bool compare = false, quiet = false;
  std::string watch;          // --watch DIR: rewrite the page as the job's parts appear (report_watch.cpp)
  int watchUntil = 0;         // --watch-until N: complete once N stats were read (0: no such bound)
  double watchInterval = 1;   // --watch-interval S: seconds between looks
};

int runRender(const RenderArgs& a);    // render_command.cpp
int runCompile(const CompileArgs& a);  // compile_command.cpp
int runConverge(const RenderArgs& a);  // converge_command.cpp
int runMerge(const MergeArgs& a);      // merge_command.cpp
int runReport(const ReportArgs& a);    // report_command.cpp
int runReportWatch(const ReportArgs& a);  // report_watch.cpp (runReport with --watch)

// An output's extension, lower case (".exr"); and the one check of an image output's name
// (render's and merge's -o, farm submit's outputs): .exr, .png or .film, else InputError("-o").
std::string lowerExtension(const std::string& path);  // render_command.cpp
void checkOutputName(const std::string& out);         // render_command.cpp

}  // namespace rayes
