// `rayes farm submit`: checks everything, writes the two scripts into the parts folder and
// submits them with sbatch (or prints them: --dry-run).
//
// Why the merge waits with afterany, not afterok: Slurm's afterok on an array job remembers a
// task that ended badly even after that task is requeued and completes (measured on Slurm
// 22.05: `scancel --signal=KILL` on one task, `scontrol requeue` of it, all four tasks then
// COMPLETED, and the merge still ends DependencyNeverSatisfied). afterany waits until every
// task has ended, a requeued one included, and the merge script itself refuses a missing part,
// naming it (rayes merge does; the script adds the task's log and how to requeue it).
#include "app/farm_command.h"
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <CLI/CLI.hpp>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>
#include "app/command_line.h"
#include "app/commands.h"
#include "app/farm_script.h"
#include "app/render_args.h"
#include "core/error.h"

extern char** environ;

namespace rayes {
namespace {
namespace fs = std::filesystem;

// Characters a path may have where Slurm reads it unquoted (#SBATCH lines; '%' would be one of
// sbatch's filename patterns).
bool slurmSafe(const std::string& s) {
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || std::strchr("/._-+=:,@", c))) return false;
  return !s.empty();
}

std::string absolute(const std::string& path) { return fs::absolute(path).lexically_normal().string(); }

// The render options as words again, from what `rayes render`'s parser made of them: each
// option given, in the parser's order, as --name=value (so a value such as -2 stays a value),
// flags bare. Options the farm sets itself are refused.
std::vector<std::string> renderWordsFrom(CLI::App* render, bool& threadsGiven) {
  static const std::set<std::string> setPerTask = {"--part", "--checkpoint", "--resume"};
  static const std::set<std::string> farmOutputs = {"--output", "--stats", "--report"};
  std::vector<std::string> words;
  threadsGiven = false;
  for (const CLI::Option* o : render->get_options()) {
    if (o->count() == 0 || !o->nonpositional()) continue;
    const std::string name = o->get_name();
    if (setPerTask.count(name))
      throw InputError(name, "", "farm submit sets --part, --checkpoint and --resume for every task itself");
    if (farmOutputs.count(name))
      throw InputError(name, "", "not an option of farm submit (its outputs are -o and --stats, written by the merge)");
    if (name == "--threads") threadsGiven = true;
    const bool isLong = name.rfind("--", 0) == 0;
    for (const std::string& v : o->results()) {
      if (o->get_expected_min() == 0) {  // a flag
        words.push_back(v == "true" ? name : name + "=" + v);
      } else if (isLong) {
        words.push_back(name + "=" + v);
      } else {
        words.push_back(name);
        words.push_back(v);
      }
    }
  }
  return words;
}

// The program on PATH, or empty.
std::string onPath(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "/usr/bin:/bin";
  size_t start = 0;
  while (start <= dirs.size()) {
    size_t end = dirs.find(':', start);
    if (end == std::string::npos) end = dirs.size();
    const std::string candidate = (end > start ? dirs.substr(start, end - start) : ".") + "/" + program;
    if (::access(candidate.c_str(), X_OK) == 0) return candidate;
    start = end + 1;
  }
  return "";
}

// Runs `args` (args[0] looked up on PATH), its stderr to ours; returns its exit code (-1 if it
// could not run) and its stdout in `out`.
int runCapturing(const std::vector<std::string>& args, std::string& out) {
  int pipeFds[2];
  if (::pipe(pipeFds) != 0) return -1;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipeFds[1], STDOUT_FILENO);
  posix_spawn_file_actions_addclose(&actions, pipeFds[0]);
  posix_spawn_file_actions_addclose(&actions, pipeFds[1]);
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(pipeFds[1]);
  if (spawned != 0) {
    ::close(pipeFds[0]);
    return -1;
  }
  char buf[4096];
  ssize_t n;
  while ((n = ::read(pipeFds[0], buf, sizeof buf)) > 0 || (n < 0 && errno == EINTR))
    if (n > 0) out.append(buf, size_t(n));
  ::close(pipeFds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// The job id sbatch --parsable printed ("123" or "123;cluster"), or empty.
std::string jobIdFrom(const std::string& out) {
  size_t n = 0;
  while (n < out.size() && std::isdigit(static_cast<unsigned char>(out[n]))) ++n;
  return out.substr(0, n);
}

std::string commandLine(const std::vector<std::string>& args) {
  std::string s;
  for (const std::string& a : args) s += (s.empty() ? "" : " ") + shellQuoted(a);
  return s;
}

void writeScript(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::trunc);
  out << text;
  out.close();
  if (!out) throw InputError(path, "", "cannot write the job script here");
  fs::permissions(path, fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec |
                            fs::perms::others_read | fs::perms::others_exec);
}

// The checked FarmJob, from the farm's options and the render words; throws InputError.
FarmJob checkedJob(const FarmArgs& a, const std::vector<std::string>& renderWords) {
  if (a.tasks < 1 || a.tasks > 100000) throw InputError("--tasks", "", "must be in [1, 100000]");
  RenderArgs ra;
  CLI::App parser;
  CLI::App* render = addRenderCommand(parser, ra);
  std::vector<std::string> words = {"rayes", "render"};
  words.insert(words.end(), renderWords.begin(), renderWords.end());
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  try {
    parser.parse(int(argv.size()), argv.data());
  } catch (const CLI::ParseError& e) {
    throw InputError("farm submit", "", std::string(e.what()) + " (the scene and the options of 'rayes render --help')");
  }
  // The render command takes extras so that `rayes render` can name a mistyped option; here
  // they are refused as they are there.
  if (const std::vector<std::string> rest = render->remaining(); !rest.empty())
    throw InputError("farm submit", "", rest.front() + ": not an option of rayes render (see rayes render --help)");
  FarmJob job;
  job.renderArgs = renderWordsFrom(render, job.threadsGiven);
  if (ra.scene == "-") throw InputError("farm submit", "", "the tasks read the scene from a file: give its path, not -");
  // Everything a task would refuse, refused now: the options, then the scene itself.
  checkedOptions(ra);
  preparedScene(ra);

  job.tasks = a.tasks;
  job.partition = a.partition;
  if (!a.partition.empty() && !slurmSafe(a.partition))
    throw InputError("--partition", "", "'" + a.partition + "' is not a partition name");
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw InputError("/proc/self/exe", "", "cannot find the rayes binary the tasks should run");
  job.rayes = exe.string();
  job.scene = absolute(ra.scene);
  job.workDir = fs::current_path().string();
  const std::string stem = fs::path(ra.scene).stem().string();
  job.outputs = a.outputs;
  if (job.outputs.empty()) job.outputs.push_back("out/" + stem + ".exr");
  for (std::string& o : job.outputs) {
    checkOutputName(o);
    o = absolute(o);
  }
  if (!a.stats.empty()) {
    if (lowerExtension(a.stats) != ".json") throw InputError(a.stats, "", "--stats must end in .json");
    job.stats = absolute(a.stats);
  }
  // The parts folder: given, or beside the first output, named after it.
  const fs::path first(job.outputs.front());
  job.dir = absolute(a.dir.empty() ? (first.parent_path() / (first.stem().string() + ".parts")).string() : a.dir);
  while (job.dir.size() > 1 && job.dir.back() == '/') job.dir.pop_back();
  if (!slurmSafe(job.dir))
    throw InputError(job.dir, "", "the parts folder (--dir) may hold only letters, digits and / . _ - + = : , @ "
                                  "(Slurm reads it unquoted in the job scripts)");
  if (fs::exists(job.dir) && !fs::is_directory(job.dir)) throw InputError(job.dir, "", "the parts folder (--dir) is not a folder");
  if (fs::is_directory(job.dir))
    for (const auto& e : fs::directory_iterator(job.dir, ec))
      if (e.path().filename().string().rfind("part-", 0) == 0)
        throw InputError(e.path().string(), "", "the parts folder holds parts of an earlier job: remove them, or give "
                                                "another --dir");
  std::string name;
  for (char c : stem) name += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' ? c : '_';
  job.name = "rayes-" + name;
  return job;
}

// The two sbatch calls: the render array, and the merge after the render job `renderId`.
std::vector<std::string> renderCall(const FarmArgs& a, const std::string& script) {
  std::vector<std::string> call = {"sbatch", "--parsable"};
  call.insert(call.end(), a.sbatchArgs.begin(), a.sbatchArgs.end());
  call.push_back(script);
  return call;
}
std::vector<std::string> mergeCall(const FarmArgs& a, const std::string& renderId, const std::string& script) {
  std::vector<std::string> call = {"sbatch", "--parsable", "--dependency=afterany:" + renderId,
                                   "--kill-on-invalid-dep=yes", "--export=ALL,RAYES_FARM_RENDER_JOB=" + renderId};
  call.insert(call.end(), a.sbatchArgs.begin(), a.sbatchArgs.end());
  call.push_back(script);
  return call;
}

// Submits the two scripts; prints the job ids. Throws InputError when sbatch refuses a job,
// after cancelling the render job when only the merge was refused.
void submit(const FarmJob& job, const FarmArgs& a, const std::string& renderPath, const std::string& mergePath) {
  const std::vector<std::string> renderArgs = renderCall(a, renderPath);
  std::string out;
  int code = runCapturing(renderArgs, out);
  const std::string renderId = jobIdFrom(out);
  if (code != 0 || renderId.empty())
    throw InputError("sbatch", "", "refused the render job (its message above): " + commandLine(renderArgs));

  const std::vector<std::string> mergeArgs = mergeCall(a, renderId, mergePath);
  out.clear();
  code = runCapturing(mergeArgs, out);
  const std::string mergeId = jobIdFrom(out);
  if (code != 0 || mergeId.empty()) {
    std::string ignored;
    runCapturing({"scancel", renderId}, ignored);
    throw InputError("sbatch", "", "refused the merge job (its message above), so render job " + renderId +
                                       " was cancelled: " + commandLine(mergeArgs));
  }
  std::printf("render job %s: %d tasks, parts and logs in %s\n", renderId.c_str(), job.tasks, job.dir.c_str());
  std::printf("merge job %s: writes %s once every task has ended\n", mergeId.c_str(), job.outputs.front().c_str());
  std::fflush(stdout);
}

}  // namespace

CLI::App* addFarmCommand(CLI::App& app, FarmArgs& a) {
  CLI::App* farm = app.add_subcommand("farm", "render on a Slurm cluster (docs/batch-and-farm.md, \"Slurm\")");
  farm->require_subcommand(1);
  CLI::App* s = farm->add_subcommand(
      "submit",
      "submit SCENE as a Slurm array job of --tasks parts (task i: rayes render --part i/N with a checkpoint, "
      "requeued to resume when stopped) and a job that merges the parts once every task has ended. Takes every "
      "option of 'rayes render' that says how to render; after --, options for sbatch (both jobs), e.g. "
      "-- --account=A --time=2:00:00");
  s->add_option("--tasks", a.tasks, "parts, one array task each (1..100000)")->required();
  s->add_option("--partition", a.partition, "the Slurm partition of both jobs (default: the cluster's)");
  s->add_option("--dir", a.dir, "the folder for the parts, their checkpoints and logs, and the two job scripts, on a "
                                "filesystem every node sees (default: beside the first output, OUT.parts/)");
  s->add_option("-o,--output", a.outputs, "the merged image(s): .exr, .png or .film; may be given several times "
                                          "(default out/<scene>.exr)");
  s->add_option("--stats", a.stats, "the merged render statistics, JSON (docs/stats.md)");
  s->add_flag("--dry-run", a.dryRun, "print the two job scripts and the sbatch commands; write and submit nothing");
  s->footer("SCENE and the render options come as for 'rayes render SCENE [options]' (rayes render --help); "
            "-o, --stats and the per-task --part, --checkpoint and --resume are the farm's.");
  s->allow_extras();
  return s;
}

int runFarmSubmit(const FarmArgs& a, const std::vector<std::string>& renderWords) {
  const FarmJob job = checkedJob(a, renderWords);
  const std::string renderPath = job.dir + "/render.sh", mergePath = job.dir + "/merge.sh";
  if (a.dryRun) {
    std::printf("# %s\n%s\n# %s\n%s", commandLine(renderCall(a, renderPath)).c_str(), renderScript(job).c_str(),
                commandLine(mergeCall(a, "<render job>", mergePath)).c_str(), mergeScript(job).c_str());
    return 0;
  }
  if (onPath("sbatch").empty())
    throw InputError("sbatch", "", "not found on PATH: run farm submit where Slurm's commands are installed (a login "
                                   "node), or print the job scripts with --dry-run");
  // Written before submitting (sbatch reads the file); removed again if a job is refused.
  const bool madeDir = !fs::exists(job.dir);
  std::error_code ec;
  fs::create_directories(job.dir, ec);
  if (ec) throw InputError(job.dir, "", "cannot create the parts folder: " + ec.message());
  try {
    writeScript(renderPath, renderScript(job));
    writeScript(mergePath, mergeScript(job));
    submit(job, a, renderPath, mergePath);
  } catch (...) {
    fs::remove(renderPath, ec);
    fs::remove(mergePath, ec);
    if (madeDir) fs::remove(job.dir, ec);  // only when empty
    throw;
  }
  return 0;
}

}  // namespace rayes
