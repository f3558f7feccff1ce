// `rayes converge`: renders at doubling spp until the budget and writes the error curve as a
// CSV and an SVG chart; lbt refines its beams as spp doubles; the error counts the pixels of an
// error mask; bad input (no reference, a reference or mask of another size, an unknown method, a
// box outside the image, a beam growth out of range) is refused with exit code 2 and nothing written.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <gtest/gtest.h>
#include "app/converge.h"
#include "support/render_fixtures.h"
#include "support/temp_folder.h"

namespace rayes {
namespace {

std::string read(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class Converge : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto r = testing::runRayes({"render", testing::sourcePath("scenes/cornell-box.json"), "--res", "16x12", "--spp",
                                      "4", "-q", "-o", dir.path("ref.exr")});
    ASSERT_EQ(r.code, 0) << r.err;
  }
  testing::TempFolder dir;
  std::string csv() const { return dir.path("curve.csv"); }
  std::vector<std::string> args(std::vector<std::string> extra) const {
    std::vector<std::string> a{"converge", testing::sourcePath("scenes/cornell-box.json"), "--res", "16x12", "-q",
                               "-o", csv()};
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  }
  std::string ref() const { return dir.path("ref.exr"); }
};

// How many rows fit a budget depends on the machine; a tiny budget always gets the first one.
TEST_F(Converge, WritesTheCurveAndAChart) {
  const auto r = testing::runRayes(args({"--reference", ref(), "--method", "pm", "--budget", "0.001", "--photons", "100",
                                         "--region", "0,0,8,6"}));
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string text = read(csv());
  EXPECT_EQ(text.rfind("seconds,cpu_seconds,spp,photons,beam_resolution,beam_segments,rmse,rel_mse,region_bias\n", 0),
            0u)
      << text;
  EXPECT_NE(text.find(",1,100,0,0,"), std::string::npos)
      << "the first render has 1 spp, pm traces --photons per sample, and no beams: " << text;
  EXPECT_NE(read(dir.path("curve.svg")).find("<polyline"), std::string::npos);
}

TEST_F(Converge, RefusesBadInputAndWritesNothing) {
  const auto other = testing::runRayes({"render", testing::sourcePath("scenes/cornell-box.json"), "--res", "8x8", "--spp",
                                        "1", "-q", "-o", dir.path("small.exr")});
  ASSERT_EQ(other.code, 0) << other.err;
  const std::vector<std::vector<std::string>> bad{
      {"--method", "pt", "--budget", "1"},                                          // no reference
      {"--reference", dir.path("small.exr"), "--budget", "1"},        // another size
      {"--reference", ref(), "--method", "nope", "--budget", "1"},                   // unknown method
      {"--reference", ref(), "--budget", "0"},                                       // no budget
      {"--reference", ref(), "--budget", "1", "--region", "0,0,17,12"},              // box leaves the image
      {"--reference", ref(), "--budget", "1", "--mask", dir.path("small.exr")},  // mask of another size
      {"--reference", ref(), "--budget", "1", "--error-mask", dir.path("small.exr")},  // error mask of another size
      {"--reference", ref(), "--reference", dir.path("small.exr"), "--budget", "1"},  // a summand of another size
      {"--reference", ref(), "--budget", "1", "--method", "lbt", "--beam-growth", "0.5"},  // beams would coarsen
  };
  // A parse error points at converge's own help.
  const auto noReference = testing::runRayes(args(bad[0]));
  EXPECT_NE(noReference.err.find("--reference"), std::string::npos) << noReference.err;
  EXPECT_NE(noReference.err.find("'rayes converge --help'"), std::string::npos) << noReference.err;
  for (const auto& extra : bad) {
    const auto r = testing::runRayes(args(extra));
    EXPECT_EQ(r.code, 2) << extra[0] << " " << extra[1] << ": " << r.err;
    EXPECT_FALSE(std::filesystem::exists(csv())) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir.path("curve.svg"))) << r.err;
  }
}

// The first lbt render uses --beam-resolution as given, and its row says so.
TEST_F(Converge, LbtRowsCarryTheirBeamResolution) {
  const auto r = testing::runRayes({"converge", testing::sourcePath("scenes/lbt-mirror.json"), "--res", "16x12", "-q",
                                    "-o", csv(), "--reference", ref(), "--method", "lbt", "--budget", "0.001",
                                    "--beam-resolution", "8"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(read(csv()).find(",1,0,8,"), std::string::npos) << read(csv());
}

TEST(ConvergeSchedule, BeamsDoubleWithSppUpToTheCap) {
  ConvergeSchedule s;
  EXPECT_EQ(s.beamResolution(16, 0), 16);
  EXPECT_EQ(s.beamResolution(16, 2), 32);   // 4 spp: 4x the beams
  EXPECT_EQ(s.beamResolution(16, 8), 256);
  EXPECT_EQ(s.beamResolution(16, 30), 4096);
  s.beamGrowth = 1;
  EXPECT_EQ(s.beamResolution(16, 10), 16);
}

// Two pixels, errors (1, 1, 1) and (3, 3, 3): over both RMSE = sqrt(5); the mask keeps the second.
TEST(ConvergeError, CountsOnlyTheErrorMasksPixels) {
  const std::vector<float> rgba{1, 1, 1, 1, 3, 3, 3, 1}, ref(6, 0.0f);
  const PixelRegion all{0, 0, 2, 1, {}};
  EXPECT_DOUBLE_EQ(errorAgainst(rgba, ref, all, 2, 1).rmse, std::sqrt(5.0));
  EXPECT_DOUBLE_EQ(errorAgainst(rgba, ref, all, 2, 1).relMse, (1 + 9) / 2 / 0.01);
  const PixelRegion second{0, 0, 0, 0, {0, 0, 0, 1, 0, 0}};
  EXPECT_DOUBLE_EQ(errorAgainst(rgba, ref, second, 2, 1).rmse, 3.0);
  EXPECT_DOUBLE_EQ(errorAgainst(rgba, ref, PixelRegion{0, 0, 0, 0, {0, 0, 0, 0, 0, 0}}, 2, 1).rmse, 0.0);
}

}  // namespace
}  // namespace rayes
