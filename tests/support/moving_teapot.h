// A teapot patch placed by a transform, and a moving one of three keyframes: the patches of the
// motion tests (geometry/moving_patch_test.cpp, dicing/motion_dice_test.cpp).
#pragma once
#include <memory>
#include <vector>
#include "core/transform.h"
#include "geometry/bezier_patch.h"
#include "geometry/moving_patch.h"
#include "support/patch_test_util.h"

namespace rayes::test {

inline PatchPtr teapotPatchAt(const Transform& xf, int which = 0) {
  auto cp = test::loadTeapot()[size_t(which)];
  for (auto& p : cp) p = xf.point(p);
  return std::make_shared<BezierPatch>(cp);
}

// Three keyframes: still, moved and turned, moved further.
inline std::shared_ptr<MovingPatch> movingTeapotPatch() {
  std::vector<PatchPtr> samples = {
      teapotPatchAt(Transform{}),
      teapotPatchAt(Transform::translate({0.4f, -0.2f, 0.3f}) * Transform::rotate({0, 0, 1}, 20.0f)),
      teapotPatchAt(Transform::translate({0.9f, 0.1f, 0.2f}) * Transform::rotate({0, 1, 0}, 15.0f)),
  };
  return std::make_shared<MovingPatch>(samples, std::vector<float>{0.0f, 0.5f, 1.0f});
}

}  // namespace rayes::test
