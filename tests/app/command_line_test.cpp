// The `rayes render` command: outputs on success; on bad input one message naming the file
// and place, exit code 2, and nothing at the output paths.
#include <filesystem>
#include <fstream>
#include <unistd.h>
#include <gtest/gtest.h>
#include <gmock/gmock.h>
#include <nlohmann/json.hpp>
#include "app/command_line.h"
#include "core/vector_isa.h"
#include "core/version.h"
#include "support/render_fixtures.h"
#include "support/temp_folder.h"

namespace rayes {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

using testing::RunResult;
RunResult run(std::vector<std::string> args) { return testing::runRayes(std::move(args)); }

class CommandLine : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return temp_.path(name); }
  std::string write(const std::string& name, const std::string& text) const { return temp_.write(name, text); }
  bool dirHasOnly(std::vector<std::string> names) const {
    std::sort(names.begin(), names.end());
    return temp_.entries() == names;
  }
  testing::TempFolder temp_;
};

const std::string kScene = std::string(RAYES_SOURCE_DIR) + "/scenes/teapot.json";

TEST_F(CommandLine, RenderWritesExrPngAndStats) {
  const RunResult r = run({"render", kScene, "--spp", "1", "--res", "32x24", "-o", path("t.exr"), "--stats",
                     path("s.json"), "-q"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(path("t.exr")));
  EXPECT_TRUE(fs::exists(path("t.png")));
  std::ifstream in(path("s.json"));
  const auto j = nlohmann::json::parse(in);
  ASSERT_TRUE(j["generations"].is_array());
  ASSERT_FALSE(j["generations"].empty());
  const auto& g = j["generations"][0];
  EXPECT_GT(g["rays"].get<int>(), 0);
  EXPECT_GT(g["leaves_diced"].get<int>(), 0);
  EXPECT_GT(g["micropolygons_created"].get<int>(), 0);
  ASSERT_FALSE(g["iterations"].empty());
  EXPECT_TRUE(g["iterations"][0].contains("active_rays"));
  EXPECT_TRUE(g["iterations"][0].contains("candidates_per_ray"));
  const auto& t = j["totals"];
  for (const char* k : {"leaves_diced", "micropolygons_created", "micropolygons_potential", "peak_rss_bytes"})
    EXPECT_TRUE(t.contains(k)) << k;
  for (const char* k : {"toplevel", "sort", "dice", "bottom", "shade", "total"})
    EXPECT_TRUE(t["time_s"].contains(k)) << k;
  EXPECT_EQ(t["micropolygons_potential"].get<uint64_t>(), 39ull << 20);  // 39 leaves at 4^10
  EXPECT_LT(t["micropolygons_created"].get<uint64_t>(), t["micropolygons_potential"].get<uint64_t>());
  EXPECT_TRUE(j["skipped"].contains("volumes"));
  // The teapot reads no texture: its rays keep no surface derivatives.
  EXPECT_TRUE(j["skipped"].contains("texture_footprint"));
  EXPECT_EQ(j["features"]["textured_materials"].get<int>(), 0);
  // Which row kernels ran (core/vector_isa.h): the image does not depend on it, the time does.
  EXPECT_EQ(j["settings"]["vector_isa"].get<std::string>(), vectorIsaName(vectorIsa()));
}

TEST_F(CommandLine, ReportIsReadableHtmlOfTheSameStats) {
  const RunResult r = run({"render", kScene, "--spp", "1", "--res", "16x12", "-o", path("img/t.exr"), "--report",
                           path("r.html"), "-q"});
  ASSERT_EQ(r.code, 0) << r.err;
  std::ifstream in(path("r.html"));
  const std::string html((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_THAT(html, HasSubstr("<h1>rayes report: pt (path tracing)</h1>"));  // the method named first
  for (const char* section : {"Where the time went", "Dicing", "Memory by owner", "Generations", "Used and skipped"})
    EXPECT_THAT(html, HasSubstr(section));
  // The preview is inside the page (self-contained), not a file beside it.
  EXPECT_THAT(html, HasSubstr("src=\"data:image/png;base64,iVBORw0KGgo"));
  EXPECT_THAT(html, HasSubstr("skipped: volumes"));
  EXPECT_THAT(html, HasSubstr(programVersion()));
}

TEST_F(CommandLine, ReferenceGivesErrorAgainstTime) {
  ASSERT_EQ(run({"render", kScene, "--spp", "4", "--res", "16x12", "-o", path("ref.exr"), "-q"}).code, 0);
  const RunResult r = run({"render", kScene, "--spp", "4", "--seed", "3", "--res", "16x12", "-o", path("x.exr"),
                     "--reference", path("ref.exr"), "--stats", path("s.json"), "-q"});
  ASSERT_EQ(r.code, 0) << r.err;
  std::ifstream in(path("s.json"));
  const auto curve = nlohmann::json::parse(in)["error_vs_time"];
  ASSERT_EQ(curve.size(), 3u);  // passes end at 1, 2, 4 spp
  EXPECT_EQ(curve[2]["spp"].get<int>(), 4);
  EXPECT_GT(curve[0]["rmse"].get<double>(), 0.0);
}

// -o NAME.png asks for the preview alone: no EXR is written (not even over the PNG).
TEST_F(CommandLine, PngOutputWritesThePreviewAlone) {
  const RunResult r = run({"render", kScene, "--spp", "1", "--res", "8x6", "-o", path("p.png"), "-q"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(dirHasOnly({"p.png"}));
  std::ifstream in(path("p.png"), std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG");
}

TEST_F(CommandLine, MissingSceneIsExit2WithNothingWritten) {
  const RunResult r = run({"render", path("nope.json"), "-o", path("o.exr"), "-q"});
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("nope.json"));
  EXPECT_FALSE(fs::exists(path("o.exr")));
  EXPECT_FALSE(fs::exists(path("o.png")));
}

TEST_F(CommandLine, SyntaxErrorIsExit2WithLineAndColumn) {
  const std::string scene = write("bad.json", "{\n  \"camera\": {\"position\": [0,0,1],,}\n}\n");
  const RunResult r = run({"render", scene, "-o", path("o.exr"), "-q"});
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("bad.json:2:"));
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one message: " << r.err;
  EXPECT_TRUE(dirHasOnly({"bad.json"}));
}

TEST_F(CommandLine, ImpossibleArgumentsAreExit2) {
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"--spp", "-3"}, {"--res", "0x5"}, {"--res", "abc"}, {"--ray-memory", "12Q"},
           {"--ray-memory", "10"}, {"--max-lod", "40"}, {"--lod", "random"}, {"--threads"},
           {"--engine", "optix"}, {"--embree-lod", "auto"}, {"--engine", "embree", "--memory-limit", "12Q"}}) {
    std::vector<std::string> full = {"render", kScene, "-o", path("o.exr"), "-q"};
    full.insert(full.end(), args.begin(), args.end());
    const RunResult r = run(full);
    EXPECT_EQ(r.code, 2) << args[0] << ": " << r.err;
    EXPECT_FALSE(fs::exists(path("o.exr"))) << args[0];
  }
}

// Issue 10, item 8: a cache of no entries, a count that is not a whole number, a bias beyond
// the levels there are: one message naming the option, exit 2, nothing written.
TEST_F(CommandLine, BadDiceCacheAndLodBiasAreOneMessageExit2AndNothingWritten) {
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"--dice-cache", "0"}, {"--dice-cache", "-5"}, {"--dice-cache", "ten"}, {"--dice-cache", "2.5"},
           {"--dice-cache", "10", "--engine", "embree"}, {"--dice-cache", "10", "--trace-mode", "alone"},
           {"--lod-bias", "13"}, {"--lod-bias", "-13"}, {"--lod-bias", "0.5"}, {"--lod-bias", "x"},
           {"--lod-bias", "-1", "--engine", "embree"}}) {
    std::vector<std::string> full = {"render", kScene, "-o", path("o.exr"), "--stats", path("s.json"), "-q"};
    full.insert(full.end(), args.begin(), args.end());
    const RunResult r = run(full);
    EXPECT_EQ(r.code, 2) << args[0] << " " << args[1] << ": " << r.err;
    // One message naming the option (a value that does not parse also gets the --help hint).
    EXPECT_THAT(r.err.substr(0, r.err.find('\n')), HasSubstr(args[0])) << args[1];
    EXPECT_LE(std::count(r.err.begin(), r.err.end(), '\n'), 2) << "one message: " << r.err;
    EXPECT_TRUE(dirHasOnly({})) << args[0] << " " << args[1];
  }
}

TEST_F(CommandLine, UnknownMethodIsOneMessageExit2AndNothingWritten) {
  const RunResult r = run({"render", kScene, "-o", path("o.exr"), "--stats", path("s.json"), "-q", "--method", "bdpt"});
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("--method: unknown method 'bdpt'"));
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one message: " << r.err;
  EXPECT_TRUE(dirHasOnly({}));
}

TEST_F(CommandLine, LightTracingWritesItsMethodAndSplatsInTheStats) {
  const RunResult r = run({"render", kScene, "--spp", "1", "--res", "16x12", "-o", path("t.exr"), "--stats",
                           path("s.json"), "-q", "--method", "lt"});
  ASSERT_EQ(r.code, 0) << r.err;
  std::ifstream in(path("s.json"));
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["settings"]["method"], "lt");
  EXPECT_GT(j["totals"]["splats"].get<int>(), 0);
}

TEST_F(CommandLine, HelpDocumentsEveryOption) {
  const auto args = std::vector<std::string>{"rayes", "render", "--help"};
  std::vector<char*> argv;
  for (auto a : args) argv.push_back(strdup(a.c_str()));
  ::testing::internal::CaptureStdout();
  const int code = runCommandLine(int(argv.size()), argv.data());
  const std::string out = ::testing::internal::GetCapturedStdout();
  for (char* a : argv) free(a);
  EXPECT_EQ(code, 0);
  for (const char* opt : {"--output", "--spp", "--res", "--threads", "--stats", "--max-lod", "--ray-memory",
                          "--lod", "--trace-mode", "--reference", "--progressive", "--engine", "--embree-lod", "--memory-limit",
                          "--method", "--progress", "--quiet"})
    EXPECT_THAT(out, HasSubstr(opt));
}

}  // namespace
}  // namespace rayes
