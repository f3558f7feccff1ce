#include "geometry/forest.h"
#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <stdexcept>
#include <string>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include "core/rng.h"
#include "geometry/bezier_patch.h"
#include "geometry/bilinear_patch.h"
#include "geometry/displaced_patch.h"

namespace rayes {
namespace {
constexpr float kPi = std::numbers::pi_v<float>;
// Bézier handle length of a quarter circle (4/3 tan(π/8)): radial error 0.027 %.
constexpr float kArcHandle = 0.5522847498f;
// cos and sin of the quarter angles 0, π/2, π, 3π/2, exactly: the four quarters of a ring meet
// in bit-identical points, and quarter 3 closes on quarter 0.
constexpr float kQuarterCos[5] = {1, 0, -1, 0, 1};
constexpr float kQuarterSin[5] = {0, 1, 0, -1, 0};

int segmentsAt(int level) { return level == 0 ? 3 : 2; }

// Counter-based numbers for one tree: a pure function of (seed, tree, draw index), so a tree
// grows the same whichever thread grows it and whatever was grown before.
class TreeRandom {
 public:
  TreeRandom(uint64_t seed, uint32_t tree) : key_(mix64(seed ^ 0x6f72657374ull) ^ mix64(tree + 1ull)) {}
  float uniform() { return bitsToUnitFloat(mix64(key_ + 0x9e3779b97f4a7c15ull * ++n_)); }
  float uniform(float a, float b) { return a + (b - a) * uniform(); }

 private:
  uint64_t key_, n_ = 0;
};

Vec3 bezier(const Vec3 (&p)[4], float t) {
  const float s = 1 - t;
  return p[0] * (s * s * s) + p[1] * (3 * s * s * t) + p[2] * (3 * s * t * t) + p[3] * (t * t * t);
}
Vec3 bezierTangent(const Vec3 (&p)[4], float t) {
  const float s = 1 - t;
  return (p[1] - p[0]) * (3 * s * s) + (p[2] - p[1]) * (6 * s * t) + (p[3] - p[2]) * (3 * t * t);
}

// The ring of a branch at spine parameter t: centre, radius, and the frame (n, b) the quarter
// angles are measured in. Every patch that touches the ring at t computes it by this one
// function from the same float t, so shared borders are bit-identical.
struct Ring {
  Vec3 c, n, b;
  float r;
  Vec3 at(int q) const { return c + (n * kQuarterCos[q] + b * kQuarterSin[q]) * r; }
  Vec3 tangentAt(int q) const { return (b * kQuarterCos[q] - n * kQuarterSin[q]) * (kArcHandle * r); }
};
Ring ringAt(const Forest::Branch& br, float t) {
  const Vec3 T = normalize(bezierTangent(br.spine, t));
  const Vec3 n = normalize(br.up - T * dot(br.up, T));
  return {bezier(br.spine, t), n, cross(T, n), br.r0 + (br.r1 - br.r0) * t};
}

Vec3 leastAlignedAxis(Vec3 d) {
  const Vec3 a = vabs(d);
  if (a.x <= a.y && a.x <= a.z) return {1, 0, 0};
  return a.y <= a.z ? Vec3{0, 1, 0} : Vec3{0, 0, 1};
}

// Grows one tree: branches depth-first (children in order), foliage on the last level.
struct TreeGrowth {
  std::vector<Forest::Branch> branches;
  std::vector<Forest::Foliage> foliage;
};

void grow(const ForestParams& prm, TreeRandom& rnd, uint32_t tree, Vec3 start, Vec3 dir, float length,
          float radius, int level, TreeGrowth& out) {
  // The spine bends a little sideways and upward (towards the light).
  Vec3 t, b;
  orthonormalBasis(dir, t, b);
  const Vec3 up{0, 1, 0};
  const Vec3 bend1 = (t * rnd.uniform(-1, 1) + b * rnd.uniform(-1, 1)) * (0.06f * length);
  const Vec3 bend2 = (t * rnd.uniform(-1, 1) + b * rnd.uniform(-1, 1)) * (0.06f * length) + up * (0.08f * length);
  Forest::Branch br;
  br.spine[0] = start;
  br.spine[1] = start + dir * (length / 3) + bend1;
  br.spine[2] = start + dir * (2 * length / 3) + bend2;
  br.spine[3] = start + dir * length + bend2 * 1.5f;
  const Vec3 axis = normalize(br.spine[3] - br.spine[0]);
  br.up = leastAlignedAxis(axis);
  br.r0 = radius;
  br.r1 = radius * 0.62f;
  br.segments = uint16_t(segmentsAt(level));
  br.tree = tree;
  out.branches.push_back(br);

  if (level < prm.detail) {
    const Vec3 tip = br.spine[3];
    const Vec3 tipDir = normalize(bezierTangent(br.spine, 1.0f));
    Vec3 tt, tb;
    orthonormalBasis(tipDir, tt, tb);
    const float phase = rnd.uniform(0, 2 * kPi);
    for (int c = 0; c < prm.branching; ++c) {
      const float azimuth = phase + 2 * kPi * (float(c) + rnd.uniform(-0.2f, 0.2f)) / float(prm.branching);
      const float spread = rnd.uniform(0.45f, 0.8f);  // radians from the parent's direction
      Vec3 d = tipDir * std::cos(spread) + (tt * std::cos(azimuth) + tb * std::sin(azimuth)) * std::sin(spread);
      d = normalize(d + up * 0.2f);
      // A child starts a little inside its parent's tip so the tubes overlap at the joint.
      grow(prm, rnd, tree, tip - tipDir * (0.5f * br.r1), d, length * rnd.uniform(0.62f, 0.78f), br.r1 * 0.92f,
           level + 1, out);
    }
    return;
  }
  // A twig: leaves along its outer two thirds, each a flat quad beside the twig.
  const float leafSize = 0.05f * prm.treeHeight / float(1 + prm.detail) * 2.5f;
  for (int k = 0; k < prm.leavesPerTwig; ++k) {
    const float s = rnd.uniform(0.3f, 1.0f);
    const Ring ring = ringAt(br, s);
    const float a = rnd.uniform(0, 2 * kPi);
    const Vec3 out_ = ring.n * std::cos(a) + ring.b * std::sin(a);
    const Vec3 along = normalize(bezierTangent(br.spine, s));
    Forest::Foliage f;
    f.centre = ring.c + out_ * (ring.r + 0.6f * leafSize);
    const Vec3 side = normalize(cross(along, out_));
    const float tilt = rnd.uniform(-0.6f, 0.6f);
    f.halfU = (out_ * std::cos(tilt) + along * std::sin(tilt)) * (0.6f * leafSize);
    f.halfV = side * (0.3f * leafSize);
    out.foliage.push_back(f);
  }
}

void check(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}

}  // namespace

// A shear or an unequal scale would bend displacement heights, and a mirror would turn the
// terrain's normals down: a forest is placed by similarities only.
float Forest::placementScale(const Transform& t) {
  if (std::memcmp(t.m, Transform{}.m, sizeof t.m) == 0) return 0;
  for (const auto& row : t.m)
    for (float v : row) check(std::isfinite(v), "the placement must be finite");
  const double det = t.determinant();
  check(det > 0, "the placement must keep orientation (positive determinant)");
  const double s = std::cbrt(det);
  check(s > 1e-30 && s < 1e30, "the placement's scale must be in (1e-30, 1e30)");
  // Columns of the linear part: orthogonal, each of length s (to float rounding).
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) {
      double d = 0;
      for (int k = 0; k < 3; ++k) d += double(t.m[k][i]) * double(t.m[k][j]);
      check(std::fabs(d - (i == j ? s * s : 0.0)) <= 1e-5 * s * s,
            "a forest takes only rotations, uniform scales and translations");
    }
  return float(s);
}

namespace {
NoiseParams terrainNoiseParams(const ForestParams& p) {
  NoiseParams n;
  n.amplitude = p.terrainAmplitude;
  n.frequency = 3.0f / p.area;
  n.octaves = 5;
  n.seed = uint32_t(mix64(p.seed ^ 0x7465727261696eull));
  return n;
}
}  // namespace

uint64_t Forest::leafCount(const ForestParams& p) {
  // In double first: an absurd detail must not wrap around.
  double perTree = 0, atLevel = 1;
  for (int level = 0; level <= p.detail; ++level) {
    perTree += atLevel * 4 * segmentsAt(level);
    if (level == p.detail) perTree += atLevel * p.leavesPerTwig;
    atLevel *= p.branching;
  }
  const double total = double(p.trees) * perTree + double(p.terrainTiles) * double(p.terrainTiles);
  return total >= 1.8e19 ? UINT64_MAX : uint64_t(total);
}

Forest::Forest(const ForestParams& prm, uint64_t maxLeaves) : params_(prm) {
  check(prm.detail >= 0 && prm.detail <= ForestParams::kMaxDetail,
        "detail must be in [0, " + std::to_string(ForestParams::kMaxDetail) + "]");
  check(prm.branching >= 1 && prm.branching <= ForestParams::kMaxBranching,
        "branching must be in [1, " + std::to_string(ForestParams::kMaxBranching) + "]");
  check(std::isfinite(prm.area) && prm.area > 0 && prm.area < 1e7f, "area must be in (0, 1e7)");
  check(std::isfinite(prm.treeHeight) && prm.treeHeight > 0 && prm.treeHeight < 1e6f, "tree height must be in (0, 1e6)");
  check(prm.terrainTiles >= 1 && prm.terrainTiles <= ForestParams::kMaxTerrainTiles,
        "terrain tiles must be in [1, " + std::to_string(ForestParams::kMaxTerrainTiles) + "]");
  check(std::isfinite(prm.terrainAmplitude) && prm.terrainAmplitude >= 0 && prm.terrainAmplitude < 1e6f,
        "terrain amplitude must be in [0, 1e6)");
  check(prm.leavesPerTwig >= 0 && prm.leavesPerTwig <= ForestParams::kMaxLeavesPerTwig,
        "leaves per twig must be in [0, " + std::to_string(ForestParams::kMaxLeavesPerTwig) + "]");
  const uint64_t count = leafCount(prm);
  check(count <= maxLeaves, "the forest would have " + std::to_string(count) + " leaves, more than the limit of " +
                                std::to_string(maxLeaves));
  placementScale_ = placementScale(prm.placement);
  terrainNoise_ = std::make_shared<NoiseDisplacement>(terrainNoiseParams(prm));
  placedTerrainNoise_ = terrainNoise_;
  if (placed()) {
    NoiseParams n = terrainNoiseParams(prm);
    n.amplitude *= placementScale_;
    n.offset *= placementScale_;
    placedTerrainNoise_ = std::make_shared<NoiseDisplacement>(n);
  }

  // Trees grow in parallel into their own lists; joining them in tree order makes the result
  // independent of the thread count.
  std::vector<TreeGrowth> trees(prm.trees);
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, prm.trees), [&](const auto& r) {
    for (uint32_t i = r.begin(); i != r.end(); ++i) {
      TreeRandom rnd(prm.seed, i);
      const float x = (rnd.uniform() - 0.5f) * 0.9f * prm.area, z = (rnd.uniform() - 0.5f) * 0.9f * prm.area;
      const float height = prm.treeHeight * rnd.uniform(0.8f, 1.2f);
      const float radius = 0.035f * height;
      const Vec3 base{x, groundHeight(x, z) - radius, z};
      const Vec3 dir = normalize(Vec3{rnd.uniform(-0.08f, 0.08f), 1, rnd.uniform(-0.08f, 0.08f)});
      grow(prm, rnd, i, base, dir, 0.42f * height, radius, 0, trees[i]);
    }
  });

  const uint32_t tiles = uint32_t(prm.terrainTiles) * uint32_t(prm.terrainTiles);
  leaves_.reserve(count);
  for (uint32_t t = 0; t < tiles; ++t) leaves_.push_back({ForestLeaf::Part::Terrain, 0, 0, t});
  for (TreeGrowth& g : trees) {
    for (Branch& br : g.branches) {
      const uint32_t index = uint32_t(branches_.size());
      for (uint16_t s = 0; s < br.segments; ++s)
        for (uint8_t q = 0; q < 4; ++q) leaves_.push_back({ForestLeaf::Part::Bark, q, s, index});
      branches_.push_back(br);
    }
    for (Foliage& f : g.foliage) {
      leaves_.push_back({ForestLeaf::Part::Foliage, 0, 0, uint32_t(foliage_.size())});
      foliage_.push_back(f);
    }
    g = TreeGrowth{};
  }
  // Each leaf's box is its patch's own conservative bound; the patch is dropped again.
  bounds_.resize(leaves_.size());
  size_.resize(leaves_.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, leaves_.size(), 256), [&](const auto& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const PatchPtr patch = makePatch(i);
      bounds_[i] = patch->bounds();
      size_[i] = {patch->sizeBound(), patch->dicingErrorCoefficient()};
    }
  });
}

float Forest::groundHeight(float x, float z) const {
  return terrainNoise_->sample({x, 0, z}, {1, 0, 0}, {0, 0, -1}, 0, 0).h;
}

PatchPtr Forest::makeTerrain(uint32_t tile) const {
  const uint32_t n = uint32_t(params_.terrainTiles);
  const uint32_t i = tile % n, j = tile / n;
  // The terrain reaches a little beyond the trees. Tile corners come from one expression of
  // the integer grid coordinate, so neighbouring tiles share their border points bit for bit.
  const float side = 1.2f * params_.area, half = 0.5f * side;
  auto coord = [&](uint32_t k) { return -half + side * (float(k) / float(n)); };
  const float x0 = coord(i), x1 = coord(i + 1), z0 = coord(j), z1 = coord(j + 1);
  // u along +x and v along -z, so dP/du x dP/dv points up (+y).
  const Vec3 c[4] = {{x0, 0, z1}, {x1, 0, z1}, {x0, 0, z0}, {x1, 0, z0}};
  auto base = std::make_shared<BilinearPatch>(place(c[0]), place(c[1]), place(c[2]), place(c[3]));
  // Placed, the noise stays a function of the unplaced surface (DisplacedPatch's reference).
  PatchPtr reference = placed() ? std::make_shared<BilinearPatch>(c[0], c[1], c[2], c[3]) : nullptr;
  return std::make_shared<DisplacedPatch>(std::move(base), placedTerrainNoise_, std::move(reference));
}

PatchPtr Forest::makeBark(const ForestLeaf& leaf) const {
  const Branch& br = branches_[leaf.index];
  const int q = leaf.quarter;
  // Rows along the spine: the border rows (j = 0, 3) are the exact rings at the segment's ends,
  // shared with the neighbouring segments; the inner rows are rings at the thirds, which makes
  // the tube follow the spine closely (within the control hull, as every Bézier patch).
  std::array<Vec3, 16> cp;
  for (int j = 0; j < 4; ++j) {
    const float t = j == 0 ? float(leaf.segment) / float(br.segments)
                  : j == 3 ? float(leaf.segment + 1) / float(br.segments)
                           : (float(leaf.segment) + float(j) / 3.0f) / float(br.segments);
    const Ring ring = ringAt(br, t);
    const Vec3 p0 = ring.at(q), p3 = ring.at(q + 1);
    cp[j * 4 + 0] = p0;
    cp[j * 4 + 1] = p0 + ring.tangentAt(q);
    cp[j * 4 + 2] = p3 - ring.tangentAt(q + 1);
    cp[j * 4 + 3] = p3;
  }
  // Bark: ridged noise of position, about a fifth of the branch's radius deep.
  NoiseParams bark;
  bark.amplitude = 0.18f * br.r0;
  bark.offset = -0.09f * br.r0;
  bark.frequency = 1.5f / br.r0;
  bark.octaves = 3;
  bark.ridged = true;
  bark.seed = uint32_t(mix64(params_.seed ^ br.tree));
  if (!placed())
    return std::make_shared<DisplacedPatch>(std::make_shared<BezierPatch>(cp), std::make_shared<NoiseDisplacement>(bark));
  auto reference = std::make_shared<BezierPatch>(cp);
  for (Vec3& p : cp) p = place(p);
  bark.amplitude *= placementScale_;
  bark.offset *= placementScale_;
  return std::make_shared<DisplacedPatch>(std::make_shared<BezierPatch>(cp), std::make_shared<NoiseDisplacement>(bark),
                                          std::move(reference));
}

PatchPtr Forest::makePatch(size_t i) const {
  const ForestLeaf& leaf = leaves_[i];
  switch (leaf.part) {
    case ForestLeaf::Part::Terrain: return makeTerrain(leaf.index);
    case ForestLeaf::Part::Bark: return makeBark(leaf);
    case ForestLeaf::Part::Foliage: break;
  }
  const Foliage& f = foliage_[leaf.index];
  return std::make_shared<BilinearPatch>(place(f.centre - f.halfU - f.halfV), place(f.centre + f.halfU - f.halfV),
                                         place(f.centre - f.halfU + f.halfV), place(f.centre + f.halfU + f.halfV));
}

uint64_t Forest::countOf(ForestLeaf::Part part) const {
  return uint64_t(std::count_if(leaves_.begin(), leaves_.end(), [&](const ForestLeaf& l) { return l.part == part; }));
}

double Forest::bytesPerLeaf() const {
  if (leaves_.empty()) return 0;
  const double bytes = double(leaves_.size()) * double(sizeof(ForestLeaf) + sizeof(Box3) + sizeof(LeafSize)) +
                       double(branches_.size()) * double(sizeof(Branch)) + double(foliage_.size()) * double(sizeof(Foliage));
  return bytes / double(leaves_.size());
}

}  // namespace rayes
