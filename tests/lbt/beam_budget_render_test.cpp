// Beams within --beam-memory (lbt/beam_budget.h; issue 30): the cases that once exceeded the
// budget by gigabytes, scaled down to run in about a second -- many glossy leaves under a spot
// light, many area-light samples, splits between parallel mirrors, a fine grid on two quads --
// each checked to stay within a small budget (the beams' own high-water mark, counted by the
// account, not the process's RSS) with the same segments and image as without a budget, or to be
// refused with ResourceError naming --beam-memory; and distant-light beams aimed at the
// scatterers: a small mirror's caustic under a sun matches its closed form at any floor size.
#include <gtest/gtest.h>
#include <cfloat>
#include <cmath>
#include <string>
#include "support/beam_scenes.h"
#include "support/render_fixtures.h"
#include "support/temp_folder.h"
#include "core/error.h"

namespace rayes::testing {
namespace {

const BeamIntegrator& beamsOf(const Renderer& r) { return dynamic_cast<const BeamIntegrator&>(r.integrator()); }

RenderOptions lbt(int resolution, size_t memory = size_t(1) << 30) {
  RenderOptions o;
  o.method.name = "lbt";
  o.method.beams.resolution = resolution;
  o.method.beams.memoryBytes = memory;
  return o;
}

// Renders with a budget of a quarter of what the beams held without one: they must stay within
// it (the account's peak), in batches, with the same segments and the same image bit for bit.
void expectWithinAQuarterBudget(const Scene& scene, RenderOptions whole) {
  size_t peak = 0;
  uint64_t segments = 0;
  {
    Renderer r(scene, whole);
    ASSERT_TRUE(beamsOf(r).stats().built) << beamsOf(r).stats().skipped;
    peak = beamsOf(r).stats().peakBytes;
    segments = beamsOf(r).stats().trace.segments;
    EXPECT_LE(peak, whole.method.beams.memoryBytes);
    EXPECT_GE(peak, beamsOf(r).stats().bytes) << "the peak holds the store";
    // The grids the engine kept between the corner rays' traces were on the account too (no
    // camera ray has been traced yet: the cache's peak is the beams').
    EXPECT_LE(r.stats().engine.cachePeakBytes, whole.method.beams.memoryBytes);
  }
  RenderOptions small = whole;
  small.method.beams.memoryBytes = peak / 4;
  {
    Renderer r(scene, small);
    const BeamRenderStats& s = beamsOf(r).stats();
    ASSERT_TRUE(s.built) << s.skipped;
    EXPECT_GE(s.batches, 2u);
    EXPECT_LE(s.peakBytes, small.method.beams.memoryBytes);
    EXPECT_LE(r.stats().engine.cachePeakBytes, small.method.beams.memoryBytes);
    EXPECT_LE(s.bytes, s.peakBytes);
    EXPECT_EQ(s.trace.segments, segments);
    // The rounds retrace the ranges while the film is rendered: the stats file's peak_bytes is
    // the peak after them, still within the budget.
    ThreadLimit limit(2);
    const Film film = r.render();
    EXPECT_EQ(r.stats().method.number("peak_bytes"), double(s.peakBytes));
    EXPECT_LE(s.peakBytes, small.method.beams.memoryBytes);
    EXPECT_EQ(film.beautyRgba(), renderBeauty(scene, whole, 2));
  }
}

// A "forest" of k×k small glossy leaves (bark) at alternating tilts over a diffuse floor, lit by
// a spot light: the case that died with bad_alloc at 4.3-8.8 GB under a 256 MB budget.
TEST(BeamBudget, ManyGlossyLeavesUnderASpotLightStayWithinTheBudget) {
  std::string quads;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) {
      const float x = -1.5f + 0.6f * float(i), y = -1.5f + 0.6f * float(j), t = 0.1f * float((i + j) % 3 - 1);
      if (!quads.empty()) quads += ", ";
      quads += "[[" + std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(1 + t) + "], [" +
               std::to_string(x + 0.4f) + ", " + std::to_string(y) + ", " + std::to_string(1 - t) + "], [" +
               std::to_string(x) + ", " + std::to_string(y + 0.4f) + ", " + std::to_string(1 + t) + "], [" +
               std::to_string(x + 0.4f) + ", " + std::to_string(y + 0.4f) + ", " + std::to_string(1 - t) + "]]";
    }
  const Scene scene = parseScene(R"({
      "camera": {"position": [0, -6, 4], "look_at": [0, 0, 1], "up": [0, 0, 1], "fov": 50},
      "film": {"resolution": [20, 15], "spp": 1},
      "integrator": {"max_depth": 4, "seed": 0},
      "materials": {"bark": {"type": "glossy", "specular": [0.5, 0.5, 0.5], "sigma": 0.05},
        "ground": {"type": "diffuse", "albedo": [0.8, 0.8, 0.8]}},
      "shapes": [{"type": "bilinear", "material": "bark", "quads": [)" + quads + R"(]},
        {"type": "bilinear", "material": "ground", "quads": [[[-6, -6, 4], [6, -6, 4], [-6, 6, 4], [6, 6, 4]]]},
        {"type": "bilinear", "material": "ground", "quads": [[[-6, -6, -0.5], [6, -6, -0.5], [-6, 6, -0.5], [6, 6, -0.5]]]}],
      "lights": [{"type": "spot", "position": [0.3, 0.2, 3], "look_at": [0, 0, 1], "intensity": [20, 20, 20],
                  "cone_angle": 60}]})",
                                 "forest.json");
  RenderOptions whole = lbt(32);
  whole.method.beams.lobeCells = 0;  // keep the grid fine enough to need batches
  expectWithinAQuarterBudget(scene, whole);
}

// One rect light as 12×12 sample points (each a point light seeding the mirror): the seeds are
// streamed, not held (the case that died at 5.0 GB with --beam-area-samples 64).
TEST(BeamBudget, ManyAreaLightSamplesStayWithinTheBudget) {
  const Scene scene = parseScene(rectLightOverMirrorJson(20, 15, 1), "area.json");
  RenderOptions whole = lbt(8);
  whole.method.beams.areaSamples = 12;
  expectWithinAQuarterBudget(scene, whole);
}

// Two parallel mirrors facing each other with a point light between them: beams bounce up to
// 16 times and split up to 6 times where they reach the mirrors' edges (12 and 64 take minutes). Within a small budget
// they are traced in smaller chunks (the tracer's working set and split children counted), and
// a budget below what one seed triangle's splits need is refused naming --beam-memory (the
// case that died after 93 s at 4 GB).
TEST(BeamBudget, SplitsBetweenParallelMirrorsAreCountedAndRefusedWhenOneBeamDoesNotFit) {
  const Scene scene = parseScene(R"({
      "camera": {"position": [0, -6, 0], "look_at": [0, 0, 0], "up": [0, 0, 1], "fov": 50},
      "film": {"resolution": [20, 15], "spp": 1},
      "integrator": {"max_depth": 4, "seed": 0},
      "materials": {"mirror": {"type": "glossy", "specular": [0.95, 0.95, 0.95], "sigma": 0.0001},
        "wall": {"type": "diffuse", "albedo": [0.8, 0.8, 0.8]}},
      "shapes": [
        {"type": "bilinear", "material": "mirror", "quads": [[[-1, -1, -1], [1, -1, -1], [-1, 1, -1], [1, 1, -1]]]},
        {"type": "bilinear", "material": "mirror", "quads": [[[-1, -1, 1], [-1, 1, 1], [1, -1, 1], [1, 1, 1]]]},
        {"type": "bilinear", "material": "wall", "quads": [[[3, -4, -4], [3, 4, -4], [3, -4, 4], [3, 4, 4]]]}],
      "lights": [{"type": "point", "position": [-0.9, 0.1, 0.05], "intensity": [10, 10, 10]}]})",
                                 "mirrors.json");
  RenderOptions whole = lbt(4);
  whole.method.beams.splitDepth = 6;
  whole.method.beams.maxDepth = 16;
  expectWithinAQuarterBudget(scene, whole);
  RenderOptions tiny = whole;
  tiny.method.beams.memoryBytes = 4096;
  try {
    Renderer r(scene, tiny);
    ADD_FAILURE() << "a budget below one beam was accepted";
  } catch (const ResourceError& e) {
    EXPECT_EQ(e.file(), "--beam-memory") << e.what();
  }
}

// A grid much finer than the budget holds at once on two quads: traced in chunks of grid rows,
// stored in ranges (the case that peaked at 3.0 GB with a 1 GB budget at --beam-resolution 4096).
TEST(BeamBudget, AFineGridOnTwoQuadsIsTracedInChunksWithinTheBudget) {
  const Scene scene = parseScene(R"({
      "camera": {"position": [0, -5, 1], "look_at": [0, 0, 1.5], "up": [0, 0, 1], "fov": 50},
      "film": {"resolution": [20, 15], "spp": 1},
      "integrator": {"max_depth": 4, "seed": 0},
      "materials": {"mirror": {"type": "glossy", "specular": [0.9, 0.9, 0.9], "sigma": 0.0001},
        "ceiling": {"type": "diffuse", "albedo": [0.8, 0.8, 0.8]}},
      "shapes": [
        {"type": "bilinear", "material": "mirror", "quads": [[[-1, -1, 0], [0, -1, 0], [-1, 1, 0], [0, 1, 0]]]},
        {"type": "bilinear", "material": "mirror", "quads": [[[0, -1, 0.1], [1, -1, 0.1], [0, 1, 0.1], [1, 1, 0.1]]]},
        {"type": "bilinear", "material": "ceiling", "quads": [[[-4, -4, 2], [4, -4, 2], [-4, 4, 2], [4, 4, 2]]]}],
      "lights": [{"type": "point", "position": [0, 0, 1], "intensity": [10, 10, 10]}]})",
                                 "quads.json");
  expectWithinAQuarterBudget(scene, lbt(96));
}

// A budget that cannot hold the seeds of one beam: ResourceError (exit code 3) naming the option.
TEST(BeamBudget, ABudgetBelowOneBeamIsAResourceErrorWithExitCode3) {
  TempFolder tmp;
  const std::string out = tmp.path("o.exr");
  const RunResult r = runRayes({"render", sourcePath("scenes/lbt-mirror.json"), "-o", out, "-q", "--res", "8x6",
                                "--spp", "1", "--method", "lbt", "--beam-memory", "100"});
  EXPECT_EQ(r.code, 3) << r.err;
  EXPECT_NE(r.err.find("--beam-memory"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
}

// A 2×2 mirror (ρ = 0.9, σ below the delta limit) at z = 0 under a sun of irradiance E = 3 at
// 45° (travelling along (1, 0, -1)/√2), a diffuse floor of half-width F at z = -1 below it and a
// wall at x = 3 (leaf 2) that catches the reflection, travelling along (1, 0, 1)/√2: the mirror
// point (x0, y0) lands at (3, y0, 3 - x0), z in [2, 4], |y| < 1, with irradiance ρ·E·cos 45° on
// the wall (the beam's cross-section is kept). The beams are aimed at the mirror, not spread
// over the floor: the same beams (corner rays, segments) at F = 10 and F = 10⁷.
std::string sunOverMirror(const TempFolder& tmp, double floorHalfWidth) {
  const std::string path = tmp.path("sun.json");
  const std::string f = std::to_string(floorHalfWidth);
  std::ofstream(path) << R"({
    "camera": {"position": [0, -8, 2], "look_at": [1, 0, 1], "up": [0, 0, 1], "fov": 50},
    "film": {"resolution": [8, 6], "spp": 1},
    "materials": {"mirror": {"type": "glossy", "specular": [0.9, 0.9, 0.9], "sigma": 0.0001},
      "floor": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}, "wall": {"type": "diffuse", "albedo": [0.8, 0.8, 0.8]}},
    "shapes": [
      {"type": "bilinear", "material": "mirror", "quads": [[[-1, -1, 0], [1, -1, 0], [-1, 1, 0], [1, 1, 0]]]},
      {"type": "bilinear", "material": "floor", "quads": [[[-)" << f << ", -" << f << ", -1], [" << f << ", -" << f
                      << ", -1], [-" << f << ", " << f << ", -1], [" << f << ", " << f << R"(, -1]]]},
      {"type": "bilinear", "material": "wall", "quads": [[[3, -3, 0.5], [3, 3, 0.5], [3, -3, 6], [3, 3, 6]]]}],
    "lights": [{"type": "distant", "direction": [-1, 0, 1], "irradiance": [3, 3, 3]}]})";
  return path;
}

TEST(BeamBudget, ASunOnASmallMirrorGetsItsCausticAtAnyFloorSize) {
  TempFolder tmp;
  const int n = 32;
  BeamTraceStats first;
  for (double F : {10.0, 1e7}) {
    const Scene scene = loadScene(sunOverMirror(tmp, F));
    Renderer r(scene, lbt(n));
    const BeamStore* beams = beamsOf(r).beams();
    ASSERT_NE(beams, nullptr) << F << ": " << beamsOf(r).stats().skipped;
    // Parallel light on a plane: every beam keeps its cross-section, so E = ρ·E_sun·cos 45°
    // exactly, up to float rounding of the triangles' areas: a few ε of the coordinates (at most
    // 4) over the cells' width (the mirror's 2√2 across the light over N), in Φ and in A⊥.
    const double exact = 0.9 * 3 / std::sqrt(2.0);
    const double cell = 2 * std::sqrt(2.0) / n;
    const double rounding = 4 * 2 * FLT_EPSILON * 4 / cell;
    for (float z : {2.3f, 3.0f, 3.7f})
      for (float y : {0.17f, 0.6f, -0.8f}) {  // off the cells' edges (which both neighbours light)
        double e = 0;
        // At the world point (3, y, z), in the render frame the beams are in (scene.h, RenderFrame).
        beams->gather(2, scene.frame.point(Vec3d(Vec3{3, y, z})), {-1, 0, 0}, [&](Vec3, Rgb irradiance) { e += irradiance.x; });
        EXPECT_NEAR(e, exact, rounding * exact) << F << ": " << y << ", " << z;
      }
    double outside = 0;
    beams->gather(2, scene.frame.point(Vec3d(Vec3{3, 0, 4.5f})), {-1, 0, 0},
                  [&](Vec3, Rgb irradiance) { outside += irradiance.x; });
    EXPECT_EQ(outside, 0.0) << F;
    const BeamTraceStats& s = beamsOf(r).stats().trace;
    if (F == 10.0) {
      first = s;
      continue;
    }
    EXPECT_EQ(s.generatorTriangles, first.generatorTriangles);
    EXPECT_EQ(s.cornerRays, first.cornerRays);
    EXPECT_EQ(s.segments, first.segments);
  }
}

// A roof between the sun and the mirror, far outside the mirror's bounding sphere: the corner
// rays start near the mirror, but their way back toward the sun is traced, so the roof's shadow
// takes the caustic away (no beam lights the wall).
TEST(BeamBudget, AnOccluderFarAboveTheMirrorStillShadowsTheSunsBeams) {
  TempFolder tmp;
  const std::string path = tmp.path("roof.json");
  std::ofstream(path) << R"({
    "camera": {"position": [0, -8, 2], "look_at": [1, 0, 1], "up": [0, 0, 1], "fov": 50},
    "film": {"resolution": [8, 6], "spp": 1},
    "materials": {"mirror": {"type": "glossy", "specular": [0.9, 0.9, 0.9], "sigma": 0.0001},
      "wall": {"type": "diffuse", "albedo": [0.8, 0.8, 0.8]}},
    "shapes": [
      {"type": "bilinear", "material": "mirror", "quads": [[[-1, -1, 0], [1, -1, 0], [-1, 1, 0], [1, 1, 0]]]},
      {"type": "bilinear", "material": "wall", "quads": [[[3, -3, 0.5], [3, 3, 0.5], [3, -3, 6], [3, 3, 6]]]},
      {"type": "bilinear", "material": "wall", "quads": [[[-40, -20, 30], [-20, -20, 30], [-40, 20, 30], [-20, 20, 30]]]}],
    "lights": [{"type": "distant", "direction": [-1, 0, 1], "irradiance": [3, 3, 3]}]})";
  const Scene scene = loadScene(path);
  Renderer r(scene, lbt(16));
  EXPECT_EQ(beamsOf(r).beams(), nullptr);
  EXPECT_EQ(beamsOf(r).stats().trace.segments, 0u);
}

}  // namespace
}  // namespace rayes::testing
