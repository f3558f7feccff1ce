// Level-of-detail rules (declared in dice_buffer.h). Integer and exact power-of-two arithmetic
// only, so the choice has no rounding surprises and every input has a defined result.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include "dicing/dice_buffer.h"

namespace rayes {

int levelForFootprint(float patchSize, float footprintWidth, int maxLevel) {
  if (maxLevel <= 0) return 0;
  if (patchSize <= 0.0f) return 0;
  if (!std::isfinite(patchSize)) return maxLevel;
  if (!(footprintWidth > 0.0f) || !std::isfinite(footprintWidth)) return maxLevel;
  // Doubling is exact (or +inf, and stays so), so w = width * 2^m exactly, as ldexp would give,
  // and this is the exact smallest m with size <= width * 2^m. (Not ldexp: a libm call per
  // level was 3 % of a displaced-terrain render.)
  float w = footprintWidth;
  for (int m = 0; m < maxLevel; ++m, w += w)
    if (patchSize <= w) return m;
  return maxLevel;
}

int levelForDicingError(float patchSize, float errorCoefficient, int maxLevel) {
  if (maxLevel <= 0 || !(errorCoefficient > 0.0f)) return 0;
  if (!std::isfinite(errorCoefficient)) return maxLevel;
  if (!(patchSize > 0.0f)) return maxLevel;  // no size to be small against
  // In double: the tolerance cannot underflow, and quartering a float's C is exact there.
  const double tolerance = double(patchSize) * kRelativeDicingError;
  double error = errorCoefficient;
  for (int m = 0; m < maxLevel; ++m, error *= 0.25)
    if (error <= tolerance) return m;
  return maxLevel;
}

int floorAtDistance(int floorAtSize, float patchSize, float distance) {
  if (!(patchSize > 0.0f) || !std::isfinite(patchSize)) return std::max(floorAtSize, 0);
  // 4 * reach is exact (or +inf, which no finite distance reaches), so k is the exact largest
  // k <= floorAtSize with patchSize * 4^k <= distance.
  int level = floorAtSize;
  for (float reach = patchSize; level > 0 && 4.0f * reach <= distance; reach *= 4.0f) --level;
  return std::max(level, 0);
}

int biasedLevel(int level, int bias, int maxLevel) {
  // In int64 so no bias can overflow; the clamp keeps the result a level the buffer holds.
  return int(std::clamp<int64_t>(int64_t(level) + bias, 0, std::max(maxLevel, 0)));
}

int levelForDensity(uint64_t rays, int spp, int maxLevel) {
  if (maxLevel <= 0) return 0;
  const uint64_t perPixel = spp > 0 ? uint64_t(spp) : 1;
  // 4^m >= rays / spp  <=>  4^m >= ceil(rays / spp), for integer 4^m.
  const uint64_t need = rays / perPixel + (rays % perPixel != 0);
  for (int m = 0; m < maxLevel; ++m)
    if (m >= 32 || (uint64_t(1) << (2 * m)) >= need) return m;  // 4^32 exceeds any uint64
  return maxLevel;
}

}  // namespace rayes
