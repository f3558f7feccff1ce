#include "geometry/forest_patches.h"
#include <array>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include "core/rng.h"
#include "geometry/bezier_patch.h"
#include "geometry/bilinear_patch.h"
#include "geometry/displaced_patch.h"
#include "geometry/forest_rings.h"

namespace rayes {
namespace {
void check(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}
}  // namespace

// A shear or an unequal scale would bend displacement heights, and a mirror would turn the
// terrain's normals down: a forest is placed by similarities only.
float forestPlacementScale(const Transform& t) {
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

void checkForestParams(const ForestParams& prm) {
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
  forestPlacementScale(prm.placement);
}

NoiseParams forestTerrainNoise(const ForestParams& p) {
  NoiseParams n;
  n.amplitude = p.terrainAmplitude;
  n.frequency = 3.0f / p.area;
  n.octaves = 5;
  n.seed = uint32_t(mix64(p.seed ^ 0x7465727261696eull));
  return n;
}

ForestPatches::ForestPatches(const ForestParams& params, GatedSpan<ForestBranch> branches,
                             GatedSpan<ForestFoliage> foliage, std::shared_ptr<const void> owner)
    : params_(params), branches_(branches), foliage_(foliage), owner_(std::move(owner)) {
  checkForestParams(params_);
  placementScale_ = forestPlacementScale(params_.placement);
  NoiseParams n = forestTerrainNoise(params_);
  if (placed()) {
    n.amplitude *= placementScale_;
    n.offset *= placementScale_;
  }
  placedTerrainNoise_ = std::make_shared<NoiseDisplacement>(n);
}

PatchPtr ForestPatches::makeTerrain(uint32_t tile) const {
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

PatchPtr ForestPatches::makeBark(const ForestLeaf& leaf) const {
  using namespace forest_rings;
  const ForestBranch br = branches_[leaf.index];
  if (leaf.segment >= br.segments)
    throw std::invalid_argument("segment " + std::to_string(leaf.segment) + " of a branch of " + std::to_string(br.segments));
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

PatchPtr ForestPatches::make(const ForestLeaf& leaf) const {
  const auto outside = [](const char* what, uint64_t i, uint64_t n) {
    throw std::invalid_argument(std::string(what) + " " + std::to_string(i) + " of " + std::to_string(n));
  };
  switch (leaf.part) {
    case ForestLeaf::Part::Terrain: {
      const uint64_t tiles = uint64_t(params_.terrainTiles) * uint64_t(params_.terrainTiles);
      if (leaf.index >= tiles) outside("terrain tile", leaf.index, tiles);
      return makeTerrain(leaf.index);
    }
    case ForestLeaf::Part::Bark:
      if (leaf.index >= branches_.size()) outside("branch", leaf.index, branches_.size());
      if (leaf.quarter > 3) outside("quarter", leaf.quarter, 4);
      return makeBark(leaf);
    case ForestLeaf::Part::Foliage: break;
    default: throw std::invalid_argument("forest part " + std::to_string(int(leaf.part)));
  }
  if (leaf.index >= foliage_.size()) outside("foliage leaf", leaf.index, foliage_.size());
  const ForestFoliage f = foliage_[leaf.index];
  return std::make_shared<BilinearPatch>(place(f.centre - f.halfU - f.halfV), place(f.centre + f.halfU - f.halfV),
                                         place(f.centre - f.halfU + f.halfV), place(f.centre + f.halfU + f.halfV));
}

}  // namespace rayes
