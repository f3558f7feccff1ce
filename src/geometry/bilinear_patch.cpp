#include "geometry/bilinear_patch.h"
#include "geometry/patch_math.h"

namespace rayes {

using detail::canonicalLerp;
using detail::lerp;

BilinearPatch::BilinearPatch(Vec3 p00, Vec3 p10, Vec3 p01, Vec3 p11)
    : p00_(p00), p10_(p10), p01_(p01), p11_(p11) {
  Box3 box;
  for (Vec3 p : {p00, p10, p01, p11}) box.extend(p);
  bounds_ = box.grownBy(detail::bilinearEvaluationError(box.magnitude()));
  // Iso lines are segments whose ends blend linearly between opposite borders, so none is
  // longer than the longest border.
  sizeBound_ = std::max(std::max(length(p10 - p00), length(p11 - p01)),
                        std::max(length(p01 - p00), length(p11 - p10)));
  tinyNormal_ = detail::degenerateNormalThreshold(box.longestSide());
}

Vec3 BilinearPatch::normalAt(float u, float v) const {
  return cross(lerp(p10_ - p00_, p11_ - p01_, v), lerp(p01_ - p00_, p11_ - p10_, u));
}

SurfacePoint BilinearPatch::evaluate(float u, float v) const {
  SurfacePoint sp;
  if (v == 0.0f) sp.p = canonicalLerp(p00_, p10_, u);
  else if (v == 1.0f) sp.p = canonicalLerp(p01_, p11_, u);
  else if (u == 0.0f) sp.p = canonicalLerp(p00_, p01_, v);
  else if (u == 1.0f) sp.p = canonicalLerp(p10_, p11_, v);
  else sp.p = lerp(lerp(p00_, p10_, u), lerp(p01_, p11_, u), v);
  sp.n = detail::nonDegenerateNormal([this](float uu, float vv) { return normalAt(uu, vv); },
                                     normalAt(u, v), u, v, tinyNormal_);
  return sp;
}

}  // namespace rayes
