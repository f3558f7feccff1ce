// The scene the rays tests trace: the Utah teapot (32 Bézier patches) on a floor of four
// bilinear quads sharing edges, x and y in [-5, 5], z = 0; `TracedWorld`, leaves with what
// the engines read of them (the source, the boxes, the top level); and rays toward the teapot.
#pragma once
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>
#include "core/ray_batch.h"
#include "core/rng.h"
#include "geometry/bezier_patch.h"
#include "geometry/bilinear_patch.h"
#include "geometry/leaf_source.h"
#include "toplevel/toplevel_bvh.h"

namespace rayes::test {

inline std::vector<PatchPtr> teapotOnFloor() {
  std::vector<PatchPtr> leaves;
  for (const auto& cp : loadBezierPatchFile(std::string(RAYES_SOURCE_DIR) + "/scenes/teapot.bpt"))
    leaves.push_back(std::make_shared<BezierPatch>(cp));
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) {
      const float x0 = -5 + 5 * i, y0 = -5 + 5 * j;
      leaves.push_back(std::make_shared<BilinearPatch>(Vec3{x0, y0, 0}, Vec3{x0 + 5, y0, 0}, Vec3{x0, y0 + 5, 0},
                                                       Vec3{x0 + 5, y0 + 5, 0}));
    }
  return leaves;
}

// Leaves as every engine of the tests reads them.
struct TracedWorld {
  std::vector<PatchPtr> leaves;
  StoredLeaves source;
  std::vector<Box3> boxes;
  TopLevelBvh top;
  explicit TracedWorld(std::vector<PatchPtr> l) : leaves(std::move(l)), source(leaves) {
    for (const auto& leaf : leaves) boxes.push_back(leaf->bounds());
    top.build(boxes);
  }
};

// The teapot on its floor and the leaves `more`, after them.
inline std::vector<PatchPtr> teapotOnFloorAnd(std::vector<PatchPtr> more) {
  std::vector<PatchPtr> leaves = teapotOnFloor();
  leaves.insert(leaves.end(), more.begin(), more.end());
  return leaves;
}

// n rays from a ring around the teapot (radius 7, heights 0.5-5.5) toward random points of its
// box, with zero footprint (so every ray takes the engine's fixed or finest level); `stream`
// keeps tests' ray sets independent. Shadow rays stop at t = 8.
inline RayBatch raysAtTheTeapot(int n, bool shadow, uint32_t stream) {
  RayBatch b;
  b.resize(n);
  for (int i = 0; i < n; ++i) {
    const RngKey k{uint32_t(i), shadow ? 1u : 0u, 0, stream};
    const float a = 6.2831853f * sampleUniform(k, 0);
    const Vec3 o{7 * std::cos(a), 7 * std::sin(a), 0.5f + 5 * sampleUniform(k, 1)};
    const Vec3 target{-2 + 4 * sampleUniform(k, 2), -2 + 4 * sampleUniform(k, 3), 3 * sampleUniform(k, 4)};
    const float tMax = shadow ? 8.0f : std::numeric_limits<float>::infinity();
    b.setFromNowhere(i, shadow ? RayKind::Shadow : RayKind::Closest, o, normalize(target - o), tMax, 0.0f, 0.0f);
  }
  return b;
}

}  // namespace rayes::test
