// One surface hit as both integrators leave it: the point, the geometric normal and the
// origin offset of rays that leave it (originOffset), and the test that keeps
// shading normals from leaking light through the true surface.
#pragma once
#include "core/vec.h"

namespace rayes {

struct SurfaceHit {
  Vec3 p;          // the hit point
  Vec3 ng;         // unit geometric normal of the micro-triangle
  float offset;    // how far leaving rays start off the surface

  // The origin of a ray leaving toward w: pushed off to w's side of the geometric normal.
  Vec3 originToward(Vec3 w) const { return p + (dot(ng, w) >= 0 ? ng : -ng) * offset; }

  // Whether directions a and b (aL, bL in the shading frame) lie on the sides of the true
  // surface that the frame claims: both on one side for reflection, on opposite sides for
  // transmission. Otherwise it is the light leak of shading normals at silhouettes.
  bool consistent(Vec3 a, Vec3 aL, Vec3 b, Vec3 bL) const {
    const float s = dot(ng, a) * dot(ng, b);
    return aL.z * bL.z > 0 ? s > 0 : s < 0;
  }
};

}  // namespace rayes
