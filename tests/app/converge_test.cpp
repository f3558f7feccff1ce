// `rayes converge`: renders at doubling spp while the budget allows and writes the error curve
// as a CSV and an SVG chart; lbt refines its beams as spp doubles; the error counts the pixels of
// an error mask; a clamped RMSE column when asked; a warning when a few pixels hold most of the
// squared error. The budget: a render starts only when its predicted time fits, one that reaches
// the budget is stopped and leaves no row, the first always completes (a scripted clock, no
// timing). Bad input (no reference, a reference or mask of another size, found from the header
// before a pixel is read, NaN or infinite values, an error mask of no pixel, an unknown method, a
// box outside the image, a beam growth or quantile out of range) is refused with exit code 2 and
// nothing written.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <gtest/gtest.h>
#include "app/converge.h"
#include "app/image_io.h"
#include "support/exr_test_file.h"
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
  // The reference's pixels (16x12 RGB), to write altered copies of.
  std::vector<float> refPixels() const {
    int w = 0, h = 0;
    return readExrRgb(ref(), w, h);
  }
  std::string written(const std::string& name, const std::vector<float>& rgb, int w = 16, int h = 12) const {
    testing::writeRgbExr(dir.path(name), w, h, rgb);
    return dir.path(name);
  }
};

std::string firstLineOf(const std::string& text) { return text.substr(0, text.find('\n')); }

// How many rows fit a budget depends on the machine; a tiny budget always gets the first one.
TEST_F(Converge, WritesTheCurveAndAChart) {
  const auto r = testing::runRayes(args({"--reference", ref(), "--method", "pm", "--budget", "0.001", "--photons", "100",
                                         "--region", "0,0,8,6"}));
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string text = read(csv());
  EXPECT_EQ(text.rfind("seconds,cpu_seconds,spp,photons,beam_resolution,beam_segments,rmse,rel_mse,region_bias\n", 0),
            0u)
      << text;
  EXPECT_EQ(std::count(text.begin(), text.end(), ','), 8 * std::count(text.begin(), text.end(), '\n'))
      << "no clamped_rmse column unless asked: " << text;
  EXPECT_NE(text.find(",1,100,0,0,"), std::string::npos)
      << "the first render has 1 spp, pm traces --photons per sample, and no beams: " << text;
  EXPECT_NE(read(dir.path("curve.svg")).find("<polyline"), std::string::npos);
}

TEST_F(Converge, RefusesBadInputAndWritesNothing) {
  const auto other = testing::runRayes({"render", testing::sourcePath("scenes/cornell-box.json"), "--res", "8x8", "--spp",
                                        "1", "-q", "-o", dir.path("small.exr")});
  ASSERT_EQ(other.code, 0) << other.err;
  std::vector<float> corner(16 * 12 * 3);  // only pixel (0, 0)
  corner[0] = 1;
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
      {"--reference", written("nan.exr", std::vector<float>(16 * 12 * 3, NAN)), "--budget", "1"},  // all NaN
      {"--reference", ref(), "--budget", "1", "--error-mask", written("zero.exr", std::vector<float>(16 * 12 * 3))},
      {"--reference", ref(), "--budget", "1", "--mask", dir.path("zero.exr")},  // an empty region
      {"--reference", ref(), "--budget", "1", "--error-mask", written("corner.exr", corner), "--region", "8,6,16,12"},
      {"--reference", ref(), "--budget", "1", "--clamped-rmse", "1"},    // clamps nothing
      {"--reference", ref(), "--budget", "1", "--clamped-rmse", "0"},    // clamps everything to the least
      {"--reference", ref(), "--budget", "1", "--clamped-rmse", "nan"},
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

// The messages of the refusals that name what is wrong in a file.
TEST_F(Converge, RefusesANonFiniteReferenceNamingTheFirstPixel) {
  std::vector<float> rgb = refPixels();
  rgb[3 * (3 * 16 + 5) + 1] = NAN;                                       // (5, 3) G
  rgb[3 * (10 * 16 + 9) + 0] = std::numeric_limits<float>::infinity();  // (9, 10) R
  const std::string bad = written("bad.exr", rgb);
  const auto r = testing::runRayes(args({"--reference", bad, "--budget", "1"}));
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "rayes: " + bad + ": reference image has 2 values that are NaN or infinite, the first at pixel (5, 3) "
                   "channel G (NaN)\n");
  // The case, an all-NaN reference, also for `render --reference` (the same reader).
  const std::string nan = written("nan.exr", std::vector<float>(16 * 12 * 3, NAN));
  const auto render = testing::runRayes({"render", testing::sourcePath("scenes/cornell-box.json"), "--res", "16x12",
                                         "--spp", "1", "-q", "-o", dir.path("o.exr"), "--reference", nan});
  EXPECT_EQ(render.code, 2);
  EXPECT_NE(render.err.find("reference image has 576 values that are NaN or infinite, the first at pixel (0, 0) "
                            "channel R (NaN)"), std::string::npos) << render.err;
  EXPECT_FALSE(std::filesystem::exists(dir.path("o.exr")));
  // A mask's NaN would count as non-zero red: refused too.
  std::vector<float> mask(16 * 12 * 3, 1.0f);
  mask[3 * 20 + 2] = -std::numeric_limits<float>::infinity();  // (4, 1) B
  const auto m = testing::runRayes(args({"--reference", ref(), "--budget", "1", "--error-mask", written("m.exr", mask)}));
  EXPECT_EQ(m.code, 2);
  EXPECT_NE(m.err.find("error mask has 1 value that is NaN or infinite, the first at pixel (4, 1) channel B (infinite)"),
            std::string::npos) << m.err;
}

// A 64x48 reference whose compressed pixels are garbage: at 64x48 it cannot be read, at 16x12
// it is refused for its size, so that refusal came from the header, before any pixel was read.
TEST_F(Converge, ChecksTheReferenceSizeFromItsHeaderBeforeItsPixels) {
  std::vector<float> rgb(64 * 48 * 3);
  for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = float(i % 97) / 97;
  const std::string big = written("big.exr", rgb, 64, 48);
  {
    std::fstream f(big, std::ios::in | std::ios::out | std::ios::binary);
    f.seekg(0, std::ios::end);
    const std::streamoff size = f.tellg();
    f.seekp(size - 200);  // inside the last chunk's zlib stream
    f.write(std::string(200, '\x5a').data(), 200);
  }
  const auto whole = testing::runRayes({"converge", testing::sourcePath("scenes/cornell-box.json"), "--res", "64x48",
                                        "-q", "-o", csv(), "--reference", big, "--budget", "1"});
  EXPECT_EQ(whole.code, 2);
  EXPECT_NE(whole.err.find("cannot read EXR"), std::string::npos) << whole.err;
  const auto r = testing::runRayes(args({"--reference", big, "--budget", "1"}));
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "rayes: " + big + ": reference image is 64x48, the render 16x12\n");
  const auto mask = testing::runRayes(args({"--reference", ref(), "--budget", "1", "--mask", big}));
  EXPECT_EQ(mask.err, "rayes: " + big + ": mask is 64x48, the render 16x12\n");
}

TEST_F(Converge, RefusesAnErrorMaskOfNoPixel) {
  const std::string zero = written("zero.exr", std::vector<float>(16 * 12 * 3));
  const auto r = testing::runRayes(args({"--reference", ref(), "--budget", "1", "--error-mask", zero}));
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "rayes: " + zero + ": error mask has no pixel with non-zero red: no pixel would be counted and "
                   "every RMSE would read 0\n");
}

// A reference with one pixel of 1000 (a firefly): the warning names it and its share, once; the
// clamped RMSE at 0.99 (rank 191 of 192: the largest pixel clamped) is below the RMSE.
TEST_F(Converge, WarnsWhenAFewPixelsHoldTheErrorAndClampsThemWhenAsked) {
  std::vector<float> rgb = refPixels();
  for (int c = 0; c < 3; ++c) rgb[3 * (3 * 16 + 5) + c] = 1000;
  const std::string firefly = written("firefly.exr", rgb);
  const auto r = testing::runRayes(args({"--reference", firefly, "--budget", "0.001", "--clamped-rmse", "0.99"}));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err.find("rayes: warning: at 1 spp, 3 of 192 pixels hold "), 0u) << r.err;
  EXPECT_NE(r.err.find("(5, 3): "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(" against 1000 in the reference, "), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("warning", r.err.find("warning") + 1), std::string::npos) << "once: " << r.err;
  const std::string text = read(csv());
  EXPECT_EQ(firstLineOf(text), "seconds,cpu_seconds,spp,photons,beam_resolution,beam_segments,rmse,rel_mse,region_bias,"
                               "clamped_rmse");
  std::stringstream row(text.substr(text.find('\n') + 1));
  std::vector<double> v;
  for (std::string cell; std::getline(row, cell, ',') && v.size() < 10;) v.push_back(std::stod(cell));
  ASSERT_EQ(v.size(), 10u) << text;
  EXPECT_GT(v[6], 500 / std::sqrt(192.0)) << "the RMSE follows the firefly: " << text;
  EXPECT_LT(v[9], v[6] / 10) << "the clamped RMSE does not: " << text;
  // Against the 1 spp render itself (the same seed): no error, no warning.
  const auto same = testing::runRayes({"render", testing::sourcePath("scenes/cornell-box.json"), "--res", "16x12",
                                       "--spp", "1", "-q", "-o", dir.path("same.exr")});
  ASSERT_EQ(same.code, 0) << same.err;
  const auto plain = testing::runRayes(args({"--reference", dir.path("same.exr"), "--budget", "0.001"}));
  ASSERT_EQ(plain.code, 0) << plain.err;
  EXPECT_EQ(plain.err, "");
  EXPECT_NE(read(csv()).find(",0,0,0\n"), std::string::npos) << read(csv());
}

// The rule needs more than half the squared error in the 3 largest of at least 100 pixels.
// Independent Gaussian noise in 200 pixels puts about 2 ln(200) / 200 = 5 % in them.
TEST(ConvergeOutliers, IndependentNoiseIsNotHeldByFewPixels) {
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0, 0.1f);
  std::vector<float> rgba(200 * 4, 1.0f), ref(200 * 3, 0.5f);
  for (size_t p = 0; p < 200; ++p)
    for (int c = 0; c < 3; ++c) rgba[4 * p + c] = 0.5f + noise(rng);
  const PixelRegion all{0, 0, 20, 10, {}};
  const LargestErrors noisy = largestErrors(rgba, ref, all, 20, 10, kOutlierPixels);
  EXPECT_LT(noisy.share, 0.25);
  EXPECT_FALSE(heldByFewPixels(noisy));
  rgba[4 * 57] = 100;  // a firefly
  EXPECT_TRUE(heldByFewPixels(largestErrors(rgba, ref, all, 20, 10, kOutlierPixels)));
  // Among 99 pixels the same firefly is not named: too few pixels for the rule to mean anything.
  const PixelRegion fewer{0, 0, 20, 5, {}};
  std::vector<float> mask(200 * 3, 0.0f);
  for (size_t p = 0; p < 99; ++p) mask[3 * p] = 1;
  EXPECT_FALSE(heldByFewPixels(largestErrors(rgba, ref, PixelRegion{0, 0, 0, 0, mask}, 20, 10, kOutlierPixels)));
  EXPECT_TRUE(heldByFewPixels(largestErrors(rgba, ref, fewer, 20, 10, kOutlierPixels))) << "100 pixels";
}

// The prediction: the last render's seconds times its growth over the one before, at least 2.
TEST(ConvergeBudget, PredictsTheNextRenderFromTheLastGrowth) {
  EXPECT_EQ(ConvergeBudget::predictedNext({1.0}), 2.0);
  EXPECT_EQ(ConvergeBudget::predictedNext({1.0, 1.5}), 3.0) << "setup-dominated: still twice";
  EXPECT_EQ(ConvergeBudget::predictedNext({1.0, 4.0}), 16.0) << "a cost that quadruples per step";
  EXPECT_EQ(ConvergeBudget::predictedNext({0.0, 1.0}), 2.0);
  const ConvergeBudget b{15};
  EXPECT_TRUE(b.mayStart(100, {})) << "the first render always starts";
  EXPECT_TRUE(b.mayStart(7, {4.0}));
  EXPECT_FALSE(b.mayStart(7.5, {4.0}));
  EXPECT_TRUE(b.mustStop(15));
  EXPECT_FALSE(b.mustStop(14.99));
}

// A method whose cost quadruples per step (lbt's beams: twice the beams, each sample gathering
// over more segments): after renders of 0.25, 1 and 4 s (5.25 s in all) a budget of 15 s has
// room for twice the last render (8 s), the old rule, but not for the 16 s the next one takes.
TEST(ConvergeBudget, DoesNotStartARenderThatWouldOverrun) {
  const ConvergeBudget b{15};
  EXPECT_LE(5.25 + 2 * 4.0, b.seconds) << "the old rule would have started it";
  EXPECT_FALSE(b.mayStart(5.25, {0.25, 1.0, 4.0}));
}

// converge() with a scripted clock (ConvergeSettings::now: read as a render starts, as it ends,
// and by the stop check of every render but the first).
class ConvergeClock : public ::testing::Test {
 protected:
  Scene scene = testing::resized(loadScene(testing::sourcePath("scenes/cornell-box.json")), 16, 12, 1);
  ConvergeSettings settings;
  std::vector<double> script;
  size_t reads = 0;
  void SetUp() override {
    settings.reference.assign(16 * 12 * 3, 0.0f);
    settings.errorPixels = settings.region = PixelRegion{0, 0, 16, 12, {}};
    settings.now = [this] { return script[std::min(reads++, script.size() - 1)]; };
  }
};

// The first render took 1 s (read 0, then 1); at 1 s the next is predicted at 2 s.
TEST_F(ConvergeClock, StartsNoRenderWhosePredictionDoesNotFit) {
  script = {0, 1, 1};
  settings.budget.seconds = 2.5;
  const ConvergeRun run = converge(scene, RenderOptions{}, settings);
  ASSERT_EQ(run.rows.size(), 1u);
  EXPECT_EQ(run.rows[0].seconds, 1.0);
  EXPECT_EQ(run.stoppedSpp, 0);
  EXPECT_EQ(reads, 3u) << "the second render was not started";
}

// The same, with room for the prediction, but the clock passes the budget while it renders: it
// is stopped at its first check and leaves no row.
TEST_F(ConvergeClock, StopsARenderThatReachesTheBudget) {
  script = {0, 1, 1, 4};
  settings.budget.seconds = 3.5;
  const ConvergeRun run = converge(scene, RenderOptions{}, settings);
  ASSERT_EQ(run.rows.size(), 1u);
  EXPECT_EQ(run.rows[0].spp, 1);
  EXPECT_EQ(run.stoppedSpp, 2);
  EXPECT_EQ(run.stoppedStart, 1.0);
  EXPECT_EQ(run.stoppedSeconds, 3.0);
}

// A budget shorter than the first render: that render still completes (at least one row).
TEST_F(ConvergeClock, AlwaysCompletesTheFirstRender) {
  script = {0, 100};
  settings.budget.seconds = 1;
  const ConvergeRun run = converge(scene, RenderOptions{}, settings);
  ASSERT_EQ(run.rows.size(), 1u);
  EXPECT_EQ(run.rows[0].seconds, 100.0);
  EXPECT_EQ(run.stoppedSpp, 0);
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

}  // namespace
}  // namespace rayes
