#include "geometry/bilinear_patch.h"
#include <array>
#include <cmath>
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
  if (!coplanarUpToRounding(p00, p10, p01, p11)) errorCoefficient_ = 0.25f * length(p00 - p10 - p01 + p11);
}

// Planarity: with a = p10 - p00, b = p01 - p00, c = p11 - p00 the corners are coplanar iff the
// triple product T = c . (a x b) is 0. Corners written as decimals (a trapezoidal floor) come
// out of float rounding with each coordinate moved by at most u M (u = 2^-24, M the largest
// corner coordinate), so a, b, c each move by at most 2 u M per coordinate, 2 sqrt(3) u M in
// length, and to first order |dT| <= 2 sqrt(3) u M (|a||b| + |b||c| + |c||a|). T is computed in
// double (its own rounding is ~2^-29 of that), and the bound is doubled for the second-order
// terms. A quad within it is planar up to rounding; whatever non-planarity is left is of the
// size of the rounding of the diced points, which the secondary-ray offset already covers.
bool BilinearPatch::coplanarUpToRounding(Vec3 p00, Vec3 p10, Vec3 p01, Vec3 p11) {
  auto d = [](Vec3 q, Vec3 o) { return std::array<double, 3>{double(q.x) - o.x, double(q.y) - o.y, double(q.z) - o.z}; };
  auto len = [](const std::array<double, 3>& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); };
  const auto a = d(p10, p00), b = d(p01, p00), c = d(p11, p00);
  const double triple = c[0] * (a[1] * b[2] - a[2] * b[1]) + c[1] * (a[2] * b[0] - a[0] * b[2]) +
                        c[2] * (a[0] * b[1] - a[1] * b[0]);
  double m = 0;
  for (Vec3 p : {p00, p10, p01, p11}) m = std::max(m, double(maxComponent(vabs(p))));
  const double u = std::ldexp(1.0, -24);
  const double tolerance = 4 * std::sqrt(3.0) * u * m * (len(a) * len(b) + len(b) * len(c) + len(c) * len(a));
  return std::fabs(triple) <= tolerance;
}

Vec3 BilinearPatch::normalAt(float u, float v) const {
  const SurfaceDerivatives d = derivatives(u, v);
  return cross(d.pu, d.pv);
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
