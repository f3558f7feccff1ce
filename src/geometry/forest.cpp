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
#include "geometry/forest_rings.h"

namespace rayes {
namespace {
using namespace forest_rings;
constexpr float kPi = std::numbers::pi_v<float>;

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
  checkForestParams(prm);
  const uint64_t count = leafCount(prm);
  if (count > maxLeaves)
    throw std::invalid_argument("the forest would have " + std::to_string(count) + " leaves, more than the limit of " +
                                std::to_string(maxLeaves));
  terrainNoise_ = std::make_shared<NoiseDisplacement>(forestTerrainNoise(prm));

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
  patches_ = std::make_unique<const ForestPatches>(params_, GatedSpan<Branch>(branches_.data(), branches_.size()),
                                                   GatedSpan<Foliage>(foliage_.data(), foliage_.size()));
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
