// Bicubic Bézier patches (the Utah teapot's kind) and the .bpt file loader.
//
// Control points are 4x4, row-major: cp[j*4+i] has u-index i and v-index j. Immutable and
// thread-safe like every Patch. Evaluation is O(1) (16 control points); dice() is O(4^level).
//
// Watertight seams: a border (u or v exactly 0 or 1) is evaluated as the cubic Bézier curve of
// its 4 border control points in canonical orientation (geometry/patch_math.h), both in dice()
// and in evaluate(), so neighbours sharing a border row of control points produce identical
// border vertices at the same level, and dice() equals evaluate() bit for bit everywhere.
#pragma once
#include <array>
#include <string>
#include <vector>
#include "geometry/patch.h"
#include "geometry/patch_math.h"

namespace rayes {

class BezierPatch final : public Patch {
 public:
  explicit BezierPatch(const std::array<Vec3, 16>& controlPoints);

  // Box of the 16 control points (convex hull property), grown by the evaluation's rounding
  // (relative to the patch's extent: points are blended relative to an anchor).
  Box3 bounds() const override { return bounds_; }
  // Longest of the 8 iso control polylines (4 rows, 4 columns). A true bound: an iso curve's
  // control polygon is a convex blend of the rows (or columns), and a Bézier curve is no
  // longer than its control polygon.
  float sizeBound() const override { return sizeBound_; }
  // P and N = dP/du x dP/dv; at poles N is taken from a nudged parameter (patch_math.h).
  SurfacePoint evaluate(float u, float v) const override;
  void dice(int level, Vec3* positions, Vec3* normals) const override;
  const char* kind() const override { return "bezier"; }
  // From bounds on the second derivatives by control-point differences: |P_uu| <= 6 max|D2u|,
  // |P_vv| <= 6 max|D2v|, |P_uv| <= 9 max|DuDv|. Over a micro-quad of side h = 2^-m the
  // bilinear interpolant errs by at most h^2 (|P_uu| + |P_vv|) / 8, and splitting it into two
  // triangles by at most h^2 |P_uv| / 4 more.
  float dicingErrorCoefficient() const override { return errorCoefficient_; }
  // The box of the sub-patch's control points (de Casteljau restriction to the rectangle),
  // grown by its rounding: conservative by the convex hull property.
  Box3 boundsOver(float u0, float u1, float v0, float v1) const override;
  // One restriction of the border curve, halved `split` times (bezier_restriction.h).
  void borderPieceBoundsAt(int sample, int e, int k, uint32_t j, int split, Box3* out) const override;

  const std::array<Vec3, 16>& controlPoints() const { return cp_; }

  // The u-direction curve at a fixed v: its control points and their first and second
  // v-derivatives (relative to the patch's anchor). evaluate(u, v) is pointOnRow(rowAt(v), u,
  // v), bit for bit: callers evaluating many points of one row (dice(), DisplacedPatch::dice())
  // compute the row once.
  struct RowAtV {
    Vec3 q[4];
    Vec3 dq[4];
    Vec3 ddq[4];
  };
  RowAtV rowAt(float v) const;
  SurfacePoint pointOnRow(const RowAtV& row, float u, float v) const;
  // u or v exactly 0 or 1: where a point is the canonical border curve's (see the top).
  static bool onBorder(float u, float v) { return u == 0.0f || u == 1.0f || v == 0.0f || v == 1.0f; }
  // pointOnRow's p alone (the same bits), for callers that need no normal.
  Vec3 positionOnRow(const RowAtV& row, float u, float v) const;
  // The partial derivatives at u on the row; cross(pu, pv) is pointOnRow's normal wherever
  // that normal is not degenerate (where the patch nudges it: poles, collapsed edges). Inline:
  // DisplacedPatch calls it in a loop over a grid row that the compiler vectorises.
  static SurfaceDerivatives derivativesOnRow(const RowAtV& row, float u) {
    float b[4];
    detail::cubicBasis(u, b);
    SurfaceDerivatives d;
    d.pu = detail::cubicDerivative(row.q, u);
    d.pv = detail::bernsteinBlend(row.dq, b);  // as rawNormal()
    d.puu = detail::cubicSecondDerivative(row.q, u);
    d.puv = detail::cubicDerivative(row.dq, u);
    d.pvv = detail::bernsteinBlend(row.ddq, b);
    return d;
  }
  // An interior point (not on a border, where positionOnRow() takes the canonical border
  // curve) from the row and the basis at u: pointOnRow's p there, bit for bit.
  Vec3 interiorPointOnRow(const RowAtV& row, const float b[4]) const { return anchor_ + detail::bernsteinBlend(row.q, b); }
  // The threshold below which pointOnRow() nudges the normal (patch_math.h).
  float degenerateNormalThreshold() const { return tinyNormal_; }

 private:
  static Vec3 rawNormal(const RowAtV& row, const float bu[4], float u);  // dP/du x dP/dv
  Vec3 positionOnRow(const RowAtV& row, const float bu[4], float u, float v) const;
  Vec3 normalAt(float u, float v) const;
  Vec3 borderPoint(float u, float v) const;  // precondition: u or v is exactly 0 or 1

  std::array<Vec3, 16> cp_;
  Vec3 anchor_;                     // the control points' box centre
  std::array<Vec3, 16> local_;      // cp_ - anchor_: blends round at the patch's own scale
  float anchoredMagnitude_ = 0;     // largest |coordinate| of local_
  Box3 bounds_;
  float sizeBound_ = 0;
  float errorCoefficient_ = 0;
  float tinyNormal_ = 0;
};

// Reads a .bpt file: the patch count; per patch one line of 16 one-based comma-separated
// control-point indices (row by row); the point count; one "x,y,z" line per point. Blank lines
// are skipped. Throws InputError(path, "line N", message) for a missing file, a malformed or
// non-finite number, an index out of range, or a count that does not match the content.
std::vector<std::array<Vec3, 16>> loadBezierPatchFile(const std::string& path);

}  // namespace rayes
