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

// Exact (every half is a float), by hand: without F16C the compiler's conversion is a library call
// (0.4 % of a forest-1 render's instructions: bench/history/2026-11.md, "a compact Ray").
// tests/core/octahedral_test.cpp checks all 65536 codes against _Float16's.
inline float decodeHalf(uint16_t bits) {
  const uint32_t sign = uint32_t(bits & 0x8000u) << 16, exponent = (bits >> 10) & 0x1fu, mantissa = bits & 0x3ffu;
  if (exponent == 0) {  // zero or subnormal: mantissa * 2^-24, exact in float
    const float m = float(mantissa) * 5.9604644775390625e-08f;
    return std::bit_cast<float>(std::bit_cast<uint32_t>(m) | sign);
  }
  if (exponent == 31) return std::bit_cast<float>(sign | 0x7f800000u | (mantissa << 13));  // never stored: encodeHalf clamps
  return std::bit_cast<float>(sign | ((exponent + 112) << 23) | (mantissa << 13));
}

}  // namespace rayes
