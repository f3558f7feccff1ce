#include "shading/ray_spawning.h"
#include <algorithm>
#include <cmath>
#include <limits>
#include "core/box.h"

namespace rayes {

// The offset is a bound, not a guess: how far the origin may lie on the wrong side of the
// surface it leaves, along the geometric normal.
//   Dicing: the micro-triangle hit at level m lies within C / 4^m of the true surface
//   (Patch::dicingErrorCoefficient; 0 for planar patches). The ray sees its own leaf at that
//   same level, but neighbours and emitters are the true surface diced at their own levels.
//   Rounding: p = o + t d with t from the watertight test. Its sheared-space t is a sum of the
//   vertices' distances along the ray weighted by non-negative barycentrics, so t |d| is off by
//   a few gamma of |p - o| + side; the vertices themselves are evaluations off the surface by
//   a few gamma of |p| + side; o + t d rounds by u (|o| + |p|). With |p - o| <= |p| + |o| (and
//   sqrt 3 between the norms) all of it is below gamma(32) (|p| + |o| + side), max norms.
// Computed in double so no input overflows on the way; an infinite or NaN C (a broken patch)
// falls back to the rounding term; the result is clamped to the largest float.
float originOffset(float side, float errorCoefficient, int level, Vec3 p, Vec3 from) {
  const double dicing = double(errorCoefficient) * std::ldexp(1.0, -2 * level);  // C / 4^level
  const double magnitude = double(maxComponent(vabs(p))) + double(maxComponent(vabs(from))) + double(side);
  const double rounding = double(gammaBound(32)) * magnitude + double(std::numeric_limits<float>::min());
  const double offset = std::isfinite(dicing) ? dicing + rounding : rounding;
  return float(std::min(offset, double(std::numeric_limits<float>::max())));
}

float spreadAfterBounce(float incoming, float pdf, bool delta) {
  if (delta) return incoming;
  const float lobe = pdf > 0 ? std::sqrt(1.0f / pdf) : kDiffuseSpread;
  return std::max(incoming, std::min(kDiffuseSpread, lobe));
}

}  // namespace rayes
