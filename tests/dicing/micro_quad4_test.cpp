// quadsMayHit4, the four-quad edge-sign filter in front of intersectMicroQuad: it keeps a quad
// exactly when some triangle of it has edge values that are not strictly of both signs (the
// rule written out below from micro_quad.h's contract, with Vec3's indexing rather than the
// filter's code), so it never drops a quad the watertight test accepts -- also for rays aimed
// at shared vertices and edges, where edge values round to 0, for degenerate quads, and far
// from the origin.
#include <gtest/gtest.h>
#include <cmath>
#include <limits>
#include <random>
#include "dicing/micro_quad.h"
#include "dicing/micro_quad4.h"

namespace rayes {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// A triangle's edge values in the ray's sheared frame, as micro_quad.h defines them.
bool edgesMayHit(const WatertightRay& ray, Vec3 a, Vec3 b, Vec3 c) {
  auto px = [&](Vec3 p) { return (p[ray.kx] - ray.ox) - ray.sx * (p[ray.kz] - ray.oz); };
  auto py = [&](Vec3 p) { return (p[ray.ky] - ray.oy) - ray.sy * (p[ray.kz] - ray.oz); };
  auto edge = [&](Vec3 p, Vec3 q) { return px(q) * py(p) - py(q) * px(p); };
  const float u = edge(b, c), v = edge(c, a), w = edge(a, b);
  if (u == 0.0f || v == 0.0f || w == 0.0f) return true;
  return !((u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f));
}

struct Quads {
  Vec3 p00[4], p10[4], p01[4], p11[4];
};

// The 4 sibling quads of a 3 x 3 vertex patch (row by row), in Z order as quadsMayHit4 numbers
// them.
Quads siblings(const Vec3 v[9]) {
  Quads q;
  for (int c = 0; c < 4; ++c) {
    const int i = 3 * (c >> 1) + (c & 1);
    q.p00[c] = v[i];
    q.p10[c] = v[i + 1];
    q.p01[c] = v[i + 3];
    q.p11[c] = v[i + 4];
  }
  return q;
}

struct Tally {
  long rays = 0, kept = 0, accepted = 0;
};

void check(const Vec3 v[9], Vec3 org, Vec3 dir, Tally& tally) {
  WatertightRay ray;
  if (!makeWatertightRay(org, dir, ray)) return;
  const Quads q = siblings(v);
  const int bits = quadsMayHit4(ray, v, 1, 3);
  ++tally.rays;
  for (int c = 0; c < 4; ++c) {
    const bool rule = edgesMayHit(ray, q.p00[c], q.p10[c], q.p11[c]) || edgesMayHit(ray, q.p00[c], q.p11[c], q.p01[c]);
    ASSERT_EQ(((bits >> c) & 1) != 0, rule) << "quad " << c;
    MicroQuadHit h;
    const bool hit = intersectMicroQuad(ray, q.p00[c], q.p10[c], q.p01[c], q.p11[c], -kInf, kInf, h);
    if (hit) {
      ASSERT_TRUE((bits >> c) & 1) << "the filter dropped a quad the watertight test accepts, quad " << c;
      ++tally.accepted;
    }
    tally.kept += (bits >> c) & 1;
  }
}

// A 3 x 3 vertex patch of a wavy surface at `scale`, moved by `offset`.
void wavyPatch(std::mt19937& rng, float scale, Vec3 offset, Vec3 v[9]) {
  std::uniform_real_distribution<float> jitter(-0.3f, 0.3f);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i)
      v[3 * j + i] = Vec3{(float(i) + jitter(rng)) * scale, (float(j) + jitter(rng)) * scale, jitter(rng) * scale} + offset;
}

void randomAndAimedRays(std::mt19937& rng, const Vec3 v[9], float scale, Tally& tally) {
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), lambda(0.0f, 1.0f);
  const Vec3 centre = v[4];
  for (int n = 0; n < 40; ++n) {
    const Vec3 org = centre + Vec3{unit(rng), unit(rng), unit(rng) + 2.0f} * (4.0f * scale);
    // At every vertex, and at points on the shared edges and diagonals: edge values near or at 0.
    const int a = int(rng() % 9), b = int(rng() % 9);
    const float l = lambda(rng);
    const Vec3 target[3] = {v[a], v[a] * (1.0f - l) + v[b] * l, centre + Vec3{unit(rng), unit(rng), 0.0f} * scale};
    for (const Vec3& t : target) {
      check(v, org, t - org, tally);
      if (::testing::Test::HasFatalFailure()) return;
    }
  }
}

TEST(QuadsMayHit4, KeepsExactlyTheQuadsWhoseEdgeSignsAllowAHitAtEveryScale) {
  std::mt19937 rng(7);
  Tally tally;
  const struct {
    float scale;
    Vec3 offset;
  } cases[] = {{1.0f, {0, 0, 0}}, {1e-3f, {0, 0, 0}}, {1e4f, {0, 0, 0}}, {1.0f, {1e6f, -1e6f, 5e5f}}, {1e-2f, {300, 45, -120}}};
  for (const auto& c : cases)
    for (int p = 0; p < 200; ++p) {
      Vec3 v[9];
      wavyPatch(rng, c.scale, c.offset, v);
      randomAndAimedRays(rng, v, c.scale, tally);
      if (HasFatalFailure()) return;
    }
  // The rays exercise both outcomes: quads kept and dropped, and hits among the kept ones.
  EXPECT_GT(tally.accepted, 0);
  EXPECT_GT(tally.kept, tally.accepted);
  EXPECT_LT(tally.kept, 4 * tally.rays);
}

TEST(QuadsMayHit4, KeepsDegenerateQuadsAsTheWatertightTestDoes) {
  // Collinear corners (zero-area slivers), a pole (coincident corners) and a flat row: the
  // filter may keep what the full test then rejects, never the reverse.
  std::mt19937 rng(11);
  const Vec3 flat[9] = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}, {0, 2, 0}, {1, 2, 0}, {2, 2, 0}};
  Vec3 pole[9], sliver[9];
  for (int i = 0; i < 9; ++i) {
    pole[i] = i < 3 ? Vec3{1, 0, 0} : flat[i];
    sliver[i] = Vec3{flat[i].x, flat[i].y * 1e-7f, 0};
  }
  Tally tally;
  for (const Vec3* v : {flat, static_cast<const Vec3*>(pole), static_cast<const Vec3*>(sliver)}) {
    randomAndAimedRays(rng, v, 1.0f, tally);
    if (HasFatalFailure()) return;
    // Axis-aligned rays straight down onto every vertex: the edge values through it are 0.
    for (int i = 0; i < 9; ++i) {
      check(v, v[i] + Vec3{0, 0, 3}, Vec3{0, 0, -1}, tally);
      check(v, v[i] + Vec3{0.25f, 0.5f, 3}, Vec3{-0.25f, -0.5f, -3}, tally);
      if (HasFatalFailure()) return;
    }
  }
  EXPECT_GT(tally.accepted, 0);
}

}  // namespace
}  // namespace rayes
