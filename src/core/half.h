// Floats stored in 16 bits (IEEE binary16, the compiler's _Float16: conversions round to nearest
// even), for a ray's cone spread (core/ray_batch.h, Ray), where a footprint needs a few
// significant digits and no more. The bound: |v| in [2^-14, 65504] keeps a relative error of at
// most 2^-11; below 2^-14 (subnormal halves) an absolute error of at most 2^-25; above 65504 the
// value is clamped to ±65504 (never infinity); NaN stores 0. Pure functions: thread-safe, O(1).
#pragma once
#include <bit>
#include <cmath>
#include <cstdint>

namespace rayes {

inline constexpr float kHalfMax = 65504.0f;

inline uint16_t encodeHalf(float v) {
  const float c = std::isnan(v) ? 0.0f : std::fmax(-kHalfMax, std::fmin(kHalfMax, v));
  return std::bit_cast<uint16_t>(static_cast<_Float16>(c));
}

inline float decodeHalf(uint16_t bits) { return static_cast<float>(std::bit_cast<_Float16>(bits)); }

}  // namespace rayes
