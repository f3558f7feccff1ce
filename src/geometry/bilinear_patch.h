// Bilinear patches: the simplest kind, for quads of meshes, ground planes and tests.
//
// u runs along p00 -> p10, v along p00 -> p01. Immutable and thread-safe like every Patch.
// Each border is the straight segment between two corners, evaluated in canonical orientation
// (geometry/patch_math.h), so bilinear patches sharing two corners -- in either order -- produce
// bit-identical border vertices at the same level. The default Patch::dice() is used: it calls
// evaluate(), which already routes borders through the canonical segment.
#pragma once
#include <array>
#include "geometry/patch.h"
#include "geometry/patch_math.h"

namespace rayes {

class BilinearPatch final : public Patch {
 public:
  BilinearPatch(Vec3 p00, Vec3 p10, Vec3 p01, Vec3 p11);

  Box3 bounds() const override { return bounds_; }    // box of the corners, grown by the rounding of evaluate()
  float sizeBound() const override { return sizeBound_; }  // longest of the 4 border edges
  SurfacePoint evaluate(float u, float v) const override;
  // P_u and P_v are linear in v and u (cross(pu, pv) is evaluate()'s normal where that is not
  // nudged), P_uv the twist, P_uu = P_vv = 0. Inline: DisplacedPatch calls it in a loop over a
  // grid row that the compiler vectorises.
  SurfaceDerivatives derivatives(float u, float v) const {
    SurfaceDerivatives d;
    d.pu = detail::lerp(p10_ - p00_, p11_ - p01_, v);
    d.pv = detail::lerp(p01_ - p00_, p11_ - p10_, u);
    d.puv = (p11_ - p01_) - (p10_ - p00_);
    d.puu = d.pvv = Vec3{0, 0, 0};
    return d;
  }
  const char* kind() const override { return "bilinear"; }
  // The corners as given to the constructor (a compiled scene stores them: geometry/patch_record.h).
  std::array<Vec3, 4> corners() const { return {p00_, p10_, p01_, p11_}; }
  // Each micro-quad is itself bilinear with twist h^2 w, w = p00 - p10 - p01 + p11; its two
  // triangles deviate from it by at most |h^2 w| / 4 (at the centre). Exactly zero when the
  // corners are coplanar up to the rounding of their coordinates: the micro-triangles
  // of a planar patch lie in its plane, whatever its shape (trapezoids have w != 0).
  float dicingErrorCoefficient() const override { return errorCoefficient_; }
  // Every border is the straight segment between two corners at every level (twisted or not):
  // neighbours at different levels leave no slit to close (up to rounding).
  bool needsBorderClosure() const override { return false; }
  // A bilinear patch over a sub-rectangle is the bilinear patch of its four corners, inside
  // their box.
  Box3 boundsOver(float u0, float u1, float v0, float v1) const override {
    Box3 b;
    for (float u : {u0, u1})
      for (float v : {v0, v1}) b.extend(evaluate(u, v).p);
    return b.grownBy(detail::bilinearEvaluationError(b.magnitude()));
  }

 private:
  // The four corners lie in one plane, to within what rounding each coordinate to float can
  // make of a truly planar quad.
  static bool coplanarUpToRounding(Vec3 p00, Vec3 p10, Vec3 p01, Vec3 p11);
  Vec3 normalAt(float u, float v) const;

  Vec3 p00_, p10_, p01_, p11_;
  Box3 bounds_;
  float sizeBound_ = 0;
  float tinyNormal_ = 0;
  float errorCoefficient_ = 0;
};

}  // namespace rayes
