// Level-of-detail rules (declared in dice_buffer.h). Integer and exact power-of-two arithmetic
// only, so the choice has no rounding surprises and every input has a defined result.
#include <cmath>
#include "dicing/dice_buffer.h"

namespace rayes {

int levelForFootprint(float patchSize, float footprintWidth, int maxLevel) {
  if (maxLevel <= 0) return 0;
  if (patchSize <= 0.0f) return 0;
  if (!std::isfinite(patchSize)) return maxLevel;
  if (!(footprintWidth > 0.0f) || !std::isfinite(footprintWidth)) return maxLevel;
  // ldexp is exact (or +inf), so this is the exact smallest m with size <= width * 2^m.
  for (int m = 0; m < maxLevel; ++m)
    if (patchSize <= std::ldexp(footprintWidth, m)) return m;
  return maxLevel;
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
