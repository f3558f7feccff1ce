// The two Slurm batch scripts of `rayes farm submit` (farm_command.cpp writes and submits them;
// docs/batch-and-farm.md, "Slurm", explains them to users). Pure text: no Slurm, no files, no
// clock, so tests read them as they are and run them with stand-ins for rayes and scontrol.
//  - the render script, an array job `--array=1-N`: task i runs `rayes render SCENE <options>
//    --part i/N -o DIR/part-i.film --checkpoint DIR/part-i.checkpoint`, adding `--resume` when
//    that checkpoint exists (a task requeued after a kill continues from it). It exits with
//    rayes's exit code; on exit code 4 (stopped with a checkpoint: rayes's --time-limit, or
//    USR1, which Slurm sends 120 s before the job's time limit and the script turns into TERM
//    for rayes) it requeues itself with `scontrol requeue`, unless the job is being cancelled
//    (TERM to the script: scancel, the time limit itself), which stays cancelled.
//  - the merge script: `rayes merge DIR/part-1.film ... DIR/part-N.film -o OUT...`, submitted
//    with `--dependency=afterany:<render job>` (see farm_command.cpp for why not afterok); a
//    missing part (a task that failed or was cancelled) is named with the task's log and the
//    way to requeue it, and rayes merge refuses it.
// Every path in a FarmJob is absolute; the scripts `cd` to workDir so relative paths inside the
// render options (a reference image, say) mean what they meant where the job was submitted.
#pragma once
#include <string>
#include <vector>

namespace rayes {

struct FarmJob {
  std::string rayes;                    // the rayes binary every task runs
  std::string scene;                    // the scene file
  std::string workDir;                  // the folder `rayes farm submit` ran in
  std::vector<std::string> renderArgs;  // options for `rayes render`, one token each, as given
  bool threadsGiven = false;            // renderArgs has --threads: leave it alone
  int tasks = 1;
  std::string dir;                      // parts, checkpoints, logs and the two scripts
  std::vector<std::string> outputs;     // the merge's -o (.exr, .png or .film)
  std::string stats;                    // the merge's --stats, or empty
  std::string partition;                // --partition for both jobs, or empty (the cluster's default)
  std::string name;                     // the render job's name; the merge's is "<name>-merge"
};

// `text` as one word for bash, in single quotes unless it needs none.
std::string shellQuoted(const std::string& text);
// DIR/part-I.film, DIR/part-I.checkpoint, DIR/part-I.log (I from 1).
std::string partFilm(const FarmJob& job, int i);
std::string partCheckpoint(const FarmJob& job, int i);
std::string partLog(const FarmJob& job, int i);
std::string mergeLog(const FarmJob& job);

std::string renderScript(const FarmJob& job);
std::string mergeScript(const FarmJob& job);

// Seconds before the time limit at which Slurm sends the render task USR1 (its #SBATCH
// --signal line; `-- --signal=B:USR1@S` on the command line overrides it).
constexpr int kCheckpointWarningSeconds = 120;

}  // namespace rayes
