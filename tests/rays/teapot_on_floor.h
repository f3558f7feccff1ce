// The scene the rays tests trace: the Utah teapot (32 Bézier patches) on a floor of four
// bilinear quads sharing edges, x and y in [-5, 5], z = 0; and `TracedWorld`, leaves with what
// the engines read of them (the source, the boxes, the top level).
#pragma once
#include <memory>
#include <string>
#include <vector>
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

}  // namespace rayes::test
