// Displacement along the normal: a Patch decorator over any base patch,
//   P'(u, v) = P(u, v) + N(u, v) h,   N = the base's unit normal, h from a Displacement.
//
// Bounds (docs/design.md, invariant 1). boundsOver(rect) = base.boundsOver(rect) + Nrange(rect) x
// Hrange(rect) per axis, in interval arithmetic, padded: Hrange is the displacement's
// conservative range (interval noise over the base's position box, or the min-max MIP
// pyramid), Nrange a conservative range of each component of the base's unit normal over the
// rectangle. For Bézier bases Nrange comes from the hodographs of the de Casteljau sub-patch
// (the derivative of a Bézier lies in the hull of its difference control points), for bilinear
// bases from the derivatives' end values (they are linear); for other kinds, and wherever the
// base normal can degenerate (poles, where the base substitutes a nudged normal), each
// component is taken in [-1, 1]. bounds() is boundsOver(0, 1, 0, 1).
//
// Normals. The displaced normal is P'_u x P'_v with P'_u = P_u + N_u h + N h_u, h_u analytically
// from the displacement. Over Bézier and bilinear bases (and references) P_u, P_v and the unit
// normal's derivative N_u = (I - N N^T) (P_uu x P_v + P_u x P_uv) / |P_u x P_v| are analytic
// (SurfaceDerivatives). Where the base normal is degenerate (|P_u x P_v| at most the base's
// threshold: a pole, where the base nudges its normal) and over other kinds (subdivision
// faces), P_u and N_u are one-sided finite differences of base evaluations at a fixed
// parameter step (2^-10, forward, backward at u or v = 1). Both are functions of (u, v) alone,
// not of the dicing's grid spacing, so dice() equals evaluate() bit for bit and the level-k
// subgrid of a level-m dicing is a level-k dicing, normals included (invariant 2). Where the
// displaced cross product is not finite or vanishes, the base normal is used. Positions use
// only the base point and unit normal, which are the base's own evaluate() bits.
//
// Seams: h of a noise displacement is a function of the base POSITION, so it is bit-identical
// on both sides of a shared border; the displaced border vertices are then bit-identical only
// where the two bases' unit normals are too. See tests/geometry/displace_patch_test.cpp for what
// the teapot does (its shared borders differ by rounding in the normal).
#pragma once
#include <string>
#include "core/vector_isa.h"
#include "geometry/displacement.h"
#include "geometry/patch.h"

namespace rayes {

class BezierPatch;
class BilinearPatch;

class DisplacedPatch final : public Patch {
 public:
  // `reference`: the surface whose position (and parameters) the displacement is a function
  // of, with the base's parametrisation -- the scene gives the shape's object-space patch, so
  // the pattern is attached to the shape and does not swim when it is transformed or moves
  // between time samples. Null: the base itself (no extra evaluations).
  DisplacedPatch(PatchPtr base, DisplacementPtr displacement, PatchPtr reference = nullptr);

  Box3 bounds() const override { return bounds_; }
  Box3 boundsOver(float u0, float u1, float v0, float v1) const override;
  void borderPieceBoundsAt(int sample, int e, int k, uint32_t j, int split, Box3* out) const override;
  // The base's boundsOver grown by the displacement's magnitudeBound() and the rounding of
  // boundsOver's composition (displaced_patch.cpp): about a tenth of boundsOver's cost with
  // noise, whose interval range is most of it. False where the displacement has no bound.
  bool coarseBoundsOverAt(int sample, float u0, float u1, float v0, float v1, Box3& out) const override;
  // The base's size lengthened by the displacement's mean slope (per unit length and per unit
  // parameter) and by max|h| times the spread of the base normal (an offset surface of a
  // curved base is longer): strongly displaced patches are diced finer. An estimate for LOD,
  // as the Patch contract allows; not a bound.
  float sizeBound() const override { return sizeBound_; }
  SurfacePoint evaluate(float u, float v) const override;
  void dice(int level, Vec3* positions, Vec3* normals) const override;
  // The conservative default: the longest side of bounds() (a bound of the distance between
  // the dicing and the surface at m = 0, divided by 4^m). A second-derivative bound would need
  // the base normal's derivatives, which the Patch interface does not give.
  float dicingErrorCoefficient() const override { return bounds_.longestSide(); }
  const char* kind() const override { return kind_.c_str(); }  // "displaced-<base kind>"
  bool isDisplaced() const override { return true; }
  bool isSubdivision() const override { return base_->isSubdivision(); }

  const Patch& base() const { return *base_; }
  const Displacement& displacement() const { return *displacement_; }
  // The reference given to the constructor, or null when it was none (the base itself).
  const Patch* givenReference() const { return reference_ == base_ ? nullptr : reference_.get(); }
  // Per component, a conservative range of the base's unit normal (as evaluate() computes it)
  // over the parameter rectangle, as a box in [-1, 1]^3 (widened for rounding).
  Box3 normalRangeOver(float u0, float u1, float v0, float v1) const;

  static constexpr float kDifferenceStep = 1.0f / 1024.0f;

 private:
  // The base at one vertex: its point, unit normal and their derivatives along u and v.
  struct Frame {
    Vec3 p, n, baseNormal, pu, pv, nu, nv;
  };
  // What the vertices of one grid row share (defined in the .cpp): the Bézier base's and
  // reference's rows at v, and the rows at v's difference point once a vertex needs them.
  struct RowContext;
  RowContext rowContext(float v) const;
  // The frames of `count` vertices of the row at r.v, at parameters us[0..count), and in (at,
  // atU, atV) the points and derivatives the displacement is sampled at: the reference's (the
  // base's when there is none). dice() calls it per grid row, evaluate() with count 1: the same
  // code, which is what makes them equal bit for bit. Analytic for Bézier and bilinear bases
  // (vectorised across the row), differences where those degenerate and for other kinds.
  void rowFrames(RowContext& row, int count, const float* us, Frame* frames, Vec3* at, Vec3* atU, Vec3* atV) const;
  // rowFrames' body and its version per instruction set (core/vector_isa.h): rowFrames calls the
  // one vectorIsa() names.
  void rowFramesBody(RowContext& row, int count, const float* us, Frame* frames, Vec3* at, Vec3* atU,
                     Vec3* atV) const;
  RAYES_TARGET_AVX2 void rowFramesAvx2(RowContext& row, int count, const float* us, Frame* frames, Vec3* at,
                                       Vec3* atU, Vec3* atV) const;
  void rowFramesBaseline(RowContext& row, int count, const float* us, Frame* frames, Vec3* at, Vec3* atU,
                         Vec3* atV) const;
  void referenceAt(const RowContext& row, float u, const Frame& f, Vec3& at, Vec3& atU, Vec3& atV) const;
  Frame differenceFrame(RowContext& row, const SurfacePoint& c, float u) const;
  SurfacePoint displaced(const Frame& f, const HeightSample& h) const;
  // The unit normal's range from boxes of P_u and P_v over a piece (a Bézier base's restricted
  // hodographs), widened by the restriction's rounding beyond a few ulps of the boxes.
  Box3 normalRangeFromHodographs(Box3 du, Box3 dv, float restrictionError) const;
  static Box3 displacedBox(const Box3& b, const Box3& nr, Interval h);
  // borderPieceBoundsAt over a Bézier base, with scratch for 2^split pieces of the reference
  // and the two hodographs.
  void displacedPieces(int e, int k, uint32_t j, int split, Box3* out, Box3* reference, Box3* du, Box3* dv) const;
  PatchPtr base_;
  DisplacementPtr displacement_;
  PatchPtr reference_;       // never null (the base when none was given)
  std::string kind_;
  // The base's and reference's kinds where they have analytic derivatives and normal ranges
  // (else null).
  const BezierPatch* bezierBase_ = nullptr;
  const BezierPatch* bezierReference_ = nullptr;
  const BilinearPatch* bilinearBase_ = nullptr;
  const BilinearPatch* bilinearReference_ = nullptr;
  Vec3 corners_[4];          // bilinear base: p00, p10, p01, p11 (from evaluate at the corners)
  Vec3 hodographU_[12];      // Bézier base: 3 x the control point differences along u (4 rows of 3)
  Vec3 hodographV_[12];      // ... and along v (3 rows of 4)
  float hodographCancellation_ = 0;  // Bézier base: the derivatives' rounding, from the control box
  float tinyNormal_ = 0;     // the base's degenerate-normal threshold (patch_math.h)
  Box3 bounds_;
  float sizeBound_ = 0;
};

}  // namespace rayes
