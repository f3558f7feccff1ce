// Light beam tracing end to end (`--method lbt`, src/lbt): beams traced through the ray engine
// on the shipped scenes, checked against closed forms (the planar mirror's irradiance, the
// ring's cusp at R/2, σ adding in quadrature over two glossy bounces), for order independence
// and budgets, for leaving out what a scene does not need (lbt = pt bit for bit), and for bad
// input.
#include <gtest/gtest.h>
#include <fstream>
#include <numbers>
#include <nlohmann/json.hpp>
#include "support/beam_scenes.h"
#include "support/mirror_caustic_scene.h"
#include "support/render_fixtures.h"
#include "support/temp_folder.h"
#include "core/error.h"
#include "shading/fresnel.h"

namespace rayes::testing {
namespace {

// The beam integrator of a render with --method lbt: its beams and what its light phase did.
const BeamIntegrator& beamsOf(const Renderer& r) { return dynamic_cast<const BeamIntegrator&>(r.integrator()); }

RenderOptions lbtOptions(int resolution = 64) {
  RenderOptions o;
  o.method.name = "lbt";
  o.method.beams.resolution = resolution;
  return o;
}

// A shipped scene at a small resolution and sample count.
Scene shippedScene(const std::string& file, int width, int height, int spp) {
  Scene scene = loadScene(sourcePath(file));
  scene.width = width;
  scene.height = height;
  scene.samplesPerPixel = spp;
  return scene;
}

// The gather at the world point x: the beams are in the scene's render frame (scene.h,
// RenderFrame), whose origin is the camera.
double gatherAt(const Scene& scene, const BeamStore& beams, uint32_t leaf, Vec3 x, Vec3 n) {
  double e = 0;
  beams.gather(leaf, scene.frame.point(Vec3d(x)), n, [&](Vec3, Rgb irradiance) { e += irradiance.x; });
  return e;
}

// lbt-mirror.json: I = 10 at (0, 0, 1), a glossy mirror of ρ = 0.9 and σ = 0.001 on [-1, 1]² at
// z = 0, the ceiling at z = 2 (leaf 1): E = 3ρI / D³, D² = x² + y² + 9, inside [-3, 3]².
TEST(Beams, PlanarMirrorThroughTheEngineMatchesTheClosedForm) {
  const Scene scene = loadScene(sourcePath("scenes/lbt-mirror.json"));
  Renderer r(scene, lbtOptions(64));
  ASSERT_NE(beamsOf(r).beams(), nullptr) << beamsOf(r).stats().skipped;
  // Away from the footprint's edge (where cells straddling the mirror's border are split, down
  // to a sixteenth of a cell, then dropped) the error is the per-triangle blend, of the order of the cell's angle squared
  // ((2/64)² ≈ 1e-3), plus the lobe's curvature σ² ≈ 1e-6.
  for (float x : {0.0f, 0.8f, -1.7f, 2.4f})
    for (float y : {0.0f, -0.6f, 2.1f}) {
      const double d = std::sqrt(double(x) * x + double(y) * y + 9);
      const double exact = 3 * 0.9 * 10 / (d * d * d);
      EXPECT_NEAR(gatherAt(scene, *beamsOf(r).beams(), 1, {x, y, 2}, {0, 0, -1}), exact, 1.5e-3 * exact) << x << ", " << y;
    }
  for (float x : {3.2f, -3.6f}) EXPECT_EQ(gatherAt(scene, *beamsOf(r).beams(), 1, {x, 0.3f, 2}, {0, 0, -1}), 0.0);
  EXPECT_GT(beamsOf(r).stats().trace.segments, 0u);
}

// Grazing incidence on a scatterer: a point light of I = 10 at (-6, 0, h) over a mirror
// [-1, 1]² at z = 0 (ρ = 0.9, σ below the delta limit), light 2.9° above it at h = 0.3; a wall
// at x = 6 (leaf 1) catches the reflection as if from the light's image (-6, 0, -h):
// E = ρ·I·cos θ / D³·D = ρ·I·12 / D³ inside the footprint. The beams' cells are as fine as the
// light sees the mirror, so the relative error is the planar mirror's (1.5e-3), and their flux
// adds up to ρ·I·Ω with Ω the mirror's solid angle from the light, however thin it is. With
// the light in the mirror's plane (h = 0) the mirror is edge-on: Ω = 0, no beams, no NaN.
std::string grazingMirror(const TempFolder& tmp, float h) {
  const std::string path = tmp.path("grazing.json");
  std::ofstream(path) << R"({
    "camera": {"position": [0, -8, 2], "look_at": [3, 0, 0.5], "up": [0, 0, 1], "fov": 50},
    "film": {"resolution": [8, 6], "spp": 1},
    "materials": {"mirror": {"type": "glossy", "specular": [0.9, 0.9, 0.9], "sigma": 0.0001},
      "wall": {"type": "diffuse", "albedo": [0.8, 0.8, 0.8]}},
    "shapes": [
      {"type": "bilinear", "material": "mirror", "quads": [[[-1, -1, 0], [1, -1, 0], [-1, 1, 0], [1, 1, 0]]]},
      {"type": "bilinear", "material": "wall", "quads": [[[6, -6, -1], [6, 6, -1], [6, -6, 5], [6, 6, 5]]]}],
    "lights": [{"type": "point", "position": [-6, 0, )" << h << R"(], "intensity": [10, 10, 10]}]})";
  return path;
}

TEST(Beams, GrazingIncidenceOnAMirrorMatchesTheClosedFormAndEdgeOnGivesNothing) {
  TempFolder tmp;
  const float h = 0.3f;
  const Scene scene = loadScene(grazingMirror(tmp, h));
  Renderer r(scene, lbtOptions(64));
  ASSERT_NE(beamsOf(r).beams(), nullptr) << beamsOf(r).stats().skipped;
  // Inside the footprint on the wall: z = h (6 - x0) / (6 + x0) in [0.214, 0.42] for mirror
  // points x0 in [-1, 1], |y| < 1.7 at its narrow end.
  for (float z : {0.25f, 0.3f, 0.38f})
    for (float y : {0.0f, 0.7f, -1.1f}) {
      const double d = std::sqrt(144.0 + double(y) * y + double(z + h) * (z + h));
      const double exact = 0.9 * 10 * 12 / (d * d * d);
      EXPECT_NEAR(gatherAt(scene, *beamsOf(r).beams(), 1, {6, y, z}, {-1, 0, 0}), exact, 1.5e-3 * exact) << y << ", " << z;
    }
  EXPECT_EQ(gatherAt(scene, *beamsOf(r).beams(), 1, {6, 0, 0.6f}, {-1, 0, 0}), 0.0);  // above the footprint
  const Vec3 light{-6, 0, h};
  Vec3 c[4] = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  for (Vec3& v : c) v = normalize(v - light);
  const double omega = sphericalTriangleArea(c[0], c[1], c[2]) + sphericalTriangleArea(c[0], c[2], c[3]);
  double power = 0;
  for (const BeamSegment& s : beamsOf(r).beams()->segments()) {
    EXPECT_TRUE(isFinite(s.power));
    power += s.scatterings == 1 ? s.power.x : 0;
  }
  EXPECT_NEAR(power, 0.9 * 10 * omega, 1e-3 * 0.9 * 10 * omega);

  const Scene edgeOn = loadScene(grazingMirror(tmp, 0));
  Renderer e(edgeOn, lbtOptions(64));
  EXPECT_EQ(beamsOf(e).beams(), nullptr);  // no beam reaches past the mirror, and the stats say so
  EXPECT_FALSE(beamsOf(e).stats().skipped.empty());
  for (float v : renderBeauty(edgeOn, lbtOptions(16), 2)) ASSERT_TRUE(std::isfinite(v));
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
  ASSERT_NE(beamsOf(r).beams(), nullptr) << beamsOf(r).stats().skipped;
  // The floor is the last shape, in tiles: gather on the tile under each point.
  const auto floorLeafAt = [&](float wx, float wy) {
    const Vec3 q = scene.frame.point(Vec3d(Vec3{wx, wy, 0}));  // leaf boxes are in the render frame
    for (size_t l = scene.leaves.size(); l-- > 0;) {
      const Box3 b = scene.leaves.bounds(l);
      if (b.contains(q)) return uint32_t(l);
    }
    return uint32_t(scene.leaves.size() - 1);
  };
  double best = -1, bestX = 0;
  for (int i = 0; i <= 120; ++i) {
    const float x = 0.2f + 0.6f * float(i) / 120;
    const double e = gatherAt(scene, *beamsOf(r).beams(), floorLeafAt(x, 0), {x, 0, 0}, {0, 0, 1});
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
  ASSERT_NE(beamsOf(r).beams(), nullptr);
  // The light sees both mirrors and beams bounce between them (up to --beam-depth): a segment
  // after n_a reflections on a and n_b on b (alternating: |n_a - n_b| ≤ 1) carries
  // σ² = n_a·σa² + n_b·σb², exactly; one a-then-b bounce gives 0.05.
  int twoBounce = 0;
  for (const BeamSegment& s : beamsOf(r).beams()->segments()) {
    bool found = false;
    for (int na = 0; na <= 4 && !found; ++na)
      for (int nb = std::max(0, na - 1); nb <= na + 1 && na + nb <= 4 && !found; ++nb)
        found = na + nb > 0 && std::fabs(s.sigma * s.sigma - (na * 0.03f * 0.03f + nb * 0.04f * 0.04f)) < 1e-6f;
    EXPECT_TRUE(found) << s.sigma;
    twoBounce += std::fabs(s.sigma - 0.05f) < 1e-6f;
  }
  EXPECT_GT(twoBounce, 0);
}

// A point light off the mirror's axis above a large ceiling: the beams' flux on the ceiling,
// ∫E dA by the midpoint rule, is ρ·I·Ω with Ω the mirror's solid angle from the light. An
// occluder (a square between the light and the mirror, of `occluder` material, none if empty)
// casts its shadow on the mirror.
std::string offAxisMirror(const TempFolder& tmp, const char* mirror, const std::string& occluder = "") {
  const std::string path = tmp.path("mirror.json");
  std::ofstream(path) << R"({
    "camera": {"position": [0, -6, 0.3], "look_at": [0, 0, 1.6], "up": [0, 0, 1], "fov": 55},
    "film": {"resolution": [8, 6], "spp": 1},
    "materials": {"mirror": )" << mirror << R"(,)" << (occluder.empty() ? "" : R"("occluder": )" + occluder + ",") << R"(
      "ceiling": {"type": "diffuse", "albedo": [0.8, 0.8, 0.8]}},
    "shapes": [
      {"type": "bilinear", "material": "mirror", "quads": [[[-1, -1, 0], [1, -1, 0], [-1, 1, 0], [1, 1, 0]]]},)"
                      << (occluder.empty() ? "" : R"(
      {"type": "bilinear", "material": "occluder", "quads": [[[-0.3, -0.25, 0.5], [0.2, -0.25, 0.5], [-0.3, 0.35, 0.5], [0.2, 0.35, 0.5]]]},)")
                      << R"(
      {"type": "bilinear", "material": "ceiling", "quads": [[[-6, -6, 2], [6, -6, 2], [-6, 6, 2], [6, 6, 2]]]}],
    "lights": [{"type": "point", "position": [0.13, 0.07, 1], "intensity": [10, 10, 10]}]})";
  return path;
}

double ceilingFlux(const Scene& scene, const BeamStore& beams, uint32_t leaf, float half, int n) {
  const double h = 2.0 * half / n;
  double sum = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      sum += gatherAt(scene, beams, leaf, {float(-half + (i + 0.5) * h), float(-half + (j + 0.5) * h), 2}, {0, 0, -1});
  return sum * h * h;
}

// The solid angle of the square [-h, h]² at z = 0 seen from `light`.
double squareSolidAngle(Vec3 light, float h) {
  const Vec3 c[4] = {{-h, -h, 0}, {h, -h, 0}, {h, h, 0}, {-h, h, 0}};
  Vec3 d[4];
  for (int k = 0; k < 4; ++k) d[k] = normalize(c[k] - light);
  return sphericalTriangleArea(d[0], d[1], d[2]) + sphericalTriangleArea(d[0], d[2], d[3]);
}

// The power of the segments that leave a first scatterer.
double firstBouncePower(const BeamStore& beams) {
  double sum = 0;
  for (const BeamSegment& s : beams.segments()) sum += s.scatterings == 1 ? s.power.x : 0;
  return sum;
}

TEST(Beams, AMirrorsEdgeNeverCutsABeam) {
  // Each leaf has its own grid of beams: none straddles the mirror's edge, so nothing needs a
  // split and nothing is dropped, whatever the split depth.
  TempFolder tmp;
  const Scene scene = loadScene(offAxisMirror(tmp, R"({"type": "glossy", "specular": [0.9, 0.9, 0.9], "sigma": 0.0001})"));
  const double exact = 0.9 * 10 * squareSolidAngle({0.13f, 0.07f, 1}, 1);
  const uint32_t ceiling = uint32_t(scene.leaves.size() - 1);
  for (const int splitDepth : {4, 0}) {
    RenderOptions o = lbtOptions(16);
    o.method.beams.splitDepth = splitDepth;
    Renderer r(scene, o);
    ASSERT_NE(beamsOf(r).beams(), nullptr);
    EXPECT_EQ(beamsOf(r).stats().trace.splits, 0u);
    EXPECT_EQ(beamsOf(r).stats().trace.droppedFlux, 0.0);
    // The footprint lies inside [-2.7, 3.3]²; the midpoint rule's error is at the footprint's
    // edge: below perimeter·h/2·E_edge ≈ 24·0.01·0.4 ≈ 0.1 (0.5 % of the 18.7 W); the aim
    // points' inset loses at most 4·10⁻⁴.
    EXPECT_NEAR(ceilingFlux(scene, *beamsOf(r).beams(), ceiling, 4, 400), exact, 0.005 * exact) << splitDepth;
    EXPECT_NEAR(firstBouncePower(*beamsOf(r).beams()), exact, 4e-4 * exact) << splitDepth;
  }
}

// The solid angle of the occluder's square (z = 0.5, [-0.3, 0.2] × [-0.25, 0.35]) from the light.
double occluderSolidAngle() {
  const Vec3 light{0.13f, 0.07f, 1};
  const Vec3 c[4] = {{-0.3f, -0.25f, 0.5f}, {0.2f, -0.25f, 0.5f}, {0.2f, 0.35f, 0.5f}, {-0.3f, 0.35f, 0.5f}};
  Vec3 d[4];
  for (int k = 0; k < 4; ++k) d[k] = normalize(c[k] - light);
  return sphericalTriangleArea(d[0], d[1], d[2]) + sphericalTriangleArea(d[0], d[2], d[3]);
}

TEST(Beams, SplittingKeepsTheFluxAroundAShadowAndNothingIsCountedTwice) {
  // A diffuse square between the light and the mirror (its shadow lies wholly on the mirror):
  // beams whose corner rays end on it are the mirror's no more. Those it cuts are split
  // (--beam-split-depth); without splits their flux is dropped (and counted). The first-bounce
  // power is ρ·I·(Ω_mirror − Ω_occluder), never more.
  TempFolder tmp;
  const char* mirror = R"({"type": "glossy", "specular": [0.9, 0.9, 0.9], "sigma": 0.0001})";
  const double mirrorPower = 0.9 * 10 * squareSolidAngle({0.13f, 0.07f, 1}, 1);
  const double shadowed = mirrorPower - 0.9 * 10 * occluderSolidAngle();
  {
    const Scene scene = loadScene(offAxisMirror(tmp, mirror, R"({"type": "diffuse", "albedo": [0.5, 0.5, 0.5]})"));
    Renderer r(scene, lbtOptions(16));
    ASSERT_NE(beamsOf(r).beams(), nullptr);
    EXPECT_GT(beamsOf(r).stats().trace.splits, 0u);
    EXPECT_LT(firstBouncePower(*beamsOf(r).beams()), shadowed * (1 + 1e-4));
    EXPECT_GT(firstBouncePower(*beamsOf(r).beams()), 0.99 * shadowed);
    EXPECT_LT(beamsOf(r).stats().trace.droppedFlux, 0.01 * shadowed);
    RenderOptions whole = lbtOptions(16);
    whole.method.beams.splitDepth = 0;
    Renderer w(scene, whole);
    ASSERT_NE(beamsOf(w).beams(), nullptr);
    EXPECT_GT(beamsOf(w).stats().trace.droppedFlux, 0);
    EXPECT_LT(firstBouncePower(*beamsOf(w).beams()), 0.98 * shadowed);
  }
  {
    // The occluder a mirror too: its own beams carry what it hides from the big one, and the
    // big one's beams toward it are not counted again: ρ·I·Ω_mirror in all.
    const Scene scene = loadScene(offAxisMirror(tmp, mirror, mirror));
    Renderer r(scene, lbtOptions(16));
    ASSERT_NE(beamsOf(r).beams(), nullptr);
    EXPECT_LT(firstBouncePower(*beamsOf(r).beams()), mirrorPower * (1 + 1e-4));
    EXPECT_GT(firstBouncePower(*beamsOf(r).beams()), 0.99 * mirrorPower);
  }
}

// One patch that a light sees twice: a U-shaped trough lit from its side, whose near wall
// hides its own inside. That inside's beams find the near wall first, on their own leaf but far
// from their aims in (u, v): they end there, so the trough as one patch sends the flux it sends
// as two patches (the same surface cut at its bottom, de Casteljau), where most of what hides
// the inside is another leaf. With the leaf checked but not the aim, the one patch sends 0.386
// against the two's 0.267 (and 0.249 both, checked): the hidden inside counted on top.
TEST(Beams, APatchFoldedInTheLightsViewSendsItsFluxOnce) {
  TempFolder tmp;
  auto trough = [&](bool split) {
    const std::string path = tmp.path(split ? "two.json" : "one.json");
    std::ofstream f(path);
    // Profiles in (x, z) swept along y in [-1, 1]: the U, or its halves at t = ½.
    const std::vector<std::array<std::array<double, 2>, 4>> profiles =
        split ? std::vector<std::array<std::array<double, 2>, 4>>{{{{1, 0}, {1, -2.0 / 3}, {0.5, -1}, {0, -1}}},
                                                                  {{{0, -1}, {-0.5, -1}, {-1, -2.0 / 3}, {-1, 0}}}}
              : std::vector<std::array<std::array<double, 2>, 4>>{{{{1, 0}, {1, -4.0 / 3}, {-1, -4.0 / 3}, {-1, 0}}}};
    f << R"({"camera": {"position": [4, -4, 1], "look_at": [0, 0, -0.5], "up": [0, 0, 1], "fov": 40},
      "film": {"resolution": [8, 6], "spp": 1},
      "materials": {"mirror": {"type": "glossy", "specular": [0.9, 0.9, 0.9], "sigma": 0.0001},
        "box": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
      "shapes": [{"type": "bezier", "material": "mirror", "patches": [)";
    for (size_t k = 0; k < profiles.size(); ++k) {
      f << (k ? ", [" : "[");
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i)
          f << (i || j ? ", " : "") << "[" << profiles[k][i][0] << ", " << (-1 + 2.0 * j / 3) << ", " << profiles[k][i][1] << "]";
      f << "]";
    }
    f << R"(]},
      {"type": "bilinear", "material": "box", "quads": [
        [[-5, -5, -2], [5, -5, -2], [-5, 5, -2], [5, 5, -2]], [[-5, -5, 2], [5, -5, 2], [-5, 5, 2], [5, 5, 2]],
        [[-5, -5, -2], [-5, 5, -2], [-5, -5, 2], [-5, 5, 2]], [[5, -5, -2], [5, 5, -2], [5, -5, 2], [5, 5, 2]],
        [[-5, -5, -2], [5, -5, -2], [-5, -5, 2], [5, -5, 2]], [[-5, 5, -2], [5, 5, -2], [-5, 5, 2], [5, 5, 2]]]}],
      "lights": [{"type": "point", "position": [3, 0.2, 0.3], "intensity": [1, 1, 1]}]})";
    f.close();
    const Scene scene = loadScene(path);
    Renderer r(scene, lbtOptions(64));
    EXPECT_NE(beamsOf(r).beams(), nullptr) << beamsOf(r).stats().skipped;
    return beamsOf(r).beams() ? firstBouncePower(*beamsOf(r).beams()) : 0.0;
  };
  const double one = trough(false), two = trough(true);
  EXPECT_GT(two, 0);
  // Beams cut along the silhouette are split and partly dropped, differently in the two.
  EXPECT_NEAR(one, two, 0.02 * two);
}

// A dielectric plane under the light: the beams carry its Fresnel-reflected part too, E =
// F(cos θ)·I·cos θ/D² on the ceiling (D² = x² + y² + 9, cos θ = 3/D at the mirror point), F of
// ior 1.5 from shading/fresnel.h.
TEST(Beams, DielectricsReflectTheirFresnelPart) {
  TempFolder tmp;
  const Scene scene = loadScene(offAxisMirror(tmp, R"({"type": "dielectric", "ior": 1.5})"));
  const int n = 64;
  Renderer r(scene, lbtOptions(n));
  ASSERT_NE(beamsOf(r).beams(), nullptr);
  EXPECT_GT(beamsOf(r).stats().trace.reflectedBranches, 0u);
  const uint32_t ceiling = uint32_t(scene.leaves.size() - 1);
  // The light at (0.13, 0.07, 1), its image at (0.13, 0.07, -1); E = F·3I/D³ with D the
  // distance from the image. Error: the corner blend, ~(2/n)² (as the mirror's), plus F
  // averaged over a triangle's corners instead of taken at x: at most F's change over one
  // cell's angle (2/n at the face's centre).
  for (float x : {0.1f, 0.9f, -1.2f})
    for (float y : {0.0f, 1.4f}) {
      const double dx = x - 0.13, dy = y - 0.07, d = std::sqrt(dx * dx + dy * dy + 9);
      const double theta = std::acos(3 / d), cell = 2.0 / n;
      const double f = fresnelDielectric(float(3 / d), 1.5f);
      const double df = std::fabs(fresnelDielectric(float(std::cos(theta + cell)), 1.5f) -
                                  fresnelDielectric(float(std::cos(std::max(0.0, theta - cell))), 1.5f));
      const double exact = f * 3 * 10 / (d * d * d);
      EXPECT_NEAR(gatherAt(scene, *beamsOf(r).beams(), ceiling, {x, y, 2}, {0, 0, -1}), exact, (1.5e-3 + df / f) * exact)
          << x << ", " << y;
    }
}

// A light inside glass under its flat top (normal up): corner rays steeper than the critical
// angle refract out (1 − F) and reflect back in (F); past it they reflect wholly. Beams that
// straddle the critical angle split; their reflected branch is whole. Every first-bounce beam
// starts on the plane, so their powers add up to I·Ω of the plane (minus what is dropped at the
// plane's edges and along the critical circle).
TEST(Beams, BeamsStraddlingTotalInternalReflectionSplitAndKeepTheirFlux) {
  TempFolder tmp;
  const std::string path = tmp.path("tir.json");
  std::ofstream(path) << R"({
    "camera": {"position": [0, -8, 0], "look_at": [0, 0, 0], "up": [0, 0, 1], "fov": 55},
    "film": {"resolution": [8, 6], "spp": 1},
    "materials": {"glass": {"type": "dielectric", "ior": 1.5},
      "wall": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
    "shapes": [
      {"type": "bilinear", "material": "glass", "quads": [[[-3, -3, 0], [3, -3, 0], [-3, 3, 0], [3, 3, 0]]]},
      {"type": "bilinear", "material": "wall", "quads": [[[-30, -30, 2], [30, -30, 2], [-30, 30, 2], [30, 30, 2]]]},
      {"type": "bilinear", "material": "wall", "quads": [[[-30, 30, -3], [30, 30, -3], [-30, -30, -3], [30, -30, -3]]]}],
    "lights": [{"type": "point", "position": [0.05, 0.03, -1], "intensity": [1, 1, 1]}]})";
  const Scene scene = loadScene(path);
  RenderOptions o = lbtOptions(24);
  o.method.beams.maxDepth = 1;
  Renderer r(scene, o);
  ASSERT_NE(beamsOf(r).beams(), nullptr);
  const BeamRenderStats& b = beamsOf(r).stats();
  EXPECT_GT(b.trace.splits, 0u);
  EXPECT_GT(b.trace.reflectedBranches, 0u);
  double up = 0, down = 0;
  for (const BeamSegment& s : beamsOf(r).beams()->segments()) {
    for (int i = 0; i < 3; ++i) EXPECT_TRUE(isFinite(s.d[i]) && std::isfinite(s.t[i]));
    (s.d[0].z > 0 ? up : down) += s.power.x;
  }
  const double omega = squareSolidAngle({0.05f, 0.03f, -1}, 3);
  // Nothing counted twice (each split shares its parent's flux exactly, each corner's 1 − F and F
  // add up to 1), and what splitting could not keep is under 1 %.
  EXPECT_LT(up + down, omega * (1 + 1e-4));
  EXPECT_GT(up + down, 0.99 * omega);
  EXPECT_GT(b.trace.droppedFlux, 0);
  // Out through the escape cone (θ < θc = asin(1/1.5)): ∫ (1 − F(θ)) dΩ, F seen from inside.
  const double thetaC = std::asin(1 / 1.5);
  double escape = 0;
  for (int k = 0; k < 4000; ++k) {
    const double th = (k + 0.5) * thetaC / 4000;
    escape += (1 - fresnelDielectric(-float(std::cos(th)), 1.5f)) * 2 * std::numbers::pi * std::sin(th) * thetaC / 4000;
  }
  EXPECT_NEAR(up, escape, 0.01 * escape);
}

// A budget that holds a third of the beams: they are processed in batches (the camera paths
// once per batch), and the image is the unbatched one bit for bit.
TEST(Beams, BatchesUnderTheBeamMemoryBudgetGiveTheSameImage) {
  Scene scene = shippedScene("scenes/lbt-mirror-glossy.json", 20, 15, 1);
  const RenderOptions whole = lbtOptions(12);
  Renderer one(scene, whole);
  ASSERT_NE(beamsOf(one).beams(), nullptr);
  EXPECT_EQ(beamsOf(one).stats().batches, 1u);
  RenderOptions small = whole;
  small.method.beams.memoryBytes = beamsOf(one).stats().bytes / 3;
  Renderer several(scene, small);
  EXPECT_GE(beamsOf(several).stats().batches, 3u);
  EXPECT_EQ(beamsOf(several).stats().trace.segments, beamsOf(one).stats().trace.segments);
  // The budget holds everything beams keep: the largest range's store and the partial gathers
  // of a camera batch (12 B per path and bounce).
  EXPECT_LE(beamsOf(several).stats().bytes, small.method.beams.memoryBytes);
  EXPECT_GE(beamsOf(several).stats().bytes,
            several.stats().pathsPerBatch * size_t(scene.integrator.maxDepth) * sizeof(Rgb));
  const auto ref = renderBeauty(scene, whole, 2);
  EXPECT_EQ(renderBeauty(scene, small, 2), ref);
  EXPECT_NE(renderBeauty(scene, RenderOptions{}, 2), ref);  // the beams are in the image
  // Every round traces the camera paths again; their first hits reach the film once (round 0).
  const Film oneFilm = Renderer(scene, whole).render(), severalFilm = Renderer(scene, small).render();
  EXPECT_EQ(severalFilm.sums().hits, oneFilm.sums().hits);
  EXPECT_EQ(severalFilm.sums().depth, oneFilm.sums().depth);
  EXPECT_EQ(severalFilm.sums().albedo, oneFilm.sums().albedo);
  // A budget the partial gathers alone fill: refused, naming both budgets' options.
  RenderOptions tiny = whole;
  tiny.method.beams.memoryBytes = several.stats().pathsPerBatch * size_t(scene.integrator.maxDepth) * sizeof(Rgb);
  try {
    Renderer refused(scene, tiny);
    ADD_FAILURE() << "a budget the partial gathers fill was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("partial gathers"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--ray-memory"), std::string::npos) << e.what();
  }
}

// A small rect light facing down onto a mirror, the ceiling above lit only through the mirror:
// every light path to the ceiling is a caustic one. lbt (beams from 2×2 points of the light)
// against the light tracer, the reference for caustics: the image means agree within 4
// standard errors, estimated from independent seeds of both.
TEST(Beams, AreaLightsSendBeamsFromSamplePointsAndMatchTheLightTracer) {
  TempFolder tmp;
  const std::string path = tmp.path("area.json");
  std::ofstream(path) << rectLightOverMirrorJson(12, 9, 4);
  Scene scene = loadScene(path);
  {
    Renderer r(scene, lbtOptions(24));
    ASSERT_NE(beamsOf(r).beams(), nullptr) << beamsOf(r).stats().skipped;
    EXPECT_GT(beamsOf(r).stats().trace.segments, 0u);
  }
  auto mean = [](const std::vector<float>& rgba) {
    double sum = 0;
    for (size_t i = 0; i < rgba.size(); i += 4) sum += rgba[i];
    return sum / double(rgba.size() / 4);
  };
  auto stats = [&](const RenderOptions& o, int seeds, double& m, double& se) {
    std::vector<double> means;
    for (int k = 0; k < seeds; ++k) {
      scene.integrator.seed = uint32_t(k + 1);
      means.push_back(mean(renderBeauty(scene, o, 2)));
    }
    m = 0;
    for (double x : means) m += x / seeds;
    double var = 0;
    for (double x : means) var += (x - m) * (x - m) / (seeds - 1);
    se = std::sqrt(var / seeds);
  };
  RenderOptions lt;
  lt.method.name = "lt";
  double mLt, seLt, mLbt, seLbt;
  stats(lt, 8, mLt, seLt);
  stats(lbtOptions(24), 4, mLbt, seLbt);
  EXPECT_GT(mLt, 0);
  EXPECT_NEAR(mLbt, mLt, 4 * std::sqrt(seLt * seLt + seLbt * seLbt)) << "lt " << mLt << " ± " << seLt;
}

// An environment light gets no beams, so its caustic paths stay with the path tracer: a glossy
// mirror (σ = 0.05: the path tracer finds every caustic path through it) stands on a diffuse
// floor under a uniform sky and a point light. lbt (beams for the point light, the path tracer
// for the sky's caustic) must agree with the full path tracer; block means within 4 standard
// errors over independent seeds (13 comparisons; Student-t with 31 degrees of freedom: a false
// alarm in about 0.5 % of runs). The sky's caustic alone (pt --caustic-paths only without the
// point light) stands well above that tolerance, so leaving it out would fail.
TEST(Beams, EnvironmentLightCausticsStayWithThePathTracer) {
  TempFolder tmp;
  auto sceneWith = [&](const char* lights) {
    const std::string path = tmp.path("env.json");
    std::ofstream(path) << R"({
      "camera": {"position": [0.6, 0, 6], "look_at": [0.6, 0, 0], "up": [0, 1, 0], "fov": 40},
      "film": {"resolution": [16, 12], "spp": 4},
      "integrator": {"max_depth": 4},
      "materials": {"floor": {"type": "diffuse", "albedo": [0.7, 0.7, 0.7]},
        "mirror": {"type": "glossy", "specular": [0.9, 0.9, 0.9], "sigma": 0.05}},
      "shapes": [
        {"type": "bilinear", "material": "floor", "quads": [[[-4, -4, 0], [4, -4, 0], [-4, 4, 0], [4, 4, 0]]]},
        {"type": "bilinear", "material": "mirror", "quads": [[[1, -1, 0.05], [1, 1, 0.05], [1, -1, 1.6], [1, 1, 1.6]]]}],
      "lights": )" << lights << "}";
    return loadScene(path);
  };
  const Scene both = sceneWith(R"([{"type": "environment", "radiance": [2, 2, 2]},
                                   {"type": "point", "position": [-0.5, 0, 1.0], "intensity": [2, 2, 2]}])");
  {
    Renderer r(both, lbtOptions(16));
    ASSERT_NE(beamsOf(r).beams(), nullptr) << beamsOf(r).stats().skipped;
  }
  constexpr int kSeeds = 32;
  RenderOptions pt, ptOnly;
  pt.lod = ptOnly.lod = LodRule::Fixed;
  pt.maxLod = ptOnly.maxLod = 3;
  ptOnly.method.causticPaths = CausticPaths::Only;
  RenderOptions lbt = lbtOptions(16);
  lbt.lod = LodRule::Fixed;
  lbt.maxLod = 3;
  const BlockEstimate all = blockEstimate(both, pt, kSeeds), beams = blockEstimate(both, lbt, kSeeds);
  const BlockEstimate sky = blockEstimate(sceneWith(R"([{"type": "environment", "radiance": [2, 2, 2]}])"),
                                          ptOnly, kSeeds);
  const double seImage = std::hypot(all.se.back(), beams.se.back());
  EXPECT_GT(sky.mean.back(), 4 * seImage + 4 * sky.se.back()) << "the sky's caustic is too faint to test";
  for (size_t b = 0; b < all.mean.size(); ++b)
    EXPECT_LE(std::fabs(beams.mean[b] - all.mean[b]), 4 * std::hypot(all.se[b], beams.se[b]))
        << "block " << b << ": pt " << all.mean[b] << " ± " << all.se[b] << ", lbt " << beams.mean[b] << " ± "
        << beams.se[b];
}

// The roulette on gathers after a path's first diffuse vertex (--later-gathers) keeps the mean.
// The camera looks at the floor beside a mirror whose caustic lands on the ceiling: the floor's
// own gathers find nothing, so the whole caustic arrives through later vertices (ceiling, then
// floor), and a missing 1/q would take three quarters of it away.
TEST(Beams, TheRouletteOnLaterGathersKeepsTheMean) {
  TempFolder tmp;
  const std::string path = tmp.path("later.json");
  std::ofstream(path) << R"({
    "camera": {"position": [3.2, 0, 1.5], "look_at": [3.2, 0.4, 0], "up": [0, 1, 0], "fov": 50},
    "film": {"resolution": [16, 12], "spp": 4},
    "integrator": {"max_depth": 4},
    "materials": {"mirror": {"type": "glossy", "specular": [0.9, 0.9, 0.9], "sigma": 0.02},
      "room": {"type": "diffuse", "albedo": [0.7, 0.7, 0.7]}},
    "shapes": [
      {"type": "bilinear", "material": "mirror", "quads": [[[-1, -1, 0], [1, -1, 0], [-1, 1, 0], [1, 1, 0]]]},
      {"type": "bilinear", "material": "room", "quads": [[[-6, -6, -0.01], [6, -6, -0.01], [-6, 6, -0.01], [6, 6, -0.01]]]},
      {"type": "bilinear", "material": "room", "quads": [[[-6, 6, 2], [6, 6, 2], [-6, -6, 2], [6, -6, 2]]]}],
    "lights": [{"type": "point", "position": [0.13, 0.07, 1], "intensity": [10, 10, 10]}]})";
  const Scene scene = loadScene(path);
  constexpr int kSeeds = 24;
  RenderOptions all = lbtOptions(16), roulette = lbtOptions(16), without;
  all.method.laterGatherProbability = 1;
  roulette.method.laterGatherProbability = 0.25f;
  without.method.causticPaths = CausticPaths::Without;
  for (RenderOptions* o : {&all, &roulette, &without}) o->lod = LodRule::Fixed, o->maxLod = 3;
  const BlockEstimate a = blockEstimate(scene, all, kSeeds), r = blockEstimate(scene, roulette, kSeeds),
                      w = blockEstimate(scene, without, kSeeds);
  const double caustic = a.mean.back() - w.mean.back(), se = std::hypot(a.se.back(), r.se.back());
  EXPECT_GT(0.75 * caustic, 6 * se) << "the later vertices' caustic is too faint to test";
  for (size_t b = 0; b < a.mean.size(); ++b)
    EXPECT_LE(std::fabs(r.mean[b] - a.mean[b]), 4 * std::hypot(a.se[b], r.se[b]))
        << "block " << b << ": every gather " << a.mean[b] << " ± " << a.se[b] << ", roulette " << r.mean[b] << " ± "
        << r.se[b];
  Renderer stats(scene, roulette);
  stats.render();
  EXPECT_GT(stats.stats().shade.gathersSkipped.load(), 0u);
  Renderer byDefault(scene, lbtOptions(16));  // off unless asked
  byDefault.render();
  EXPECT_GT(byDefault.stats().shade.gathers.load(), 0u);
  EXPECT_EQ(byDefault.stats().shade.gathersSkipped.load(), 0u);
}

// glass-caustic.json's light is a rect: lbt now traces beams through its glass.
TEST(Beams, GlassCausticGetsBeamsFromItsAreaLight) {
  Scene scene = shippedScene("scenes/glass-caustic.json", 8, 6, 1);
  RenderOptions o = lbtOptions(8);
  o.method.beams.areaSamples = 1;
  Renderer r(scene, o);
  ASSERT_NE(beamsOf(r).beams(), nullptr) << beamsOf(r).stats().skipped;
  EXPECT_GT(beamsOf(r).stats().trace.reflectedBranches, 0u);
  for (const BeamSegment& s : beamsOf(r).beams()->segments()) EXPECT_TRUE(isFinite(s.power) && maxComponent(s.power) > 0);
}

// As pm, lbt complements the path tracer within max_depth: camera bounces and the beam's
// scatterings together. At max_depth 1 the mirror caustic (ceiling, mirror, light: 2 bounces)
// is no path of the render; at 2 it is.
TEST(Beams, MaxDepthBoundsCameraBouncesAndBeamScatteringsTogether) {
  Scene scene = shippedScene("scenes/lbt-mirror.json", 12, 9, 2);
  RenderOptions without;
  without.method.causticPaths = CausticPaths::Without;
  scene.integrator.maxDepth = 1;
  EXPECT_EQ(renderBeauty(scene, lbtOptions(8), 2), renderBeauty(scene, without, 2));
  scene.integrator.maxDepth = 2;
  EXPECT_NE(renderBeauty(scene, lbtOptions(8), 2), renderBeauty(scene, without, 2));
}

// The gathers run as leaf queries of the next trace() (core/leaf_queries.h) add, bit for bit,
// what the direct call in the shading step added: the same sums, in the same order into each
// path's radiance. On glossy and specular beams, with the Rayes and Embree engines, a ray budget
// of a few paths per batch, and beams in batches under --beam-memory.
TEST(Beams, GathersAsLeafQueriesEqualGathersInTheShadingStepBitForBit) {
  for (const char* file : {"scenes/lbt-ring-glossy.json", "scenes/lbt-discoball.json"}) {
    Scene scene = shippedScene(file, 20, 15, 1);
    const RenderOptions base = lbtOptions(12);
    RenderOptions embree = base, fewPaths = base, beamBatches = base;
    embree.engine = EngineKind::Embree;
    embree.maxLod = 4;
    fewPaths.rayMemoryBytes = 29 * bytesPerPath(scene, base);
    beamBatches.method.beams.memoryBytes = beamsOf(Renderer(scene, base)).stats().bytes / 2;
    for (const RenderOptions& leafQueries : {base, embree, fewPaths, beamBatches}) {
      RenderOptions inShading = leafQueries;
      inShading.method.beams.gathersInShading = true;
      EXPECT_EQ(renderBeauty(scene, leafQueries, 2), renderBeauty(scene, inShading, 2)) << file;
    }
    RenderOptions without;
    without.method.causticPaths = CausticPaths::Without;
    EXPECT_NE(renderBeauty(scene, base, 2), renderBeauty(scene, without, 2)) << file << ": no caustic in view";
  }
}

// The camera-side share of max_depth (camera bounce + light-path vertex ≤ max_depth) beyond the
// first bounce, for lbt and pm: the camera sees only a floor below lbt-mirror's mirror, which
// no beam or photon reaches (the mirror reflects upward); the ceiling's caustic reaches the
// camera after one diffuse bounce, a path of three vertices (floor, ceiling, mirror). It is in
// the image at max_depth 3 and not at 2.
TEST(Beams, MaxDepthCountsTheCameraBouncesBeforeTheGather) {
  const Scene floorScene = parseScene(R"({
      "camera": {"position": [3, 0, 1.5], "look_at": [3, 0, -0.5], "up": [0, 1, 0], "fov": 30},
      "film": {"resolution": [12, 9], "spp": 2},
      "integrator": {"max_depth": 3, "seed": 0},
      "materials": {"mirror": {"type": "glossy", "specular": [0.9, 0.9, 0.9], "sigma": 0.001},
        "white": {"type": "diffuse", "albedo": [0.8, 0.8, 0.8]}},
      "shapes": [
        {"type": "bilinear", "material": "mirror", "quads": [[[-1, -1, 0], [1, -1, 0], [-1, 1, 0], [1, 1, 0]]]},
        {"type": "bilinear", "material": "white", "quads": [[[-4, -4, 2], [4, -4, 2], [-4, 4, 2], [4, 4, 2]]]},
        {"type": "bilinear", "material": "white", "quads": [[[-4, -4, -0.5], [4, -4, -0.5], [-4, 4, -0.5], [4, 4, -0.5]]]}],
      "lights": [{"type": "point", "position": [0, 0, 1], "intensity": [10, 10, 10]}]})",
                                      "floor.json");
  RenderOptions pm;
  pm.method.name = "pm";
  pm.method.photons.photonsPerSample = 2000;
  RenderOptions without;
  without.method.causticPaths = CausticPaths::Without;
  for (const RenderOptions& method : {lbtOptions(8), pm}) {
    Scene s = floorScene;
    s.integrator.maxDepth = 2;
    EXPECT_EQ(renderBeauty(s, method, 2), renderBeauty(s, without, 2)) << method.method.name;
    s.integrator.maxDepth = 3;
    EXPECT_NE(renderBeauty(s, method, 2), renderBeauty(s, without, 2)) << method.method.name;
  }
}

TEST(Beams, ImagesAreOrderIndependentAndBudgetIndependent) {
  Scene scene = shippedScene("scenes/lbt-mirror-glossy.json", 24, 18, 2);
  expectOrderIndependent(scene, 37, lbtOptions(16));
}

// A scene with no specular or glossy surface, and one whose only light is an environment:
// no beams, the stats say why, and the image is the path tracer's bit for bit.
TEST(Beams, ScenesWithoutLitScatterersAreThePathTracerBitForBit) {
  for (const char* file : {"scenes/cornell-box.json", "scenes/materials.json"}) {
    Scene scene = shippedScene(file, 16, 12, 2);
    Renderer r(scene, lbtOptions());
    EXPECT_EQ(beamsOf(r).beams(), nullptr) << file;
    EXPECT_FALSE(beamsOf(r).stats().skipped.empty()) << file;
    EXPECT_EQ(renderBeauty(scene, lbtOptions(), 2), renderBeauty(scene, RenderOptions{}, 2)) << file;
  }
}

TEST(Beams, BadOptionsAreRefusedWithExitCode2AndNoOutput) {
  TempFolder tmp;
  const std::string scene = sourcePath("scenes/lbt-mirror.json");
  const std::string out = tmp.path("o.exr");
  // (A --beam-memory too small for one beam is a resource limit, exit code 3:
  // beam_budget_render_test.cpp.)
  RunResult r;
  for (const char* option : {"--beam-resolution", "--beam-split-depth", "--beam-area-samples", "--beam-lobe-cells",
                             "--later-gathers"}) {
    r = runRayes({"render", scene, "-o", out, "-q", "--method", "lbt", option, "-1"});
    EXPECT_EQ(r.code, 2) << option;
    EXPECT_NE(r.err.find(option), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(out));
  }
  for (const char* q : {"0", "1.5", "nan"}) {
    r = runRayes({"render", scene, "-o", out, "-q", "--method", "lbt", "--later-gathers", q});
    EXPECT_EQ(r.code, 2) << q;
    EXPECT_NE(r.err.find("--later-gathers"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(out));
  }
  // Without their caustic estimate the caustic methods would be the path tracer without caustic paths.
  r = runRayes({"render", scene, "-o", out, "-q", "--method", "lbt", "--caustic-paths", "without"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--caustic-paths"), std::string::npos) << r.err;
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
