// `rayes farm submit`: everything checked before anything is submitted (exit code 2, nothing
// written, nothing submitted), --dry-run prints the scripts, and a submission calls sbatch twice:
// the render array, then the merge after it (here a stand-in sbatch on PATH records the calls;
// tests/farm/slurm_farm_test.sh runs the real thing).
#include <cstdlib>
#include <filesystem>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include "app/command_line.h"
#include "support/render_fixtures.h"
#include "support/temp_folder.h"

namespace rayes {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

const std::string kScene = std::string(RAYES_SOURCE_DIR) + "/scenes/teapot.json";

struct FarmRun {
  int code;
  std::string out, err;
};

class FarmSubmit : public ::testing::Test {
 protected:
  FarmSubmit() : path_(std::getenv("PATH") ? std::getenv("PATH") : "") {}
  ~FarmSubmit() override { setenv("PATH", path_.c_str(), 1); }

  FarmRun farm(std::vector<std::string> args) {
    args.insert(args.begin(), {"farm", "submit"});
    ::testing::internal::CaptureStdout();
    const testing::RunResult r = testing::runRayes(std::move(args));
    return {r.code, ::testing::internal::GetCapturedStdout(), r.err};
  }
  // A stand-in for a Slurm command on PATH (PATH then holds the stand-ins alone): it appends
  // its arguments, one line per call, to <name>.calls and runs `body`.
  void standIn(const std::string& name, const std::string& body) {
    const std::string file = temp_.write("bin/" + name, "#!/bin/bash\necho \"$@\" >> " + temp_.path(name + ".calls") +
                                                             "\n" + body + "\n");
    fs::permissions(file, fs::perms::owner_all);
    setenv("PATH", (temp_.path("bin") + ":/usr/bin:/bin").c_str(), 1);
  }
  std::vector<std::string> calls(const std::string& name) const {
    std::vector<std::string> lines;
    std::istringstream in(temp_.read(name + ".calls"));
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    return lines;
  }
  std::string path(const std::string& name) const { return temp_.path(name); }

  testing::TempFolder temp_;
  std::string path_;
};

TEST_F(FarmSubmit, DryRunPrintsBothScriptsAndWritesNothing) {
  const FarmRun r = farm({kScene, "--tasks", "3", "--spp", "2", "--res", "16x12", "--lod-bias", "-1", "-o",
                      path("f.exr"), "--dry-run", "--", "--account=proj", "--time=1:00:00"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("#SBATCH --array=1-3\n"));
  EXPECT_THAT(r.out, HasSubstr(" render " + kScene + " --spp=2 --res=16x12 --lod-bias=-1"));
  EXPECT_THAT(r.out, HasSubstr("# sbatch --parsable --account=proj --time=1:00:00 " + path("f.parts/render.sh")));
  EXPECT_THAT(r.out, HasSubstr("'--dependency=afterany:<render job>' --kill-on-invalid-dep=yes "
                               "'--export=ALL,RAYES_FARM_RENDER_JOB=<render job>' --account=proj"));
  EXPECT_THAT(r.out, HasSubstr(path("f.parts/part-3.film") + " \\\n  -o " + path("f.exr")));
  EXPECT_TRUE(fs::is_empty(temp_.dir()));
}

TEST_F(FarmSubmit, PartsFolderIsGivenOrBesideTheFirstOutput) {
  FarmRun r = farm({kScene, "--tasks", "2", "-o", path("img/a.png"), "-o", path("img/a.exr"), "--dry-run"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr(path("img/a.parts/part-1.film")));
  r = farm({kScene, "--tasks", "2", "-o", path("a.exr"), "--dir", path("p/"), "--dry-run"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr(path("p/part-1.film")));
}

TEST_F(FarmSubmit, BadRenderInputIsRefusedBeforeSubmitting) {
  standIn("sbatch", "echo 41");
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{kScene, "--tasks", "2", "--spp", "0"}, "--spp"},
      {{kScene, "--tasks", "2", "--no-such-option"}, "--no-such-option"},
      {{path("missing.json"), "--tasks", "2"}, "missing.json"},
      {{kScene, "--tasks", "0"}, "--tasks"},
      {{kScene, "--tasks", "2", "--report", path("r.html")}, "--report"},
      {{kScene, "--tasks", "2", "-o", path("a.jpg")}, "a.jpg"},
      {{"-", "--tasks", "2"}, "not -"},
      {{kScene, "--tasks", "2", "--dir", path("a b")}, "parts folder"},
  };
  for (const auto& [args, named] : cases) {
    std::vector<std::string> withOut = args;
    if (std::find(args.begin(), args.end(), "-o") == args.end()) withOut.insert(withOut.end(), {"-o", path("f.exr")});
    const FarmRun r = farm(withOut);
    EXPECT_EQ(r.code, 2) << named << ": " << r.err;
    EXPECT_THAT(r.err, HasSubstr(named));
  }
  EXPECT_TRUE(calls("sbatch").empty());
  EXPECT_EQ(temp_.entries(), (std::vector<std::string>{"bin", "bin/sbatch"}));
}

TEST_F(FarmSubmit, PartsOfAnEarlierJobAreNotMixedIn) {
  temp_.write("f.parts/part-2.film", "");
  const FarmRun r = farm({kScene, "--tasks", "2", "-o", path("f.exr"), "--dry-run"});
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("part-2.film"));
}

TEST_F(FarmSubmit, MissingSbatchIsBadInputAndLeavesNothing) {
  setenv("PATH", path("nothing").c_str(), 1);
  const FarmRun r = farm({kScene, "--tasks", "2", "-o", path("f.exr")});
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("sbatch: not found"));
  EXPECT_TRUE(fs::is_empty(temp_.dir()));
}

TEST_F(FarmSubmit, SubmitsTheArrayThenTheMergeAfterIt) {
  standIn("sbatch", "[ -f " + path("second") + " ] && echo '42;cluster' || { touch " + path("second") + "; echo 41; }");
  const FarmRun r = farm({kScene, "--tasks", "4", "--partition", "batch", "--spp", "2", "-o", path("f.exr"), "--",
                      "--account=proj"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("render job 41: 4 tasks"));
  EXPECT_THAT(r.out, HasSubstr("merge job 42"));
  const std::string dir = path("f.parts");
  EXPECT_EQ(calls("sbatch"), (std::vector<std::string>{
                                 "--parsable --account=proj " + dir + "/render.sh",
                                 "--parsable --dependency=afterany:41 --kill-on-invalid-dep=yes --export=ALL,RAYES_FARM_RENDER_JOB=41 "
                                 "--account=proj " + dir +
                                     "/merge.sh"}));
  EXPECT_THAT(temp_.read("f.parts/render.sh"), HasSubstr("#SBATCH --partition=batch\n"));
  EXPECT_THAT(temp_.read("f.parts/merge.sh"), HasSubstr("-o " + path("f.exr")));
}

TEST_F(FarmSubmit, RefusedMergeCancelsTheArrayAndLeavesNoScript) {
  standIn("sbatch", "[ -f " + path("second") + " ] && { echo 'sbatch: error: invalid account' >&2; exit 1; }; touch " +
                        path("second") + "; echo 41");
  standIn("scancel", "");
  const FarmRun r = farm({kScene, "--tasks", "2", "-o", path("f.exr")});
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("render job 41 was cancelled"));
  EXPECT_EQ(calls("scancel"), std::vector<std::string>{"41"});
  EXPECT_FALSE(fs::exists(path("f.parts")));
}

}  // namespace
}  // namespace rayes
