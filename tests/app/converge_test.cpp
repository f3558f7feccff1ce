// `rayes converge`: renders at doubling spp until the budget and writes the error curve as a
// CSV and an SVG chart; bad input (no reference, a reference or mask of another size, an
// unknown method, a box outside the image) is refused with exit code 2 and nothing written.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <gtest/gtest.h>
#include "render_fixtures.h"
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
  EXPECT_EQ(text.rfind("seconds,cpu_seconds,spp,photons,rmse,rel_mse,region_bias\n", 0), 0u) << text;
  EXPECT_NE(text.find(",1,"), std::string::npos) << "the first render has 1 spp: " << text;
  EXPECT_NE(text.find(",1,100,"), std::string::npos) << "pm traces --photons per sample: " << text;
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
  };
  for (const auto& extra : bad) {
    const auto r = testing::runRayes(args(extra));
    EXPECT_EQ(r.code, 2) << extra[0] << " " << extra[1] << ": " << r.err;
    EXPECT_FALSE(std::filesystem::exists(csv())) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir.path("curve.svg"))) << r.err;
  }
}

}  // namespace
}  // namespace rayes
