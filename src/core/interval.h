// Interval arithmetic with outward rounding: every operation returns an interval that contains
// the exact result for every choice of operands inside its operand intervals. Each endpoint is
// computed in float (round to nearest, so off by at most half an ulp) and then moved one ulp
// outward (nextFloatDown/Up, std::nextafter's results inline), which makes the result conservative without touching the FPU's
// rounding mode (the rest of the program must keep round-to-nearest for bit-identical images).
//
// Used by displacement bounds (geometry/displacement.h): the range of a noise function or a
// height map over a parameter box, times the range of the normal, added to a position box.
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>
#include "core/next_float.h"

namespace rayes {

struct Interval {
  float lo = 0, hi = 0;

  constexpr Interval() = default;
  constexpr Interval(float v) : lo(v), hi(v) {}  // NOLINT: a point is an interval
  constexpr Interval(float a, float b) : lo(a), hi(b) {}

  static Interval everything() {
    return {-std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity()};
  }
  bool empty() const { return !(lo <= hi); }
  bool contains(float x) const { return x >= lo && x <= hi; }
  bool contains(const Interval& o) const { return o.lo >= lo && o.hi <= hi; }
  float width() const { return hi - lo; }
  float mid() const { return 0.5f * lo + 0.5f * hi; }
  float magnitude() const { return std::max(std::fabs(lo), std::fabs(hi)); }  // max |x|
};

// One ulp outward (the identity on infinities; NaN stays NaN and makes the caller's checks fail).
inline float roundDown(float x) { return nextFloatDown(x); }
inline float roundUp(float x) { return nextFloatUp(x); }

// Widens by an absolute margin (rounded outward too).
inline Interval widened(Interval a, float margin) { return {roundDown(a.lo - margin), roundUp(a.hi + margin)}; }

inline Interval hull(Interval a, Interval b) { return {std::min(a.lo, b.lo), std::max(a.hi, b.hi)}; }
inline Interval hull(Interval a, float x) { return {std::min(a.lo, x), std::max(a.hi, x)}; }
// Intersection; empty() when disjoint.
inline Interval intersect(Interval a, Interval b) { return {std::max(a.lo, b.lo), std::min(a.hi, b.hi)}; }

inline Interval operator-(Interval a) { return {-a.hi, -a.lo}; }  // exact
inline Interval operator+(Interval a, Interval b) { return {roundDown(a.lo + b.lo), roundUp(a.hi + b.hi)}; }
inline Interval operator-(Interval a, Interval b) { return {roundDown(a.lo - b.hi), roundUp(a.hi - b.lo)}; }
inline Interval operator*(Interval a, Interval b) {
  const float p[4] = {a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi};
  float lo = p[0], hi = p[0];
  for (float x : p) {
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  }
  // 0 * inf is NaN: an infinite operand times an interval touching zero is everything.
  for (float x : p)
    if (std::isnan(x)) return Interval::everything();
  return {roundDown(lo), roundUp(hi)};
}
inline Interval& operator+=(Interval& a, Interval b) { a = a + b; return a; }

// |x| over the interval: exact.
inline Interval abs(Interval a) {
  if (a.lo >= 0) return a;
  if (a.hi <= 0) return -a;
  return {0.0f, std::max(-a.lo, a.hi)};
}

}  // namespace rayes
