// Motion blur end to end (issue 3, item 4): a moving object's image equals the average of
// still renders at stratified times, within noise; a static scene dices one time sample only;
// a motion whose attributes disagree on the number of time samples is a clear input error.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include "app/command_line.h"
#include "core/error.h"
#include "core/transform.h"
#include "support/render_fixtures.h"
#include "support/temp_folder.h"

namespace rayes {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

constexpr int kW = 32, kH = 16;

// An emissive square (radiance 1, both sides) sliding along x in front of nothing, seen from
// above with direct light only: every camera sample is exactly 0 or 1, so a pixel's value is
// the fraction of (pixel area x shutter) the square covers, and its noise is binomial.
// shutter: "[a, b]"; the square moves 2 units (about 10 pixels) from time 0 to 1.
std::string movingSquare(const std::string& shutter, const std::string& times = "[0, 1]",
                         const std::string& transforms = R"([[{"translate": [-1, 0, 0]}], [{"translate": [1, 0, 0]}]])") {
  return R"({
  "camera": {"position": [0, 0, 6], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 30, "shutter": )" + shutter + R"(},
  "film": {"resolution": [)" + std::to_string(kW) + ", " + std::to_string(kH) + R"(], "spp": 1},
  "integrator": {"max_depth": 1},
  "materials": {"glow": {"type": "emissive", "radiance": 1, "two_sided": true}},
  "shapes": [
    {"type": "bilinear", "material": "glow",
     "motion": {"times": )" + times + R"(,
                "transforms": )" + transforms + R"(},
     "quads": [[[-0.6, -0.6, 0], [0.6, -0.6, 0], [-0.6, 0.6, 0], [0.6, 0.6, 0]]]}
  ]
})";
}

class Motion : public ::testing::Test {
 protected:
  std::string write(const std::string& name, const std::string& text) const { return temp_.write(name, text); }
  // Red channel of a render of `json` with `spp` samples per pixel and seed `seed`.
  std::vector<double> render(const std::string& json, int spp, int seed, RenderStats* stats = nullptr) {
    Scene s = loadScene(write("scene.json", json));
    s.samplesPerPixel = spp;
    s.integrator.seed = uint32_t(seed);
    RenderOptions options;
    options.rayMemoryBytes = size_t(16) << 20;
    options.maxLod = 6;
    const std::vector<float> rgba = testing::renderBeauty(s, options, 2, stats);
    std::vector<double> red(size_t(kW) * kH);
    for (size_t i = 0; i < red.size(); ++i) red[i] = rgba[4 * i];
    return red;
  }
  testing::TempFolder temp_;
  const fs::path& dir_ = temp_.dir();
};

// The square as a still, static scene (no motion key) at time t of the keyframes below: its
// corners interpolated here, independently of the renderer, so that the comparison checks
// where the renderer puts the moving square, not only how it integrates over the shutter.
std::string stillSquare(double t) {
  const double times[3] = {0, 0.25, 1};
  const Transform keys[3] = {Transform::translate({-1.2f, 0, 0}), Transform::translate({0.4f, 0.3f, 0}),
                             Transform::translate({1.2f, -0.2f, 0}) * Transform::rotate({0, 0, 1}, 40)};
  const int i = t < times[1] ? 0 : 1;
  const double a = std::clamp((t - times[i]) / (times[i + 1] - times[i]), 0.0, 1.0);
  std::string quad = "[";
  for (const Vec3 c : {Vec3{-0.6f, -0.6f, 0}, Vec3{0.6f, -0.6f, 0}, Vec3{-0.6f, 0.6f, 0}, Vec3{0.6f, 0.6f, 0}}) {
    const Vec3 p = keys[i].point(c) * float(1 - a) + keys[i + 1].point(c) * float(a);
    quad += (quad.size() > 1 ? ", [" : "[") + std::to_string(p.x) + ", " + std::to_string(p.y) + ", 0]";
  }
  quad += "]";
  return R"({
  "camera": {"position": [0, 0, 6], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 30},
  "film": {"resolution": [)" + std::to_string(kW) + ", " + std::to_string(kH) + R"(], "spp": 1},
  "integrator": {"max_depth": 1},
  "materials": {"glow": {"type": "emissive", "radiance": 1, "two_sided": true}},
  "shapes": [{"type": "bilinear", "material": "glow", "quads": [)" + quad + R"(]}]
})";
}

TEST_F(Motion, BlurredImageEqualsTheAverageOfStillRendersAtStratifiedTimes) {
  constexpr int kSpp = 256, kTimes = 32, kStillSpp = 16;
  // Three keyframes, unevenly spaced, moving fast then slow and turning (stillSquare). The
  // whole shutter, and a part of the first interval (where a time-reversed or wrongly
  // bracketed interpolation would show the square elsewhere).
  auto scene = [](double open, double close) {
    return movingSquare("[" + std::to_string(open) + ", " + std::to_string(close) + "]", "[0, 0.25, 1]",
                        R"([[{"translate": [-1.2, 0, 0]}], [{"translate": [0.4, 0.3, 0]}],
                            [{"rotate": {"axis": [0, 0, 1], "degrees": 40}}, {"translate": [1.2, -0.2, 0]}]])");
  };
  for (const auto& [open, close] : {std::pair{0.0, 1.0}, std::pair{0.02, 0.16}}) {
    const std::vector<double> moving = render(scene(open, close), kSpp, 1);
    std::vector<double> average(moving.size(), 0.0), stillVariance(moving.size(), 0.0);
    int partialInOneStill = 0;
    for (int s = 0; s < kTimes; ++s) {
      const double t = open + (close - open) * (s + 0.5) / kTimes;
      const std::vector<double> still = render(stillSquare(t), kStillSpp, 100 + s);
      for (size_t i = 0; i < still.size(); ++i) {
        average[i] += still[i] / kTimes;
        stillVariance[i] += still[i] * (1 - still[i]) / kStillSpp / (double(kTimes) * kTimes);
        if (s == kTimes / 2) partialInOneStill += still[i] > 0 && still[i] < 1;
      }
    }
    // Per pixel: the difference within 4 standard errors (binomial, estimated from both
    // images), plus one sample's worth of slack for a variance estimated as zero by chance.
    int partialMoving = 0, outliers = 0;
    double sumDiff = 0, sumVar = 0;
    for (size_t i = 0; i < moving.size(); ++i) {
      const double m = moving[i], var = m * (1 - m) / kSpp + stillVariance[i];
      partialMoving += m > 0 && m < 1;
      const double d = m - average[i];
      sumDiff += d;
      sumVar += var;
      if (std::fabs(d) > 4 * std::sqrt(var) + 1.0 / kSpp) ++outliers;
    }
    EXPECT_EQ(outliers, 0) << "shutter " << open << " " << close;
    EXPECT_LT(std::fabs(sumDiff), 4 * std::sqrt(sumVar) + 1e-9) << sumDiff << " " << std::sqrt(sumVar) << " shutter " << open << " " << close;
    // The blur is real: many more partly covered pixels than a still frame has.
    EXPECT_GT(partialMoving, 2 * partialInOneStill) << partialMoving << " " << partialInOneStill;
  }
}

TEST_F(Motion, StaticSceneDicesOneTimeSampleAndMovingSceneTwo) {
  RenderStats still, moving;
  // Keyframes that do not move: the loader keeps one time sample.
  render(movingSquare("[0, 1]", "[0, 1]", R"([[{"translate": [1, 0, 0]}], [{"translate": [1, 0, 0]}]])"), 2, 0, &still);
  render(movingSquare("[0, 1]"), 2, 0, &moving);
  uint64_t stillMoving = 0, movingMoving = 0;
  for (const auto& g : still.generations) stillMoving += g.stats.movingDicings;
  for (const auto& g : moving.generations) movingMoving += g.stats.movingDicings;
  EXPECT_EQ(stillMoving, 0u);
  EXPECT_GT(movingMoving, 0u);
  const Scene a = loadScene(write("a.json", movingSquare("[0, 1]")));
  EXPECT_EQ(a.leaves.patch(0)->timeSamples(), 2);
  const Scene b = loadScene(write("b.json", movingSquare("[0, 1]", "[0, 1]",
                                                          R"([[{"translate": [1, 0, 0]}], [{"translate": [1, 0, 0]}]])")));
  EXPECT_EQ(b.leaves.patch(0)->timeSamples(), 1);
}

// docs/design.md, invariant 2 with motion: scenes/motion-cubes.json (a translating and a turning cube,
// three keyframes) and a moving teapot (curved: interpolated border regions too) give the same
// bits with 1 or 2 threads, every ray traced alone, and a budget small enough for several
// batches and iterations.
TEST_F(Motion, MovingScenesAreOrderIndependent) {
  const std::string teapot = write("teapot.json", R"({
  "camera": {"position": [0, -9, 4], "look_at": [0, 0, 1.5], "up": [0, 0, 1], "fov": 40, "shutter": [0, 1]},
  "materials": {"clay": {"type": "diffuse", "albedo": 0.7}},
  "shapes": [{"type": "bezier", "file": ")" + testing::sourcePath("scenes/teapot.bpt") + R"(", "material": "clay",
              "motion": {"times": [0, 1], "transforms": [[{"translate": [-0.5, 0, 0]}],
                                                        [{"rotate": {"axis": [0, 0, 1], "degrees": 25}}]]}},
             {"type": "bilinear", "material": "clay", "quads": [[[-9, -9, 0], [9, -9, 0], [-9, 9, 0], [9, 9, 0]]]}],
  "lights": [{"type": "point", "position": [3, -4, 8], "intensity": 60}]
})");
  for (const std::string& file : {testing::sourcePath("scenes/motion-cubes.json"), teapot}) {
    Scene s = loadScene(file);
    s.width = 40;
    s.height = 24;
    s.samplesPerPixel = 2;
    RenderOptions o;
    o.maxLod = 6;
    const std::vector<float> reference = testing::renderBeauty(s, o, 2);
    EXPECT_EQ(testing::renderBeauty(s, o, 1), reference) << file;
    RenderOptions alone = o;
    alone.sortByLeaf = false;
    EXPECT_EQ(testing::renderBeauty(s, alone, 2), reference) << file;
    RenderOptions small = o;
    small.rayMemoryBytes = 200 * testing::bytesPerPath(s, o);
    EXPECT_EQ(testing::renderBeauty(s, small, 2), reference) << file;
  }
}

TEST_F(Motion, TimeSampleCountsThatDisagreeAreExit2WithFileAndLine) {
  const std::string scene = write("bad.json", movingSquare("[0, 1]", "[0, 0.5, 1]"));
  try {
    loadScene(scene);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.message(), HasSubstr("bad.json:"));
    EXPECT_THAT(e.what(), HasSubstr("3 times but 2 transforms"));
    EXPECT_THAT(e.what(), HasSubstr("/shapes/0/motion/transforms"));
  }
  std::vector<std::string> args = {"rayes", "render", scene, "-o", (dir_ / "o.exr").string(), "-q"};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  ::testing::internal::CaptureStderr();
  const int code = runCommandLine(int(argv.size()), argv.data());
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(code, 2);
  EXPECT_THAT(err, HasSubstr("bad.json:"));
  EXPECT_FALSE(fs::exists(dir_ / "o.exr"));
  // Times that do not increase.
  EXPECT_THROW(loadScene(write("bad2.json", movingSquare("[0, 1]", "[1, 0]"))), InputError);
}

}  // namespace
}  // namespace rayes
