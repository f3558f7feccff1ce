// The scene the rays tests trace: the Utah teapot (32 Bézier patches) on a floor of four
// bilinear quads sharing edges, x and y in [-5, 5], z = 0.
#pragma once
#include <memory>
#include <string>
#include <vector>
#include "geometry/bezier_patch.h"
#include "geometry/bilinear_patch.h"

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

}  // namespace rayes::test
