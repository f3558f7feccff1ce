// The job scripts of `rayes farm submit` (app/farm_script.h), run by bash as Slurm would run
// them, with stand-ins for rayes and scontrol that record their arguments: which part a task
// renders, when it resumes, when it requeues itself, what the merge reads. No Slurm needed.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include "app/farm_script.h"
#include "support/temp_folder.h"

namespace rayes {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

class FarmScript : public ::testing::Test {
 protected:
  FarmScript() {
    // The stand-in rayes writes its arguments, one a line, and exits with $STANDIN_CODE; with
    // STANDIN_CODE=wait it waits for TERM (as rayes does, writing a checkpoint) and exits 4.
    temp_.write("bin/rayes",
                "#!/bin/bash\n"
                "printf '%s\\n' \"$@\" > \"$STANDIN_DIR/args\"\n"
                "if [ \"$STANDIN_CODE\" = wait ]; then\n"
                "  trap 'echo TERM >> \"$STANDIN_DIR/signals\"; exit 4' TERM\n"
                "  echo $$ > \"$STANDIN_DIR/pid\"\n"
                "  touch \"$STANDIN_DIR/started\"\n"
                "  while :; do sleep 0.01; done\n"
                "fi\n"
                "exit \"$STANDIN_CODE\"\n");
    temp_.write("bin/scontrol", "#!/bin/bash\necho \"$@\" >> \"$STANDIN_DIR/scontrol\"\n");
    for (const char* p : {"bin/rayes", "bin/scontrol"}) fs::permissions(temp_.path(p), fs::perms::owner_all);
    job_.rayes = temp_.path("bin/rayes");
    job_.scene = "/scenes/a scene's.json";
    job_.workDir = temp_.dir().string();
    job_.renderArgs = {"--spp=16", "--lod-bias=-2", "--quiet"};
    job_.tasks = 4;
    job_.dir = temp_.path("parts");
    job_.outputs = {"/out/frame.exr", "/out/frame.png"};
    job_.stats = "/out/frame.json";
    job_.name = "rayes-frame";
    fs::create_directories(job_.dir);
  }

  // Runs `script` as array task `task` of job 77 (bash, with the stand-ins first on PATH);
  // `then` is more shell run while the script runs in the background (its pid: $s). Returns
  // the script's exit code.
  int runTask(const std::string& script, int task, const std::string& code, const std::string& then = "") {
    const std::string file = temp_.write("task.sh", script);
    const std::string cmd = "cd " + temp_.dir().string() + " && export PATH=" + temp_.path("bin") +
                            ":$PATH STANDIN_DIR=" + temp_.dir().string() + " STANDIN_CODE=" + code +
                            " SLURM_ARRAY_JOB_ID=77 SLURM_ARRAY_TASK_ID=" + std::to_string(task) +
                            " && { bash " + file + " > task.out 2>&1 & s=$!; " + then +
                            " wait $s; echo $? > rc; }";
    EXPECT_EQ(std::system(("bash -c " + shellQuoted(cmd)).c_str()), 0);
    return std::stoi(temp_.read("rc"));
  }
  std::vector<std::string> rayesArgs() const {
    std::vector<std::string> lines;
    std::ifstream in(temp_.path("args"));
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    return lines;
  }

  testing::TempFolder temp_;
  FarmJob job_;
};

TEST(FarmShellQuoting, PlainWordsStayAndOthersRoundTripThroughBash) {
  EXPECT_EQ(shellQuoted("/a/b-c_d.e=1,2"), "/a/b-c_d.e=1,2");
  testing::TempFolder temp;
  for (const std::string word : {"", "a b", "it's", "$HOME `x` \"y\" \\z", "*", "--x=-2"}) {
    const std::string cmd = "printf %s " + shellQuoted(word) + " > " + temp.path("w");
    ASSERT_EQ(std::system(("bash -c " + shellQuoted(cmd)).c_str()), 0);
    EXPECT_EQ(temp.read("w"), word);
  }
}

TEST_F(FarmScript, RenderScriptIsAnArrayJobThatAppendsItsLogAndMayBeRequeued) {
  const std::string s = renderScript(job_);
  EXPECT_EQ(s.rfind("#!/bin/bash\n", 0), 0u);
  const std::vector<std::string> lines = {"#SBATCH --array=1-4\n", "#SBATCH --open-mode=append\n",
                                         "#SBATCH --requeue\n", "#SBATCH --job-name=rayes-frame\n",
                                         "#SBATCH --signal=B:USR1@120\n",
                                         "#SBATCH --output=" + job_.dir + "/part-%a.log\n"};
  for (const std::string& line : lines)
    EXPECT_THAT(s, HasSubstr(line));
  EXPECT_THAT(s, Not(HasSubstr("--partition")));
  job_.partition = "gpu";
  EXPECT_THAT(renderScript(job_), HasSubstr("#SBATCH --partition=gpu\n"));
  EXPECT_THAT(mergeScript(job_), HasSubstr("#SBATCH --partition=gpu\n"));
}

TEST_F(FarmScript, TaskRendersItsPartWithACheckpoint) {
  EXPECT_EQ(runTask(renderScript(job_), 2, "0"), 0) << temp_.read("task.out");
  const std::vector<std::string> expected = {"render", job_.scene, "--spp=16", "--lod-bias=-2", "--quiet",
                                             "--part", "2/4", "-o", job_.dir + "/part-2.film",
                                             "--checkpoint", job_.dir + "/part-2.checkpoint"};
  EXPECT_EQ(rayesArgs(), expected);
  EXPECT_FALSE(fs::exists(temp_.path("scontrol")));
  EXPECT_THAT(temp_.read("task.out"), HasSubstr("part 2/4"));
}

TEST_F(FarmScript, TaskResumesFromItsCheckpointAndRemovesItWhenDone) {
  temp_.write("parts/part-3.checkpoint", "state");
  EXPECT_EQ(runTask(renderScript(job_), 3, "0"), 0) << temp_.read("task.out");
  const std::vector<std::string> args = rayesArgs();
  ASSERT_FALSE(args.empty());
  EXPECT_EQ(args.back(), "--resume");
  EXPECT_FALSE(fs::exists(temp_.path("parts/part-3.checkpoint")));
}

TEST_F(FarmScript, TaskRequeuesItselfWhenRayesStopsWithACheckpoint) {
  EXPECT_EQ(runTask(renderScript(job_), 1, "4"), 4);
  EXPECT_EQ(temp_.read("scontrol"), "requeue 77_1\n");
}

TEST_F(FarmScript, TaskFailsWithRayesExitCodeAndIsNotRequeued) {
  EXPECT_EQ(runTask(renderScript(job_), 1, "2"), 2);
  EXPECT_FALSE(fs::exists(temp_.path("scontrol")));
}

TEST_F(FarmScript, WarningSignalStopsRayesWithACheckpointAndRequeues) {
  // USR1 reaches the script alone (--signal=B:USR1@120); the script passes TERM to rayes.
  const std::string waitStarted = "until [ -f started ]; do sleep 0.01; done; kill -USR1 $s;";
  EXPECT_EQ(runTask(renderScript(job_), 4, "wait", waitStarted), 4) << temp_.read("task.out");
  EXPECT_EQ(temp_.read("signals"), "TERM\n");
  EXPECT_EQ(temp_.read("scontrol"), "requeue 77_4\n");
}

TEST_F(FarmScript, CancelledTaskStopsWithACheckpointAndStaysCancelled) {
  // scancel signals every process of the task: the script and rayes.
  const std::string cancel = "until [ -f started ]; do sleep 0.01; done; kill -TERM $s \"$(cat pid)\";";
  EXPECT_EQ(runTask(renderScript(job_), 4, "wait", cancel), 4) << temp_.read("task.out");
  EXPECT_EQ(temp_.read("signals"), "TERM\n");
  EXPECT_FALSE(fs::exists(temp_.path("scontrol")));
}

TEST_F(FarmScript, TaskUsesTheCpusSlurmGaveItUnlessThreadsAreGiven) {
  const std::string withCpus = "export SLURM_CPUS_PER_TASK=3\n" + renderScript(job_);
  ASSERT_EQ(runTask(withCpus, 1, "0"), 0);
  EXPECT_THAT(rayesArgs(), ::testing::IsSupersetOf({"--threads", "3"}));
  job_.renderArgs.push_back("--threads=2");
  job_.threadsGiven = true;
  ASSERT_EQ(runTask("export SLURM_CPUS_PER_TASK=3\n" + renderScript(job_), 1, "0"), 0);
  EXPECT_THAT(rayesArgs(), Not(::testing::Contains("3")));
}

TEST_F(FarmScript, MergeReadsEveryPartInOrderAndWritesTheOutputs) {
  for (int i = 1; i <= 4; ++i) temp_.write("parts/part-" + std::to_string(i) + ".film", "");
  EXPECT_EQ(runTask(mergeScript(job_), 1, "0"), 0) << temp_.read("task.out");
  const std::vector<std::string> expected = {"merge", partFilm(job_, 1), partFilm(job_, 2), partFilm(job_, 3),
                                             partFilm(job_, 4), "-o", "/out/frame.exr", "-o", "/out/frame.png",
                                             "--stats", "/out/frame.json"};
  EXPECT_EQ(rayesArgs(), expected);
  EXPECT_THAT(mergeScript(job_), HasSubstr("#SBATCH --output=" + job_.dir + "/merge.log\n"));
}

TEST_F(FarmScript, MergeNamesAMissingPartWithItsLog) {
  for (int i : {1, 2, 4}) temp_.write("parts/part-" + std::to_string(i) + ".film", "");
  EXPECT_EQ(runTask(mergeScript(job_), 1, "2"), 2);
  EXPECT_THAT(temp_.read("task.out"), HasSubstr("part 3 is missing"));
  EXPECT_THAT(temp_.read("task.out"), HasSubstr(job_.dir + "/part-3.log"));
  EXPECT_THAT(temp_.read("task.out"), Not(HasSubstr("part 2 is missing")));
}

}  // namespace
}  // namespace rayes
