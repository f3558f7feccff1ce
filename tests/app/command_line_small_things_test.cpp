// The small things users hit first (issue 31, item 6): `rayes --version` (also in the stats);
// `-` reads the scene from standard input; an output name with an unknown extension is refused
// (exit 2, naming it and the accepted ones) instead of being written as an EXR; a mistyped
// option or command names the nearest real one.
#include <filesystem>
#include <fstream>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include "app/closest_name.h"
#include "core/version.h"
#include "support/rayes_process.h"
#include "support/render_fixtures.h"
#include "support/temp_folder.h"

namespace rayes {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::StartsWith;

const std::string kScene = testing::sourcePath("scenes/teapot.json");

TEST(Version, PrintsTheProgramVersionOnStdoutAndExits0) {
  const testing::ChildResult r = testing::runRayesProcess({"--version"});
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, std::string("rayes ") + programVersion() + "\n");
  // The project's version (CMakeLists.txt), then the source's git describe where there is one.
  EXPECT_THAT(std::string(programVersion()), ::testing::MatchesRegex("[0-9]+\\.[0-9]+\\.[0-9]+( \\(git .+\\))?"));
}

TEST(Version, IsInTheStatsFile) {
  const testing::TempFolder temp;
  const testing::RunResult r = testing::runRayes(
      {"render", kScene, "--res", "8x6", "--spp", "1", "-q", "-o", temp.path("o.exr"), "--stats", temp.path("s.json")});
  ASSERT_EQ(r.code, 0) << r.err;
  std::ifstream in(temp.path("s.json"));
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["settings"]["program_version"].get<std::string>(), programVersion());
  EXPECT_GT(j["memory"]["limit_bytes"].get<uint64_t>(), 0u);
  EXPECT_FALSE(j["memory"]["limit_source"].get<std::string>().empty());
}

// The scene through a pipe: the same image as from the file, and its relative file names
// resolve against the current directory: teapot.json names "teapot.bpt", beside it; piped
// from the source tree's root, the same text must name it "scenes/teapot.bpt".
TEST(StdinScene, APipedSceneRendersTheSameImageAsTheFile) {
  const testing::TempFolder temp;
  std::ifstream in(kScene);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string bpt = "\"file\": \"";
  for (size_t at = text.find(bpt); at != std::string::npos; at = text.find(bpt, at + 1))
    text.insert(at + bpt.size(), "scenes/");
  const std::vector<std::string> common = {"--res", "16x12", "--spp", "1", "-q"};
  std::vector<std::string> fromPipe = {"render", "-", "-o", temp.path("pipe.exr")};
  std::vector<std::string> fromFile = {"render", kScene, "-o", temp.path("file.exr")};
  fromPipe.insert(fromPipe.end(), common.begin(), common.end());
  fromFile.insert(fromFile.end(), common.begin(), common.end());
  testing::ChildSetup pipe;
  pipe.feedStdin = true;
  pipe.stdinText = text;
  pipe.cwd = RAYES_SOURCE_DIR;
  const testing::ChildResult a = testing::runRayesProcess(fromPipe, pipe);
  ASSERT_EQ(a.code, 0) << a.err;
  const testing::ChildResult b = testing::runRayesProcess(fromFile);
  ASSERT_EQ(b.code, 0) << b.err;
  EXPECT_EQ(temp.read("pipe.png"), temp.read("file.png"));
  EXPECT_FALSE(temp.read("pipe.png").empty());
}

TEST(StdinScene, BadInputIsNamedStdinWithThePlace) {
  const testing::TempFolder temp;
  testing::ChildSetup pipe;
  pipe.feedStdin = true;
  pipe.stdinText = "{\n  \"camera\": [1, 2]\n}\n";
  const testing::ChildResult r = testing::runRayesProcess({"render", "-", "-o", temp.path("o.exr"), "-q"}, pipe);
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, StartsWith("rayes: <stdin>:2:13: /camera: expected an object")) << r.err;
  EXPECT_TRUE(temp.entries().empty());
}

TEST(OutputName, UnknownExtensionIsRefusedNamingItAndTheAcceptedOnes) {
  const testing::TempFolder temp;
  for (const char* name : {"a.jpg", "a.tiff", "a", "a.exr.bak"}) {
    const testing::RunResult r = testing::runRayes({"render", kScene, "-o", temp.path(name), "-q", "--res", "8x6"});
    EXPECT_EQ(r.code, 2) << name;
    EXPECT_THAT(r.err, StartsWith("rayes: -o: '" + temp.path(name) + "'")) << r.err;
    for (const char* accepted : {".exr", ".png", ".film"}) EXPECT_THAT(r.err, HasSubstr(accepted)) << name;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(temp.entries().empty()) << name;
  }
  // Upper case is the same name.
  const testing::RunResult ok = testing::runRayes({"render", kScene, "-o", temp.path("A.EXR"), "-q", "--res", "8x6", "--spp", "1"});
  EXPECT_EQ(ok.code, 0) << ok.err;
}

TEST(Suggestions, EditDistanceCountsInsertionsDeletionsSubstitutionsAndSwaps) {
  EXPECT_EQ(editDistance("--spp", "--spp"), 0);
  EXPECT_EQ(editDistance("--sp", "--spp"), 1);
  EXPECT_EQ(editDistance("--spq", "--spp"), 1);
  EXPECT_EQ(editDistance("--psp", "--spp"), 1);  // a swap of neighbours
  EXPECT_EQ(editDistance("", "abc"), 3);
  EXPECT_EQ(closestName("--thraeds", {"--threads", "--seed"}), "--threads");
  EXPECT_EQ(closestName("--fast", {"--threads", "--seed", "--res"}), "");  // too far: no guess
}

TEST(Suggestions, AMistypedOptionNamesTheNearest) {
  const struct {
    std::vector<std::string> args;
    std::string message;
  } cases[] = {
      {{"render", kScene, "--sp", "4"}, "rayes: --sp: unknown option; did you mean --spp?"},
      {{"render", kScene, "--ray-memroy", "1G"}, "rayes: --ray-memroy: unknown option; did you mean --ray-memory?"},
      {{"render", kScene, "--methd=lbt"}, "rayes: --methd: unknown option; did you mean --method?"},
      {{"converge", kScene, "--budgte", "3"}, "rayes: --budgte: unknown option; did you mean --budget?"},
      {{"render", kScene, "--zzzzzz"}, "rayes: --zzzzzz: unknown option\n"},
      {{"rendr", kScene}, "rayes: rendr: unknown command; did you mean render?"},
  };
  for (const auto& c : cases) {
    const testing::RunResult r = testing::runRayes(c.args);
    EXPECT_EQ(r.code, 2) << c.args[2 - (c.args[0] == "rendr")];
    EXPECT_THAT(r.err, StartsWith(c.message)) << r.err;
    EXPECT_THAT(r.err, HasSubstr("--help' for the ")) << r.err;
  }
}

}  // namespace
}  // namespace rayes
