// Watertightness: rays aimed exactly at shared edges and vertices of diced grids -- inside one
// grid, and across the seam of two teapot patches diced into separate buffers, at several
// scales and far from the origin -- never slip through (docs/design.md, "Precision").
//
// Sub-leaves (geometry/sub_patch.h): rays aimed at the edges and corners that sub-leaves of a
// curved displaced patch share, each sub-leaf in its own buffer, are caught the same way.
//
// A ray counts as caught when, following it through its successive hits, it hits one of the
// micro-quads around the aimed point; a hit elsewhere in front (the patch folding over) is
// skipped by restarting after it. So a tunnelling ray is found even if it hits something else
// farther on.
//
// Which rays must be caught: the aimed point P is a rounded lerp of two vertices and the ray
// passes near, not exactly through, it. Over that offset delta (measured in double) a ray
// crossing the surface at an angle with sine s moves its crossing by delta / s. We only aim
// rays that are transversal to every triangle around P with s >= 2 delta / r (r = the
// smallest altitude of those triangles), so the crossing provably stays among them; and
// s >= 2^-13 so no ray merely touches the surface. Grazing rays are sampled down to that bound.
// Rays failing it are resampled; the few aims where no direction can qualify are skipped and
// counted (the test asserts they are rare).
#include <gtest/gtest.h>
#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>
#include <tuple>
#include "geometry/bezier_patch.h"
#include "geometry/displaced_patch.h"
#include "geometry/sub_patch.h"
#include "dicing/dice_buffer.h"
#include "support/patch_test_util.h"

namespace rayes {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

struct StarVertex {
  int buffer, i, j;
};

struct Triangle {
  Vec3 a, b, c;
};

// An aimed point with the grid vertices whose surrounding quads must catch the ray.
struct Aim {
  Vec3 p, va, vb;  // p = lerp(va, vb, lambda)
  std::vector<StarVertex> star;
};

struct Counts {
  long rays = 0, misses = 0, skipped = 0, grazing = 0;
};

double dist(Vec3 a, Vec3 b) {
  const double x = double(a.x) - b.x, y = double(a.y) - b.y, z = double(a.z) - b.z;
  return std::sqrt(x * x + y * y + z * z);
}

// Distance in double from p to the segment a-b.
double distToSegment(Vec3 p, Vec3 a, Vec3 b) {
  const double ab[3] = {double(b.x) - a.x, double(b.y) - a.y, double(b.z) - a.z};
  const double ap[3] = {double(p.x) - a.x, double(p.y) - a.y, double(p.z) - a.z};
  const double l2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
  double t = l2 > 0 ? (ab[0] * ap[0] + ab[1] * ap[1] + ab[2] * ap[2]) / l2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  const double d[3] = {ap[0] - t * ab[0], ap[1] - t * ab[1], ap[2] - t * ab[2]};
  return std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

struct StarQuad {
  int buffer, qx, qy;
  bool operator==(const StarQuad&) const = default;
};

class Harness {
 public:
  Harness(std::vector<const DiceBuffer*> buffers, std::vector<bool> flip, int level)
      : buffers_(std::move(buffers)), flip_(std::move(flip)), level_(level) {
    // Positions that occur at more than one grid vertex (poles; grids quantized far from the
    // origin): the surface around such a point includes the quads of every copy.
    for (const DiceBuffer* b : buffers_) {
      std::vector<Vec3> all, dup;
      for (int j = 0; j < b->resolution(); ++j)
        for (int i = 0; i < b->resolution(); ++i) all.push_back(b->position(i, j));
      auto less = [](Vec3 a, Vec3 c) { return std::tie(a.x, a.y, a.z) < std::tie(c.x, c.y, c.z); };
      std::sort(all.begin(), all.end(), less);
      for (size_t k = 1; k < all.size(); ++k)
        if (all[k] == all[k - 1] && (dup.empty() || !(dup.back() == all[k]))) dup.push_back(all[k]);
      duplicated_.push_back(dup);
    }
  }

  // The buffers hold sub-leaves of one parent split `depth` times, buffer k the sub-leaf at
  // places[k]: their hits are numbered on the parent's grid (DiceBuffer, "Sub-leaves").
  void setSubLeaves(int depth, std::vector<std::array<uint32_t, 2>> places) {
    depth_ = depth;
    places_ = std::move(places);
  }

  void shoot(test::Random& rng, const Aim& aim, float distance, Counts& counts) {
    collectStar(aim);
    // Unit normals and the smallest altitude of the non-degenerate triangles around P.
    normals_.clear();
    double r = std::numeric_limits<double>::infinity();
    for (const StarQuad& q : star_)
      for (const Triangle& t : triangles(q)) {
        const Vec3 e1 = t.b - t.a, e2 = t.c - t.a;
        const double x = double(e1.y) * e2.z - double(e1.z) * e2.y, y = double(e1.z) * e2.x - double(e1.x) * e2.z,
                     z = double(e1.x) * e2.y - double(e1.y) * e2.x;
        const double twiceArea = std::sqrt(x * x + y * y + z * z);
        if (!(twiceArea > 0)) continue;
        const double longest = std::max({dist(t.a, t.b), dist(t.b, t.c), dist(t.c, t.a)});
        r = std::min(r, twiceArea / longest);
        const double s = flip_[q.buffer] ? -1.0 : 1.0;
        normals_.push_back({float(s * x / twiceArea), float(s * y / twiceArea), float(s * z / twiceArea)});
      }
    Vec3 mean{0, 0, 0};
    for (Vec3 n : normals_) mean += n;
    mean = normalize(mean);
    const double offEdge = distToSegment(aim.p, aim.va, aim.vb);
    const bool grazing = rng.below(4) == 0;
    // The last attempt is along the mean normal, the most transversal direction there is
    // where random ones failed (a patch curving strongly around P), so an aim is only skipped
    // when the triangles around P face no common side at all.
    for (int attempt = 0; attempt <= 64; ++attempt) {
      Vec3 w = attempt == 64 ? mean : rng.unitVector();
      if (grazing && attempt < 64) {  // close to the tangent plane, down to the transversality bound
        const Vec3 t = normalize(cross(mean, w));
        const float a = std::ldexp(1.0f, -rng.below(13)) * rng.uniform(0.5f, 1.0f);
        w = t * std::cos(a) + mean * (std::sin(a) * (rng.below(2) ? 1.0f : -1.0f));
      }
      const Vec3 org = aim.p + w * distance;
      const Vec3 dir = aim.p - org;
      const double delta = offEdge + std::sqrt(std::pow(double(org.x) + dir.x - aim.p.x, 2) +
                                               std::pow(double(org.y) + dir.y - aim.p.y, 2) +
                                               std::pow(double(org.z) + dir.z - aim.p.z, 2));
      const double sMin = std::max(2 * delta / r, std::ldexp(1.0, -13));
      if (sMin > 0.9) break;
      const Vec3 d = normalize(dir);
      bool pos = true, neg = true;
      for (Vec3 n : normals_) {
        const double s = dot(d, n);
        pos = pos && s >= sMin;
        neg = neg && s <= -sMin;
      }
      if (!pos && !neg) continue;
      ++counts.rays;
      counts.grazing += grazing;
      if (!caught(org, dir)) {
        ++counts.misses;
        ADD_FAILURE_AT(__FILE__, __LINE__) << "miss: org " << org.x << " " << org.y << " " << org.z << " dir "
                                           << dir.x << " " << dir.y << " " << dir.z;
      }
      return;
    }
    ++counts.skipped;
  }

 private:
  // The quads around the aimed segment va-vb: by grid index, plus, where va or vb is a
  // duplicated position, every quad with a corner there.
  void collectStar(const Aim& aim) {
    star_.clear();
    for (const StarVertex& sv : aim.star) {
      const int n = 1 << buffers_[sv.buffer]->level();
      for (int qy = sv.j - 1; qy <= sv.j; ++qy)
        for (int qx = sv.i - 1; qx <= sv.i; ++qx)
          if (qx >= 0 && qy >= 0 && qx < n && qy < n) addStar({sv.buffer, qx, qy});
    }
    for (int k = 0; k < int(buffers_.size()); ++k) {
      const auto& dup = duplicated_[k];
      const bool any = std::find(dup.begin(), dup.end(), aim.va) != dup.end() ||
                       std::find(dup.begin(), dup.end(), aim.vb) != dup.end();
      if (!any) continue;
      const DiceBuffer& b = *buffers_[k];
      const int n = 1 << b.level();
      for (int qy = 0; qy < n; ++qy)
        for (int qx = 0; qx < n; ++qx)
          for (int c = 0; c < 4; ++c) {
            const Vec3 corner = b.position(qx + (c & 1), qy + (c >> 1));
            if (corner == aim.va || corner == aim.vb) addStar({k, qx, qy});
          }
    }
  }

  void addStar(StarQuad q) {
    if (std::find(star_.begin(), star_.end(), q) == star_.end()) star_.push_back(q);
  }

  std::array<Triangle, 2> triangles(const StarQuad& q) const {
    const DiceBuffer& b = *buffers_[q.buffer];
    const Vec3 p00 = b.position(q.qx, q.qy), p10 = b.position(q.qx + 1, q.qy), p01 = b.position(q.qx, q.qy + 1),
               p11 = b.position(q.qx + 1, q.qy + 1);
    return {Triangle{p00, p10, p11}, Triangle{p00, p11, p01}};
  }

  bool caught(Vec3 org, Vec3 dir) const {
    float tmin = 0;
    for (int crossing = 0; crossing < 64; ++crossing) {
      GridHit best;
      int bestBuffer = -1;
      for (int k = 0; k < int(buffers_.size()); ++k) {
        GridHit h;
        if (buffers_[k]->intersect(org, dir, tmin, kInf, level_, h) && (bestBuffer < 0 || h.t < best.t)) {
          best = h;
          bestBuffer = k;
        }
      }
      if (bestBuffer < 0) return false;
      const int n = 1 << level_;
      StarQuad q{bestBuffer, int(best.quad) % n, int(best.quad) / n};
      if (depth_ > 0) {  // back from the parent's numbering to the buffer's own
        const int np = n << depth_;
        q.qx = int(best.quad) % np - int(places_[size_t(bestBuffer)][0]) * n;
        q.qy = int(best.quad) / np - int(places_[size_t(bestBuffer)][1]) * n;
      }
      if (std::find(star_.begin(), star_.end(), q) != star_.end()) return true;
      tmin = best.t;
    }
    return false;
  }

  std::vector<const DiceBuffer*> buffers_;
  std::vector<bool> flip_;
  int level_;
  int depth_ = 0;
  std::vector<std::array<uint32_t, 2>> places_;
  std::vector<std::vector<Vec3>> duplicated_;
  std::vector<StarQuad> star_;
  std::vector<Vec3> normals_;
};

void expectCaught(const Counts& c, long rays, const char* what, double maxSkipped = 0.01) {
  EXPECT_EQ(c.misses, 0) << what;
  EXPECT_LE(c.skipped, long(rays * maxSkipped)) << what << ": too many aims without a qualifying direction";
  EXPECT_GT(c.grazing, rays / 8) << what;
  std::printf("[ %s ] %ld rays (%ld grazing), %ld misses, %ld aims skipped\n", what, c.rays, c.grazing, c.misses,
              c.skipped);
}

// Inner edges (horizontal, vertical, diagonal) and inner vertices of one curved grid.
void singleGrid(const test::ControlPoints& cp, long rays, uint64_t seed, const char* what) {
  const int m = 5, n = 1 << m;
  const BezierPatch bp(cp);
  DiceBuffer buffer(m);
  buffer.dice(bp, m);
  Harness harness({&buffer}, {false}, m);
  test::Random rng(seed);
  Counts counts;
  for (long s = 0; s < rays; ++s) {
    const int kind = rng.below(4);
    int i = 1 + rng.below(n - 1), j = 1 + rng.below(n - 1), di = 0, dj = 0;
    if (kind == 1) { i = rng.below(n); di = 1; }                       // horizontal edge
    if (kind == 2) { j = rng.below(n); dj = 1; }                       // vertical edge
    if (kind == 3) { i = rng.below(n); j = rng.below(n); di = dj = 1; }  // quad diagonal
    Aim aim;
    aim.va = buffer.position(i, j);
    aim.vb = buffer.position(i + di, j + dj);
    const float lambda = kind == 0 ? 0.0f : rng.uniform();
    aim.p = aim.va * (1.0f - lambda) + aim.vb * lambda;
    aim.star = {{0, i, j}, {0, i + di, j + dj}};
    harness.shoot(rng, aim, bp.sizeBound() * rng.uniform(0.5f, 2.0f), counts);
  }
  expectCaught(counts, rays, what);
}

TEST(Watertight, InnerEdgesAndVerticesOfACurvedTeapotPatch) {
  singleGrid(test::loadTeapot()[0], 250000, 41, "teapot body patch, m=5");
}

TEST(Watertight, InnerEdgesAndVerticesOfAWavyPatch) {
  test::Random rng(42);
  test::ControlPoints cp;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) cp[j * 4 + i] = {float(i), float(j), rng.uniform(-2.5f, 2.5f)};
  singleGrid(cp, 250000, 43, "random wavy patch, m=5");
}

struct SeamSetup {
  float scale;
  Vec3 offset;
  int level;
  const char* what;
  double maxSkipped = 0.01;  // fraction of aims allowed to find no transversal direction
  size_t maxBorders = SIZE_MAX;  // the first shared borders only (fine levels dice a million vertices)
};

// A 2x2 quilt of Bézier patches over one 7x7 control grid (neighbours share their border
// rows exactly): a height field z(x, y) with random control heights, curved in both
// directions, but a graph over the xy-plane at every level, so its dicings never fold and
// every aim has a transversal direction (the vertical one at least).
std::vector<test::ControlPoints> heightFieldQuilt(uint64_t seed) {
  test::Random rng(seed);
  Vec3 grid[7][7];
  for (int j = 0; j < 7; ++j)
    for (int i = 0; i < 7; ++i) grid[j][i] = {float(i), float(j), rng.uniform(-1.0f, 1.0f)};
  std::vector<test::ControlPoints> patches;
  for (int pj = 0; pj < 2; ++pj)
    for (int pi = 0; pi < 2; ++pi) {
      test::ControlPoints cp;
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) cp[j * 4 + i] = grid[3 * pj + j][3 * pi + i];
      patches.push_back(cp);
    }
  return patches;
}

// Seams between patches that share a border (the teapot's unless given), each patch in its
// own DiceBuffer.
void seams(const SeamSetup& setup, long rays, uint64_t seed, std::vector<test::ControlPoints> patches = {}) {
  const auto teapot = patches.empty() ? test::loadTeapot() : std::move(patches);
  const auto shared = test::findSharedBorders(teapot);
  ASSERT_FALSE(shared.empty());
  const int m = setup.level, n = 1 << m;
  DiceBuffer a(m), b(m);
  test::Random rng(seed);
  Counts counts;
  const size_t borders = std::min(shared.size(), setup.maxBorders);
  const long perBorder = rays / long(borders) + 1;
  for (size_t sb = 0; sb < borders; ++sb) {
    const auto& s = shared[sb];
    const BezierPatch pa(test::transformed(teapot[s.patchA], setup.scale, setup.offset));
    const BezierPatch pb(test::transformed(teapot[s.patchB], setup.scale, setup.offset));
    a.dice(pa, m);
    b.dice(pb, m);
    // Orient b's triangles like a's for the transversality test.
    const auto mid = test::borderVertex(s.sideA, n / 2, n);
    const auto midB = test::borderVertex(s.sideB, s.reversed ? n - n / 2 : n / 2, n);
    const bool flip = dot(a.normal(mid[0], mid[1]), b.normal(midB[0], midB[1])) < 0;
    Harness harness({&a, &b}, {false, flip}, m);
    for (long r = 0; r < perBorder; ++r) {
      // Border vertices 1..n-1 and edges not touching the seam's ends: at the ends four
      // patches meet, and only two are in this test.
      if (n < 2) break;
      const bool vertex = rng.below(3) == 0 || n == 2;  // level 1: one inner border vertex, no inner edge
      const int k = vertex ? 1 + rng.below(n - 1) : 1 + rng.below(n - 2);
      const int k2 = vertex ? k : k + 1;
      auto onA = [&](int kk) { return test::borderVertex(s.sideA, kk, n); };
      auto onB = [&](int kk) { return test::borderVertex(s.sideB, s.reversed ? n - kk : kk, n); };
      Aim aim;
      aim.va = a.position(onA(k)[0], onA(k)[1]);
      aim.vb = a.position(onA(k2)[0], onA(k2)[1]);
      const float lambda = vertex ? 0.0f : rng.uniform();
      aim.p = aim.va * (1.0f - lambda) + aim.vb * lambda;
      aim.star = {{0, onA(k)[0], onA(k)[1]}, {0, onA(k2)[0], onA(k2)[1]},
                  {1, onB(k)[0], onB(k)[1]}, {1, onB(k2)[0], onB(k2)[1]}};
      harness.shoot(rng, aim, pa.sizeBound() * rng.uniform(0.5f, 2.0f), counts);
    }
  }
  expectCaught(counts, rays, setup.what, setup.maxSkipped);
}

TEST(Watertight, TeapotSeamsUnitScale) { seams({1.0f, {0, 0, 0}, 5, "teapot seams, scale 1, m=5"}, 200000, 51); }

TEST(Watertight, TeapotSeamsScaled1e4AndTranslated1e6) {
  seams({1e4f, {1e6f, -1e6f, 1e6f}, 5, "teapot seams, scale 1e4 at 1e6, m=5"}, 100000, 52);
}

TEST(Watertight, TeapotSeamsScaledTo1em3) { seams({1e-3f, {0, 0, 0}, 5, "teapot seams, scale 1e-3, m=5"}, 100000, 53); }

// Far from the origin at every level. At 1e6 floats are 1/16 apart: a teapot ten thousand
// units across keeps its micro-quads hundreds of ulps wide up to level 10, so from the first
// level with an inner border vertex to the finest every aim is representable. From level 6 on
// no aim may be skipped. Below, some are, at any position: the coarse dicing itself folds
// (lid rim, knob, spout tip: the triangles around P face opposite ways, so no direction is
// transversal to all of them), as at the origin (unit scale, level 5: 0.2 % of the aims).
// The height-field quilt below covers those levels with no aim skipped.
// (A unit-size teapot at 1e6 is quantized into folds at every level: no
// dicing can render it, so it is not a watertightness question.)
TEST(Watertight, TeapotSeamsTranslated1e6AtEveryLevel) {
  for (int level = 1; level <= 10; ++level) {
    const std::string what = "teapot seams, scale 1e4 at 1e6, m=" + std::to_string(level);
    const size_t borders = level >= 8 ? 1 : level >= 6 ? 4 : SIZE_MAX;
    const double maxSkipped = level >= 6 ? 0.0 : 0.03;
    seams({1e4f, {1e6f, 1e6f, 1e6f}, level, what.c_str(), maxSkipped, borders}, 3000, 54 + level);
  }
}

// The same at every level on a surface whose dicings cannot fold (heightFieldQuilt): every
// aim is shot, none skipped, so the coarse levels are covered as fully as the fine ones. The
// quilt is 6e3 units across, so at 1e6 (ulp 1/16) its level-10 micro-quads are still about 45
// ulps wide.
TEST(Watertight, HeightFieldSeamsTranslated1e6AtEveryLevelSkipNoAim) {
  const auto quilt = heightFieldQuilt(70);
  ASSERT_EQ(test::findSharedBorders(quilt).size(), 4u);
  for (int level = 1; level <= 10; ++level) {
    const std::string what = "height-field seams, scale 1e3 at 1e6, m=" + std::to_string(level);
    const size_t borders = level >= 8 ? 1 : 4;
    seams({1e3f, {1e6f, 1e6f, 1e6f}, level, what.c_str(), 0.0, borders}, 1500, 80 + level, quilt);
  }
}

// The seams between sub-leaves (a leaf split at set-up, issue 33 item 2): a displaced teapot
// body patch (curved, and its height noise curved again) split 2^depth times each way, every
// sub-leaf in its own buffer at level m, rays aimed at the vertices and edges on the lines
// the sub-leaves share, their crossings included (four sub-leaves meet there).
void subLeafSeams(int depth, int m, long rays, uint64_t seed, const char* what) {
  const auto base = std::make_shared<BezierPatch>(test::loadTeapot()[0]);
  NoiseParams noise;
  const float size = base->bounds().longestSide();
  noise.amplitude = 0.05f * size;
  noise.frequency = 3.0f / size;
  noise.octaves = 3;
  const auto parent = std::make_shared<DisplacedPatch>(base, std::make_shared<NoiseDisplacement>(noise));
  const uint32_t side = 1u << depth;
  const int n = 1 << m, N = n << depth;  // cells per sub-leaf, per parent
  std::vector<std::unique_ptr<DiceBuffer>> owned;
  std::vector<const DiceBuffer*> buffers;
  std::vector<std::array<uint32_t, 2>> places;
  for (uint32_t y = 0; y < side; ++y)
    for (uint32_t x = 0; x < side; ++x) {
      owned.push_back(std::make_unique<DiceBuffer>(m));
      owned.back()->dice(SubPatch(parent, depth, x, y), m);
      buffers.push_back(owned.back().get());
      places.push_back({x, y});
    }
  Harness harness(buffers, std::vector<bool>(buffers.size(), false), m);
  harness.setSubLeaves(depth, places);
  // Every buffer holding parent vertex (I, J), with its indices there.
  auto holders = [&](int I, int J) {
    std::vector<StarVertex> out;
    for (int k = 0; k < int(places.size()); ++k) {
      const int i = I - int(places[size_t(k)][0]) * n, j = J - int(places[size_t(k)][1]) * n;
      if (i >= 0 && j >= 0 && i <= n && j <= n) out.push_back({k, i, j});
    }
    return out;
  };
  auto position = [&](int I, int J) {
    const StarVertex v = holders(I, J).front();
    return buffers[size_t(v.buffer)]->position(v.i, v.j);
  };
  test::Random rng(seed);
  Counts counts;
  for (long s = 0; s < rays; ++s) {
    // A shared line: a vertical (u = const) or horizontal one inside the parent.
    const bool vertical = rng.below(2) == 0;
    const int line = (1 + int(rng.below(side - 1))) * n;
    const bool vertex = rng.below(3) == 0;
    const int along = vertex ? 1 + int(rng.below(uint32_t(N - 1))) : int(rng.below(uint32_t(N)));
    const int I0 = vertical ? line : along, J0 = vertical ? along : line;
    const int I1 = vertical ? I0 : (vertex ? I0 : I0 + 1), J1 = vertical ? (vertex ? J0 : J0 + 1) : J0;
    Aim aim;
    aim.va = position(I0, J0);
    aim.vb = position(I1, J1);
    const float lambda = vertex ? 0.0f : rng.uniform();
    aim.p = aim.va * (1.0f - lambda) + aim.vb * lambda;
    aim.star = holders(I0, J0);
    for (const StarVertex& v : holders(I1, J1)) aim.star.push_back(v);
    harness.shoot(rng, aim, parent->sizeBound() * rng.uniform(0.5f, 2.0f), counts);
  }
  expectCaught(counts, rays, what);
}

TEST(Watertight, SeamsBetweenSubLeavesOfADisplacedPatch) {
  subLeafSeams(1, 5, 60000, 91, "2x2 sub-leaves of a displaced teapot patch, m=5");
  subLeafSeams(2, 4, 60000, 92, "4x4 sub-leaves of a displaced teapot patch, m=4");
  subLeafSeams(3, 3, 30000, 93, "8x8 sub-leaves of a displaced teapot patch, m=3");
}

}  // namespace
}  // namespace rayes
