// Light beam tracing end to end (`--method lbt`, src/lbt): beams traced through the ray engine
// on the shipped scenes, checked against closed forms (the planar mirror's irradiance, the
// ring's cusp at R/2, σ adding in quadrature over two glossy bounces), for order independence
// and budgets, for leaving out what a scene does not need (lbt = pt bit for bit), and for bad
// input.
#include <gtest/gtest.h>
#include <fstream>
#include <nlohmann/json.hpp>
#include "render_fixtures.h"
#include "support/temp_folder.h"

namespace rayes::testing {
namespace {

RenderOptions lbtOptions(int resolution = 64) {
  RenderOptions o;
  o.method = IntegratorMethod::LightBeams;
  o.beams.resolution = resolution;
  return o;
}

double gatherAt(const BeamStore& beams, uint32_t leaf, Vec3 x, Vec3 n) {
  double e = 0;
  beams.gather(leaf, x, n, [&](Vec3, Rgb irradiance) { e += irradiance.x; });
  return e;
}

// lbt-mirror.json: I = 10 at (0, 0, 1), a glossy mirror of ρ = 0.9 and σ = 0.001 on [-1, 1]² at
// z = 0, the ceiling at z = 2 (leaf 1): E = 3ρI / D³, D² = x² + y² + 9, inside [-3, 3]².
TEST(Beams, PlanarMirrorThroughTheEngineMatchesTheClosedForm) {
  const Scene scene = loadScene(sourcePath("scenes/lbt-mirror.json"));
  Renderer r(scene, lbtOptions(64));
  ASSERT_NE(r.beams(), nullptr) << r.stats().beams.skipped;
  // Away from the footprint's edge (where cells straddling the mirror's border are dropped)
  // the error is the per-triangle blend, of the order of the cell's angle squared
  // ((2/64)² ≈ 1e-3), plus the lobe's curvature σ² ≈ 1e-6.
  for (float x : {0.0f, 0.8f, -1.7f, 2.4f})
    for (float y : {0.0f, -0.6f, 2.1f}) {
      const double d = std::sqrt(double(x) * x + double(y) * y + 9);
      const double exact = 3 * 0.9 * 10 / (d * d * d);
      EXPECT_NEAR(gatherAt(*r.beams(), 1, {x, y, 2}, {0, 0, -1}), exact, 1.5e-3 * exact) << x << ", " << y;
    }
  for (float x : {3.2f, -3.6f}) EXPECT_EQ(gatherAt(*r.beams(), 1, {x, 0.3f, 2}, {0, 0, -1}), 0.0);
  EXPECT_GT(r.stats().beams.trace.segments, 0u);
}

// lbt-ring.json: a ring of radius R = 1 under parallel light 25° above the horizon, travelling
// along +x. Reflections off a vertical wall keep the light's slope, so on the floor the
// reflected rays' envelope is the nephroid of the 2D circle, its cusp at R/2 on the axis
// (x = +0.5: the far wall focuses back toward the light).
TEST(Beams, RingCausticCuspLiesAtHalfTheRadius) {
  Scene scene = loadScene(sourcePath("scenes/lbt-ring.json"));
  for (Material& m : scene.materials)
    if (m.type == MaterialType::Glossy) m.sigma = 0.01f;  // a finite peak to locate
  Renderer r(scene, lbtOptions(128));
  ASSERT_NE(r.beams(), nullptr) << r.stats().beams.skipped;
  // The floor is the last shape, in tiles: gather on the tile under each point.
  const auto floorLeafAt = [&](float x, float y) {
    for (size_t l = scene.leaves.size(); l-- > 0;) {
      const Box3 b = scene.leaves.bounds(l);
      if (b.lo.z <= 0 && b.hi.z >= 0 && b.lo.x <= x && x <= b.hi.x && b.lo.y <= y && y <= b.hi.y) return uint32_t(l);
    }
    return uint32_t(scene.leaves.size() - 1);
  };
  double best = -1, bestX = 0;
  for (int i = 0; i <= 120; ++i) {
    const float x = 0.2f + 0.6f * float(i) / 120;
    const double e = gatherAt(*r.beams(), floorLeafAt(x, 0), {x, 0, 0}, {0, 0, 1});
    if (e > best) best = e, bestX = x;
  }
  // The lobe (σ = 0.01 over ~0.5 of travel) and the cusp's own asymmetry shift the peak by a
  // few hundredths; a wrong normal or reflection law moves it by tenths.
  EXPECT_NEAR(bestX, 0.5, 0.04);
  EXPECT_GT(best, 0);
}

// Two glossy mirrors facing each other: beams reflected by both carry σ = sqrt(σ1² + σ2²).
TEST(Beams, TwoGlossyBouncesCombineInQuadrature) {
  TempFolder tmp;
  const std::string path = tmp.path("two-mirrors.json");
  std::ofstream(path) << R"({
    "camera": {"position": [0, -8, 3], "look_at": [0, 0, 1], "up": [0, 0, 1], "fov": 40},
    "film": {"resolution": [8, 6], "spp": 1},
    "materials": {
      "a": {"type": "glossy", "specular": [0.8, 0.8, 0.8], "sigma": 0.03},
      "b": {"type": "glossy", "specular": [0.5, 0.5, 0.5], "sigma": 0.04},
      "floor": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
    "shapes": [
      {"type": "bilinear", "material": "a", "quads": [[[-1, -1, 0], [1, -1, 0], [-1, 1, 0], [1, 1, 0]]]},
      {"type": "bilinear", "material": "b", "quads": [[[-3, -3, 4], [3, -3, 4], [-3, 3, 4], [3, 3, 4]]]},
      {"type": "bilinear", "material": "floor", "quads": [[[-20, -20, -1], [20, -20, -1], [-20, 20, -1], [20, 20, -1]]]}],
    "lights": [{"type": "point", "position": [0, 0, 1], "intensity": [10, 10, 10]}]})";
  const Scene scene = loadScene(path);
  Renderer r(scene, lbtOptions(16));
  ASSERT_NE(r.beams(), nullptr);
  // The light sees both mirrors and beams bounce between them (up to --beam-depth): a segment
  // after n_a reflections on a and n_b on b (alternating: |n_a - n_b| ≤ 1) carries
  // σ² = n_a·σa² + n_b·σb², exactly; one a-then-b bounce gives 0.05.
  int twoBounce = 0;
  for (const BeamSegment& s : r.beams()->segments()) {
    bool found = false;
    for (int na = 0; na <= 4 && !found; ++na)
      for (int nb = std::max(0, na - 1); nb <= na + 1 && na + nb <= 4 && !found; ++nb)
        found = na + nb > 0 && std::fabs(s.sigma * s.sigma - (na * 0.03f * 0.03f + nb * 0.04f * 0.04f)) < 1e-6f;
    EXPECT_TRUE(found) << s.sigma;
    twoBounce += std::fabs(s.sigma - 0.05f) < 1e-6f;
  }
  EXPECT_GT(twoBounce, 0);
}

TEST(Beams, ImagesAreOrderIndependentAndBudgetIndependent) {
  Scene scene = loadScene(sourcePath("scenes/lbt-mirror-glossy.json"));
  scene.width = 24;
  scene.height = 18;
  scene.samplesPerPixel = 2;
  expectOrderIndependent(scene, 37, lbtOptions(16));
}

// A scene with no specular or glossy surface, and one whose only light is an environment:
// no beams, the stats say why, and the image is the path tracer's bit for bit.
TEST(Beams, ScenesWithoutLitScatterersAreThePathTracerBitForBit) {
  for (const char* file : {"scenes/cornell-box.json", "scenes/materials.json"}) {
    Scene scene = loadScene(sourcePath(file));
    scene.width = 16;
    scene.height = 12;
    scene.samplesPerPixel = 2;
    Renderer r(scene, lbtOptions());
    EXPECT_EQ(r.beams(), nullptr) << file;
    EXPECT_FALSE(r.stats().beams.skipped.empty()) << file;
    EXPECT_EQ(renderBeauty(scene, lbtOptions(), 2), renderBeauty(scene, RenderOptions{}, 2)) << file;
  }
}

TEST(Beams, BadOptionsAreRefusedWithExitCode2AndNoOutput) {
  TempFolder tmp;
  const std::string scene = sourcePath("scenes/lbt-mirror.json");
  const std::string out = tmp.path("o.exr");
  RunResult r = runRayes({"render", scene, "-o", out, "-q", "--res", "8x6", "--spp", "1", "--method", "lbt",
                          "--beam-memory", "100"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--beam-memory"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("one beam"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
  r = runRayes({"render", scene, "-o", out, "-q", "--method", "lbt", "--beam-resolution", "0"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--beam-resolution"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(Beams, StatsCountTheBeams) {
  TempFolder tmp;
  const RunResult r = runRayes({"render", sourcePath("scenes/lbt-mirror.json"), "-o", tmp.path("o.exr"), "-q",
                                "--res", "8x6", "--spp", "1", "--method", "lbt", "--beam-resolution", "8", "--stats",
                                tmp.path("s.json")});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(std::ifstream(tmp.path("s.json")));
  EXPECT_EQ(j["settings"]["method"], "lbt");
  EXPECT_GT(j["beams"]["segments"].get<uint64_t>(), 0u);
  EXPECT_GT(j["beams"]["bytes"].get<uint64_t>(), 0u);
  EXPECT_FALSE(j["skipped"].contains("beams"));
}

}  // namespace
}  // namespace rayes::testing
