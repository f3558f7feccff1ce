// The caustic gather of beam segments (lbt/beam_segment.h, lbt/beam_store.h) against the planar
// mirror's closed form, built without the ray engine: a point light of intensity I at (0, 0, 1)
// above the mirror [-1, 1]² (z = 0, reflectance ρ) is seen from the mirror as its image at
// (0, 0, -1), so every reflected corner ray leaves its mirror point away from the image. On the
// ceiling z = 2: E = ρ·I·cos θ / D² = 3ρI / D³ inside the footprint [-3, 3]², 0 outside; the
// total flux is ρ·I·Ω = ρ·I·2π/3. Then the stiff cases: a focus, past a focus, collinear
// corners, a gather point on a corner ray, grazing receivers, a glossy lobe crossing its
// scatterer's horizon.
#include <gtest/gtest.h>
#include <cmath>
#include <numbers>
#include <vector>
#include "core/error.h"
#include "lbt/beam_seeds.h"
#include "lbt/beam_store.h"
#include "toplevel/toplevel_bvh.h"

namespace rayes {
namespace {
constexpr double kPi = std::numbers::pi;
constexpr float kRho = 0.9f, kI = 10.0f;
const Vec3 kImage{0, 0, -1}, kLight{0, 0, 1};

// The mirror's beams: an n×n grid of cells on the mirror, two triangles each; power ρ·I·Ω.
std::vector<BeamSegment> mirrorBeams(int n, float sigma) {
  std::vector<BeamSegment> out;
  auto corner = [&](int i, int j) { return Vec3{-1 + 2.0f * i / n, -1 + 2.0f * j / n, 0}; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const Vec3 c[4] = {corner(i, j), corner(i + 1, j), corner(i + 1, j + 1), corner(i, j + 1)};
      for (const auto& tri : {std::array<int, 3>{0, 1, 2}, std::array<int, 3>{0, 2, 3}}) {
        BeamSegment s;
        for (int k = 0; k < 3; ++k) {
          s.o[k] = c[tri[k]];
          s.d[k] = normalize(s.o[k] - kImage);
          s.t[k] = 2 / s.d[k].z;  // to the ceiling
        }
        const float omega = float(sphericalTriangleArea(normalize(s.o[0] - kLight), normalize(s.o[1] - kLight),
                                                        normalize(s.o[2] - kLight)));
        s.power = Rgb{1, 1, 1} * (kRho * kI * omega);
        s.sigma = sigma;
        out.push_back(s);
      }
    }
  return out;
}

// The ceiling [-h, h]² at z = 2 as m×m leaves of a top level, so gathers are per leaf.
struct Ceiling {
  std::vector<Box3> boxes;
  TopLevelBvh top;
  int m;
  float half;
  Ceiling(int leaves, float h) : m(leaves), half(h) {
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) {
        const float x0 = -h + 2 * h * i / m, y0 = -h + 2 * h * j / m;
        boxes.push_back({{x0, y0, 2}, {x0 + 2 * h / m, y0 + 2 * h / m, 2}});
      }
    top.build(boxes);
  }
  uint32_t leafAt(float x, float y) const {
    const int i = std::clamp(int((x + half) / (2 * half) * m), 0, m - 1);
    const int j = std::clamp(int((y + half) / (2 * half) * m), 0, m - 1);
    return uint32_t(j * m + i);
  }
};

double irradiance(const BeamStore& store, const Ceiling& c, float x, float y) {
  double e = 0;
  store.gather(c.leafAt(x, y), {x, y, 2}, {0, 0, -1}, [&](Vec3, Rgb irradiance) { e += irradiance.x; });
  return e;
}

double exactMirror(double x, double y) {
  if (std::fabs(x) >= 3 || std::fabs(y) >= 3) return 0;
  const double d = std::sqrt(x * x + y * y + 9);
  return 3 * kRho * kI / (d * d * d);
}

TEST(BeamGather, PlanarMirrorIrradianceInsideTheFootprintAndZeroOutside) {
  const Ceiling ceiling(16, 4);
  const BeamStore store(mirrorBeams(32, 0), ceiling.top, ceiling.top.leafBoxes(), size_t(1) << 30);
  // Each beam's flux triangle is exact for a point source; what differs from the closed form
  // is that Ω/A⊥ and the cosine are taken at one blended direction per triangle: a relative
  // error of the order of the cell's angular size squared, (2/32)² / 3 ≈ 1.3e-3.
  // Generic points: a point exactly on a flux triangle's edge or corner (such as the grid
  // lines x = 0 or y = ±2.5 here) may be counted by none or all of the specular beams that
  // meet there (measure zero in a render; glossy beams are continuous there, tested below).
  for (float x : {0.013f, 0.37f, -1.31f, 2.2f, 2.9f})
    for (float y : {0.007f, 0.11f, -2.47f, 1.7f}) {
      const double e = irradiance(store, ceiling, x, y);
      EXPECT_NEAR(e, exactMirror(x, y), 1.3e-3 * exactMirror(x, y)) << x << ", " << y;
    }
  for (float x : {3.05f, -3.5f, 3.9f}) EXPECT_EQ(irradiance(store, ceiling, x, 0.5f), 0.0) << x;
  EXPECT_EQ(irradiance(store, ceiling, 0.5f, -3.2f), 0.0);
}

// ∫E dA by the midpoint rule on a grid whose lines include the footprint's edges, so only the
// smooth part is integrated (error O(h²), far below 1 %).
double totalFlux(const BeamStore& store, const Ceiling& c, float half, int n) {
  const double h = 2.0 * half / n;
  double sum = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) sum += irradiance(store, c, float(-half + (i + 0.5) * h), float(-half + (j + 0.5) * h));
  return sum * h * h;
}

TEST(BeamGather, TotalFluxOnALargeReceiverIsRhoPhiForSpecularAndGlossyBeams) {
  const double expected = kRho * kI * 2 * kPi / 3;
  const Ceiling ceiling(16, 4.5f);
  const BeamStore specular(mirrorBeams(16, 0), ceiling.top, ceiling.top.leafBoxes(), size_t(1) << 30);
  EXPECT_NEAR(totalFlux(specular, ceiling, 3.0f, 150), expected, 0.01 * expected);
  const BeamStore glossy(mirrorBeams(16, 0.05f), ceiling.top, ceiling.top.leafBoxes(), size_t(1) << 30);
  EXPECT_NEAR(totalFlux(glossy, ceiling, 4.5f, 120), expected, 0.01 * expected);
}

TEST(BeamGather, GlossyTendsToSpecularAwayFromEdges) {
  const Ceiling ceiling(8, 4);
  const BeamStore specular(mirrorBeams(8, 0), ceiling.top, ceiling.top.leafBoxes(), size_t(1) << 30);
  const BeamStore glossy(mirrorBeams(8, 1e-5f), ceiling.top, ceiling.top.leafBoxes(), size_t(1) << 30);
  // Points well inside flux triangles (cells of the 8×8 grid are 0.75 wide on the ceiling):
  // the lobe's mass outside is below Q(100): nothing.
  for (float x : {0.2f, -1.1f, 1.9f})
    for (float y : {0.1f, -0.9f, 2.3f}) {
      const double s = irradiance(specular, ceiling, x, y), g = irradiance(glossy, ceiling, x, y);
      EXPECT_NEAR(g, s, 1e-5 * s) << x << ", " << y;
    }
}

TEST(BeamGather, NoJumpAcrossAGlossyFluxTriangleEdge) {
  const Ceiling ceiling(8, 4);
  const BeamStore glossy(mirrorBeams(8, 0.02f), ceiling.top, ceiling.top.leafBoxes(), size_t(1) << 30);
  // The cell edge x = 0 (mirror x = 0 maps to ceiling x = 0): E on both sides agrees to first
  // order in the step (E is smooth there: relative slope ~ 1 per unit length).
  const double left = irradiance(glossy, ceiling, -1e-4f, 0.4f), right = irradiance(glossy, ceiling, 1e-4f, 0.4f);
  EXPECT_NEAR(left, right, 1e-3 * right);
  // Exactly on the edge and on a corner shared by six flux triangles: the same value again
  // (each triangle contributes its own lobe mass, no double counting).
  EXPECT_NEAR(irradiance(glossy, ceiling, 0, 0.4f), right, 1e-3 * right);
  EXPECT_NEAR(irradiance(glossy, ceiling, 0, 0), irradiance(glossy, ceiling, 1e-4f, 1e-4f), 1e-3 * right);
}

// A beam focused at F = (0, 0, 2): corners on a circle of radius 0.1 at z = 0, aimed at F.
BeamSegment focusedBeam(float sigma, Vec3 focus = {0, 0, 2}) {
  BeamSegment s;
  for (int k = 0; k < 3; ++k) {
    const double a = 2 * kPi * k / 3;
    s.o[k] = {float(0.1 * std::cos(a)), float(0.1 * std::sin(a)), 0};
    s.d[k] = normalize(focus - s.o[k]);
    s.t[k] = 10;
  }
  s.power = {1, 1, 1};
  s.sigma = sigma;
  return s;
}

TEST(BeamGather, FocusIsFiniteAndGlossyTendsToItsLimit) {
  Vec3 psi;
  const Vec3 up{0, 0, 1};
  const BeamSegment specular = focusedBeam(0);
  const Rgb atFocus = beamIrradiance(specular, {0, 0, 2}, up, psi);
  EXPECT_TRUE(isFinite(atFocus));
  EXPECT_EQ(atFocus.x, 0.0f);  // unbounded: the documented guard gives nothing
  const float sigma = 0.01f;
  const BeamSegment glossy = focusedBeam(sigma);
  const double r = length(Vec3{0, 0, 2} - glossy.o[0]);
  const double limit = 1.0 / (2 * kPi * sigma * sigma * r * r);
  const Rgb e = beamIrradiance(glossy, {0, 0, 2}, up, psi);
  EXPECT_TRUE(isFinite(e));
  EXPECT_NEAR(e.x, limit, 1e-3 * limit);
  // Approaching the focus along the axis, the value goes continuously to the limit: the flux
  // triangle has shrunk to 1e-4 of the lobe's width there.
  const Rgb near = beamIrradiance(glossy, {0, 0, 2 - 1e-6f}, up, psi);
  EXPECT_NEAR(near.x, limit, 2e-3 * limit);
}

// The spike of lbt-ring-glossy (bench/history/2026-11.md): a curved reflector's beam nearly
// focuses, its corner rays leaving the reflector at different distances from the focus. Off the
// focus by about the lobe's width, the flux triangle is tiny (A⊥ ~ ε²) while x sees it at a large
// angle: P/A⊥ must still stay below the lobe's peak density over r² (E ≤ Φ|cos|/(2πσ²r²), r the
// nearest corner's distance), as it did not when each corner's angle was measured from its own
// origin (the angular triangle then shrinks only like δ·ε: E was 2-800x the bound here).
TEST(BeamGather, NearAGlossyFocusOfACurvedReflectorEStaysBelowThePeakBound) {
  Vec3 psi;
  const Vec3 up{0, 0, 1}, focus{0, 0, 2};
  const float sigma = 0.05f;
  const float heights[3] = {0.0f, 0.3f, -0.2f};
  for (double eps : {1e-3, 1e-4, 1e-5}) {
    BeamSegment s;
    for (int k = 0; k < 3; ++k) {
      const double a = 2 * kPi * k / 3;
      s.o[k] = {float(0.1 * std::cos(a)), float(0.1 * std::sin(a)), heights[k]};
      const Vec3 aim = focus + Vec3{float(eps * std::cos(a + 1)), float(eps * std::sin(a + 1)), 0};
      s.d[k] = normalize(aim - s.o[k]);
      s.t[k] = 10;
    }
    s.power = {1, 1, 1};
    s.sigma = sigma;
    for (double delta : {0.0, 0.3 * sigma, 1.0 * sigma, 2.0 * sigma, 3.0 * sigma}) {
      const Vec3 x = focus + Vec3{float(delta), 0, 0};
      double rMin = 1e30;
      for (int k = 0; k < 3; ++k) rMin = std::min(rMin, double(length(x - s.o[k])));
      const double bound = 1.0 / (2 * kPi * sigma * sigma * rMin * rMin);
      const Rgb e = beamIrradiance(s, x, up, psi);
      EXPECT_TRUE(isFinite(e));
      EXPECT_LE(e.x, bound * (1 + 1e-3)) << "eps " << eps << ", delta " << delta;
    }
  }
}

TEST(BeamGather, PastTheFocusTheInvertedTriangleGathersLikeItsMirrorImage) {
  Vec3 psi;
  const Vec3 up{0, 0, 1};
  // At z = 4 the beam (focused at z = 2) has its inverted cross-section of the same size as at
  // z = 0: E there equals E at a point just as far before the focus, by symmetry up to the
  // distance to the corners (5 % further at z = 4: compare with 1/r² scaling removed).
  const BeamSegment s = focusedBeam(0);
  const Rgb after = beamIrradiance(s, {0, 0, 3}, up, psi), before = beamIrradiance(s, {0, 0, 1}, up, psi);
  EXPECT_TRUE(isFinite(after));
  EXPECT_GT(after.x, 0);
  EXPECT_NEAR(after.x, before.x, 1e-3 * before.x);  // |A⊥| is the same at ±1 from the focus
  const BeamSegment g = focusedBeam(0.01f);
  const Rgb glossyAfter = beamIrradiance(g, {0, 0, 3}, up, psi);
  EXPECT_TRUE(isFinite(glossyAfter));
  EXPECT_GT(glossyAfter.x, 0);
}

TEST(BeamGather, CollinearCornersOnCornerRaysAndGrazingReceiversStayFinite) {
  Vec3 psi;
  BeamSegment line;
  for (int k = 0; k < 3; ++k) {
    line.o[k] = {0.1f * k, 0, 0};
    line.d[k] = {0, 0, 1};
    line.t[k] = 5;
  }
  line.power = {1, 1, 1};
  for (float sigma : {0.0f, 0.02f}) {
    line.sigma = sigma;
    const Rgb e = beamIrradiance(line, {0.1f, 0, 1}, {0, 0, 1}, psi);
    EXPECT_TRUE(isFinite(e)) << sigma;
    EXPECT_GE(e.x, 0.0f);
  }
  // On a corner ray (φ = 0 for that corner) and on an edge.
  BeamSegment tri = focusedBeam(0.02f, {0, 0, 50});
  const Vec3 onCorner = tri.o[0] + tri.d[0] * 1.5f;
  const Rgb c = beamIrradiance(tri, onCorner, {0, 0, 1}, psi);
  EXPECT_TRUE(isFinite(c));
  EXPECT_GT(c.x, 0);
  const Vec3 onEdge = (tri.o[0] + tri.o[1]) * 0.5f + Vec3{0, 0, 1};
  EXPECT_TRUE(isFinite(beamIrradiance(tri, onEdge, {0, 0, 1}, psi)));
  // Grazing: the receiver's normal perpendicular to the light: E = 0 exactly, never NaN.
  const Rgb graze = beamIrradiance(tri, {0, 0, 1}, {1, 0, 0}, psi);
  EXPECT_TRUE(isFinite(graze));
  EXPECT_NEAR(graze.x, 0.0f, 1e-3f * beamIrradiance(tri, {0, 0, 1}, {0, 0, 1}, psi).x);
}

// Grazing light on a flat glossy mirror (origins on z = 0, every corner ray along the mirror
// direction d = (cos α, 0, sin α), α = 0.03, σ = 0.05: the lobe crosses the horizon) and a wall
// at x = 10 receiving it. Below the mirror's plane nothing arrives (no reflection goes there; the
// path tracer's lobe is 0 there too); above it the whole lobe does, so the flux on the wall is
// ρΦ times the lobe's mass above the horizon, Φ_N(α/σ) for small angles (an error of order
// α² + σ² = 3.4e-3 relative, and O(h²) from the midpoint rule: within 1 %).
TEST(BeamGather, AGlossyLobeCrossingItsScatterersHorizonSendsNothingBelowIt) {
  const float alpha = 0.03f, sigma = 0.05f, wall = 10;
  const Vec3 d{std::cos(alpha), 0, std::sin(alpha)};
  std::vector<BeamSegment> beams;
  const int n = 4;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      auto corner = [&](int a, int b) { return Vec3{-0.5f + float(i + a) / n, -0.5f + float(j + b) / n, 0}; };
      const Vec3 c[4] = {corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)};
      for (const auto& tri : {std::array<int, 3>{0, 1, 2}, std::array<int, 3>{0, 2, 3}}) {
        BeamSegment s;
        for (int k = 0; k < 3; ++k) {
          s.o[k] = c[tri[k]];
          s.d[k] = d;
          s.t[k] = (wall - s.o[k].x) / d.x;  // to the wall
        }
        s.power = Rgb{1, 1, 1} * (1.0f / (2 * n * n));  // 1 W in all
        s.sigma = sigma;
        beams.push_back(s);
      }
    }
  auto irradianceAt = [&](float y, float z) {
    double e = 0;
    Vec3 psi;
    for (const BeamSegment& s : beams) e += beamIrradiance(s, {wall, y, z}, {-1, 0, 0}, psi).x;
    return e;
  };
  // A point 1σ below the mirror direction but under the horizon gets nothing; one above it does.
  EXPECT_EQ(irradianceAt(0, -0.2f), 0.0);
  EXPECT_EQ(irradianceAt(0.3f, -1e-3f), 0.0);
  EXPECT_GT(irradianceAt(0, 0.05f), 0.0);
  // ∫E dA over the wall, y in [-3, 3], z in [-2.5, 3.5] (the lobe reaches 4σ·10 = 2 around the
  // beam's centre z ≈ 0.3).
  const double h = 0.05;
  double flux = 0;
  for (double y = -3 + h / 2; y < 3; y += h)
    for (double z = -2.5 + h / 2; z < 3.5; z += h) flux += irradianceAt(float(y), float(z)) * h * h;
  const double above = 0.5 * std::erfc(-alpha / sigma / std::numbers::sqrt2);
  EXPECT_NEAR(flux, above, 0.01 * above);
}

// The gather asks a caller's filter (the path tracer's depth rule) before any work on a segment,
// and bins the segments by their reach: it must sum exactly what the full gather sums, the
// irradiance of every segment in segment order where x lies in the segment's reach and outside
// what its envelope excludes (a lobe mass below Q(kLobeReach): beam_envelope_test.cpp). Checked
// against that sum over all segments (no bins) at random points, on the footprint's edges, on
// corner rays' ends and at the focus of a converging beam, specular and glossy.
TEST(BeamStore, GatherSumsExactlyTheSegmentsInReachWithTheFilterAskedFirst) {
  for (const float sigma : {0.0f, 0.05f}) {
    std::vector<BeamSegment> beams = mirrorBeams(6, sigma);
    // A beam converging to a focus at (0.5, 0.5, 2) on the ceiling, and one scattered twice.
    BeamSegment focus = beams.front();
    for (int k = 0; k < 3; ++k) {
      focus.d[k] = normalize(Vec3{0.5f, 0.5f, 2} - focus.o[k]);
      focus.t[k] = length(Vec3{0.5f, 0.5f, 2} - focus.o[k]);
    }
    beams.push_back(focus);
    beams[3].scatterings = 2;
    const Ceiling ceiling(4, 4);
    const BeamStore store(beams, ceiling.top, ceiling.top.leafBoxes(), size_t(1) << 24);
    std::vector<Vec3> points;
    uint32_t state = 12345;
    auto uniform = [&] { return (state = state * 1664525u + 1013904223u) / 4294967296.0f; };
    for (int i = 0; i < 2000; ++i) points.push_back({-4 + 8 * uniform(), -4 + 8 * uniform(), 2});
    for (float u : {-3.0f, -1.0f, 0.0f, 1.0f, 3.0f}) points.push_back({3, u, 2}), points.push_back({u, -3, 2});
    for (const BeamSegment& s : beams)
      for (int k = 0; k < 3; ++k) points.push_back(s.o[k] + s.d[k] * s.t[k]);
    points.push_back({0.5f, 0.5f, 2});
    const auto notTwice = [](const BeamSegment& s) { return s.scatterings < 2; };
    for (const Vec3 x : points) {
      const uint32_t leaf = ceiling.leafAt(x.x, x.y);
      const Box3& box = ceiling.boxes[leaf];
      const Vec3 inside = vmin(vmax(x, box.lo), box.hi);
      Rgb full{}, fullFiltered{};
      for (const BeamSegment& s : beams) {
        Vec3 psi;
        const Rgb e = beamIrradiance(s, x, {0, 0, -1}, psi);
        if (!(maxComponent(e) > 0 && BeamStore::reaches(s, inside)) || beamEnvelope(s).excludes(x)) continue;
        full += e;
        if (notTwice(s)) fullFiltered += e;
      }
      Rgb gathered{}, gatheredFiltered{};
      store.gather(leaf, x, {0, 0, -1}, [&](Vec3, Rgb e) { gathered += e; });
      store.gather(leaf, x, {0, 0, -1}, [&](Vec3, Rgb e) { gatheredFiltered += e; }, notTwice);
      EXPECT_EQ(gathered.x, full.x) << "sigma " << sigma << " at " << x.x << ", " << x.y;
      EXPECT_EQ(gatheredFiltered.x, fullFiltered.x) << "sigma " << sigma << " at " << x.x << ", " << x.y;
    }
  }
}

TEST(BeamStore, RefusesABudgetTooSmallForOneBeam) {
  const Ceiling ceiling(4, 4);
  EXPECT_THROW(BeamStore(mirrorBeams(2, 0), ceiling.top, ceiling.top.leafBoxes(), 64), InputError);
  EXPECT_NO_THROW(BeamStore(mirrorBeams(2, 0), ceiling.top, ceiling.top.leafBoxes(), size_t(1) << 20));
}

}  // namespace
}  // namespace rayes
