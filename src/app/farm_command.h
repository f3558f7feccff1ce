// `rayes farm submit SCENE --tasks N [--partition P] [--dir D] [-o OUT ...] [--stats S.json]
// [--dry-run] [render options ...] [-- sbatch options ...]`: renders a frame on a Slurm cluster
// as an array job of N parts and a merge job (the scripts: farm_script.h; for users:
// docs/batch-and-farm.md, "Slurm"). Everything is checked before anything is submitted: the
// render options are parsed by `rayes render`'s own parser (addRenderCommand) and checked, and
// the scene is loaded; bad input, sbatch missing or refusing a job: exit code 2, with nothing
// left submitted and no script left behind.
#pragma once
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace rayes {

struct FarmArgs {
  int tasks = 0;
  std::string partition, dir, stats;
  std::vector<std::string> outputs;
  bool dryRun = false;
  std::vector<std::string> sbatchArgs;  // the words after `--`, for both sbatch calls
};

// Adds `farm` with its subcommand `submit` to `app`; returns `submit`. Its unknown words (the
// scene and the render options) are left for runFarmSubmit (CLI::App::remaining()).
CLI::App* addFarmCommand(CLI::App& app, FarmArgs& a);
// `renderWords`: the scene and the render options, as the user wrote them.
int runFarmSubmit(const FarmArgs& a, const std::vector<std::string>& renderWords);

}  // namespace rayes
