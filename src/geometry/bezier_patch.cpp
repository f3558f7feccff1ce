#include "geometry/bezier_patch.h"
#include <algorithm>
#include "geometry/bezier_restriction.h"
#include "geometry/patch_math.h"

namespace rayes {

using detail::canonicalCubic;
using detail::cubicBasis;
using detail::bernsteinBlend;

BezierPatch::BezierPatch(const std::array<Vec3, 16>& controlPoints) : cp_(controlPoints) {
  Box3 box;
  for (const Vec3& p : cp_) box.extend(p);
  // Blends run on control points relative to the box centre (docs/design.md, "Precision").
  anchor_ = box.center();
  float anchored = 0;
  for (int i = 0; i < 16; ++i) {
    local_[size_t(i)] = cp_[size_t(i)] - anchor_;
    anchored = std::max(anchored, maxComponent(vabs(local_[size_t(i)])));
  }
  anchoredMagnitude_ = anchored;
  // The true surface lies in the control points' box (convex hull); a diced vertex lies
  // within its evaluation error of the true surface.
  bounds_ = box.grownBy(detail::anchoredEvaluationError(anchored));
  float longest = 0;
  for (int r = 0; r < 4; ++r) {
    float row = 0, col = 0;
    for (int k = 0; k < 3; ++k) {
      row += length(cp_[r * 4 + k + 1] - cp_[r * 4 + k]);
      col += length(cp_[(k + 1) * 4 + r] - cp_[k * 4 + r]);
    }
    longest = std::max(longest, std::max(row, col));
  }
  sizeBound_ = longest;
  float d2u = 0, d2v = 0, duv = 0;
  for (int a = 0; a < 4; ++a)
    for (int k = 0; k < 2; ++k) {
      d2u = std::max(d2u, length(cp_[a * 4 + k] - 2.0f * cp_[a * 4 + k + 1] + cp_[a * 4 + k + 2]));
      d2v = std::max(d2v, length(cp_[k * 4 + a] - 2.0f * cp_[(k + 1) * 4 + a] + cp_[(k + 2) * 4 + a]));
    }
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i)
      duv = std::max(duv, length(cp_[(j + 1) * 4 + i + 1] - cp_[(j + 1) * 4 + i] - cp_[j * 4 + i + 1] + cp_[j * 4 + i]));
  errorCoefficient_ = (6.0f * d2u + 6.0f * d2v) / 8.0f + 9.0f * duv / 4.0f;
  tinyNormal_ = detail::degenerateNormalThreshold(box.longestSide());
}

BezierPatch::RowAtV BezierPatch::rowAt(float v) const {
  float b[4];
  cubicBasis(v, b);
  RowAtV row;
  for (int i = 0; i < 4; ++i) {
    const Vec3 column[4] = {local_[i], local_[4 + i], local_[8 + i], local_[12 + i]};
    row.q[i] = bernsteinBlend(column, b);
    row.dq[i] = detail::cubicDerivative(column, v);
    row.ddq[i] = detail::cubicSecondDerivative(column, v);
  }
  return row;
}

Vec3 BezierPatch::rawNormal(const RowAtV& row, const float b[4], float u) {
  const Vec3 du = detail::cubicDerivative(row.q, u);
  return cross(du, bernsteinBlend(row.dq, b));
}

Vec3 BezierPatch::normalAt(float u, float v) const {
  float b[4];
  cubicBasis(u, b);
  return rawNormal(rowAt(v), b, u);
}

Vec3 BezierPatch::borderPoint(float u, float v) const {
  if (v == 0.0f) return canonicalCubic(cp_[0], cp_[1], cp_[2], cp_[3], u);
  if (v == 1.0f) return canonicalCubic(cp_[12], cp_[13], cp_[14], cp_[15], u);
  if (u == 0.0f) return canonicalCubic(cp_[0], cp_[4], cp_[8], cp_[12], v);
  return canonicalCubic(cp_[3], cp_[7], cp_[11], cp_[15], v);
}

inline Vec3 BezierPatch::positionOnRow(const RowAtV& row, const float b[4], float u, float v) const {
  return onBorder(u, v) ? borderPoint(u, v) : interiorPointOnRow(row, b);
}

Vec3 BezierPatch::positionOnRow(const RowAtV& row, float u, float v) const {
  float b[4];
  cubicBasis(u, b);
  return positionOnRow(row, b, u, v);
}

SurfacePoint BezierPatch::pointOnRow(const RowAtV& row, float u, float v) const {
  float b[4];
  cubicBasis(u, b);
  SurfacePoint sp;
  sp.p = positionOnRow(row, b, u, v);
  sp.n = detail::nonDegenerateNormal([this](float uu, float vv) { return normalAt(uu, vv); },
                                     rawNormal(row, b, u), u, v, tinyNormal_);
  return sp;
}

SurfacePoint BezierPatch::evaluate(float u, float v) const { return pointOnRow(rowAt(v), u, v); }

// Same operations as evaluate() per vertex, with the v-reduction hoisted out of each row.
void BezierPatch::dice(int level, Vec3* positions, Vec3* normals) const {
  const int n = 1 << level;
  const float fn = float(n);
  for (int j = 0; j <= n; ++j) {
    const float v = float(j) / fn;
    const RowAtV row = rowAt(v);
    for (int i = 0; i <= n; ++i) {
      const SurfacePoint sp = pointOnRow(row, float(i) / fn, v);
      positions[size_t(j) * (n + 1) + i] = sp.p;
      normals[size_t(j) * (n + 1) + i] = sp.n;
    }
  }
}


Box3 BezierPatch::boundsOver(float u0, float u1, float v0, float v1) const {
  // Rounding is monotonic, so the anchored box translated is the box of the translated points.
  const Box3 local = detail::restrictedHull<4, 4>(local_.data(), u0, u1, v0, v1);
  const Box3 box{anchor_ + local.lo, anchor_ + local.hi};
  // Each restriction is two de Casteljau splits of 3 levels, 3 roundings per level on values
  // within the anchored hull, plus the rounded split parameter (b - a) / (1 - a): at most 24
  // roundings of the anchored magnitude per direction, 48 for both; the diced vertices this
  // box must also hold add their own evaluation error.
  return box.grownBy(gammaBound(48) * anchoredMagnitude_ + detail::anchoredEvaluationError(anchoredMagnitude_));
}

void BezierPatch::borderPieceBoundsAt(int, int e, int k, uint32_t j, int split, Box3* out) const {
  Vec3 curve[4];
  const int n = detail::borderCurve<4, 4>(local_.data(), e, curve);
  const float inv = 1.0f / float(1u << k);  // a power of two: the segment's ends are exact
  detail::borderPieceHulls(curve, n, float(j) * inv, float(j + 1) * inv, split, out);
  // As boundsOver: the anchored hull's rounding, and the diced vertices' evaluation error.
  const float pad = gammaBound(detail::borderPieceRoundings(split)) * anchoredMagnitude_ +
                    detail::anchoredEvaluationError(anchoredMagnitude_);
  for (uint32_t i = 0; i < (1u << split); ++i) out[i] = Box3{anchor_ + out[i].lo, anchor_ + out[i].hi}.grownBy(pad);
}

}  // namespace rayes

