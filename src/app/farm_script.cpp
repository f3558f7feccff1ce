#include "app/farm_script.h"
#include <sstream>

namespace rayes {
namespace {

bool plainWord(const std::string& s) {
  if (s.empty()) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || std::string_view("/._-+=:,@%").find(c) != std::string_view::npos))
      return false;
  return true;
}

// `text` for a comment line: a control character (a newline in a file name) would end the comment.
std::string commentSafe(std::string text) {
  for (char& c : text)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  return text;
}

// "#SBATCH --partition=P" when P is set.
std::string partitionLine(const FarmJob& job) {
  return job.partition.empty() ? "" : "#SBATCH --partition=" + job.partition + "\n";
}

}  // namespace

std::string shellQuoted(const std::string& text) {
  if (plainWord(text)) return text;
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string partFilm(const FarmJob& job, int i) { return job.dir + "/part-" + std::to_string(i) + ".film"; }
std::string partCheckpoint(const FarmJob& job, int i) { return job.dir + "/part-" + std::to_string(i) + ".checkpoint"; }
std::string partLog(const FarmJob& job, int i) { return job.dir + "/part-" + std::to_string(i) + ".log"; }
std::string mergeLog(const FarmJob& job) { return job.dir + "/merge.log"; }

std::string renderScript(const FarmJob& job) {
  const std::string n = std::to_string(job.tasks), d = shellQuoted(job.dir);
  std::ostringstream s;
  s << "#!/bin/bash\n"
       "# Written by `rayes farm submit`: task I of this array job renders part I/" << n << " of\n"
       "# " << commentSafe(job.scene) << "\n"
       "# (docs/batch-and-farm.md, \"Slurm\"). Resubmit it with `sbatch [options] " << job.dir << "/render.sh`.\n"
       "#SBATCH --job-name=" << job.name << "\n"
       "#SBATCH --array=1-" << n << "\n"
       "#SBATCH --output=" << job.dir << "/part-%a.log\n"
       "#SBATCH --open-mode=append\n"
       "#SBATCH --requeue\n"
       "#SBATCH --signal=B:USR1@" << kCheckpointWarningSeconds << "\n"
    << partitionLine(job) <<
       "set -u\n"
       "cd " << shellQuoted(job.workDir) << " || exit 2\n"
       "i=${SLURM_ARRAY_TASK_ID:?this script runs as a Slurm array task}\n"
       "part=" << d << "/part-$i\n"
       "# A checkpoint is there when an earlier run of this task was stopped or killed: go on from it.\n"
       "resume=()\n"
       "if [ -f \"$part.checkpoint\" ]; then resume=(--resume); fi\n";
  if (!job.threadsGiven)
    s << "threads=()\n"
         "if [ -n \"${SLURM_CPUS_PER_TASK:-}\" ]; then threads=(--threads \"$SLURM_CPUS_PER_TASK\"); fi\n";
  s << "echo \"rayes farm: part $i/" << n << " on $(hostname) at $(date '+%F %T'), restart ${SLURM_RESTART_COUNT:-0}"
       "${resume:+, resuming from $part.checkpoint}\"\n"
    << shellQuoted(job.rayes) << " render " << shellQuoted(job.scene);
  for (const std::string& a : job.renderArgs) s << ' ' << shellQuoted(a);
  if (!job.threadsGiven) s << " \"${threads[@]}\"";
  s << " --part \"$i/" << n << "\" -o \"$part.film\" --checkpoint \"$part.checkpoint\" \"${resume[@]}\" &\n"
       "rayes=$!\n"
       "# Run in the background so signals reach this shell while rayes runs. USR1 (the #SBATCH\n"
       "# --signal warning before the time limit, sent to this shell alone) stops rayes with a\n"
       "# checkpoint; TERM or INT (a cancel, the time limit: Slurm signals every process of the task,\n"
       "# rayes too) marks the task as ending, so it is not requeued.\n"
       "ending=no\n"
       "trap 'kill -TERM \"$rayes\" 2>/dev/null' USR1\n"
       "trap 'ending=yes' TERM INT\n"
       "while kill -0 \"$rayes\" 2>/dev/null; do wait \"$rayes\"; done\n"
       "wait \"$rayes\"\n"
       "rc=$?\n"
       "echo \"rayes farm: part $i ended with exit code $rc; CPU time (user system) of this shell, then of rayes:\"\n"
       "times\n"
       "if [ \"$rc\" -eq 0 ]; then rm -f \"$part.checkpoint\"; fi\n"
       "if [ \"$rc\" -eq 4 ] && [ \"$ending\" = no ] && [ -n \"${SLURM_ARRAY_JOB_ID:-}\" ]; then\n"
       "  echo \"rayes farm: part $i stopped with a checkpoint (exit code 4): requeued, it resumes from it\"\n"
       "  # Slurm stops this script at once and runs the task again later.\n"
       "  scontrol requeue \"${SLURM_ARRAY_JOB_ID}_$i\" && exit 4\n"
       "  echo \"rayes farm: scontrol requeue failed; requeue the task by hand: scontrol requeue ${SLURM_ARRAY_JOB_ID}_$i\" >&2\n"
       "fi\n"
       "exit \"$rc\"\n";
  return s.str();
}

std::string mergeScript(const FarmJob& job) {
  std::ostringstream s;
  s << "#!/bin/bash\n"
       "# Written by `rayes farm submit`: merges the " << job.tasks << " parts of\n"
       "# " << commentSafe(job.scene) << "\n"
       "# once every task of the render job has ended (docs/batch-and-farm.md, \"Slurm\"). Run it again\n"
       "# after requeueing a failed task: `sbatch [options] --dependency=afterany:<render job> " << job.dir << "/merge.sh`.\n"
       "#SBATCH --job-name=" << job.name << "-merge\n"
       "#SBATCH --output=" << job.dir << "/merge.log\n"
       "#SBATCH --open-mode=append\n"
    << partitionLine(job) <<
       "set -u\n"
       "cd " << shellQuoted(job.workDir) << " || exit 2\n"
       "echo \"rayes farm: merging on $(hostname) at $(date '+%F %T')\"\n"
       "for i in $(seq 1 " << job.tasks << "); do\n"
       "  if [ ! -f " << shellQuoted(job.dir) << "/part-$i.film ]; then\n"
       "    echo \"rayes farm: part $i is missing: its task did not finish (its log: " << job.dir
    << "/part-$i.log); requeue it (scontrol requeue ${RAYES_FARM_RENDER_JOB:-<render job>}_$i), then submit this script again\" >&2\n"
       "  fi\n"
       "done\n"
    << shellQuoted(job.rayes) << " merge";
  for (int i = 1; i <= job.tasks; ++i) s << " \\\n  " << shellQuoted(partFilm(job, i));
  for (const std::string& o : job.outputs) s << " \\\n  -o " << shellQuoted(o);
  if (!job.stats.empty()) s << " \\\n  --stats " << shellQuoted(job.stats);
  s << "\n"
       "rc=$?\n"
       "echo \"rayes farm: merge ended with exit code $rc; CPU time (user system) of this shell, then of rayes:\"\n"
       "times\n"
       "exit \"$rc\"\n";
  return s.str();
}

}  // namespace rayes
