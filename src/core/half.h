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

// Rounds to nearest even, as _Float16's conversion does (tests/core/octahedral_test.cpp checks
// every rounding case against it), by hand: without F16C the compiler's conversion and
// std::fmin / fmax are library calls, 0.7 % of a forest-1 render's instructions (bench/history/
// 2026-11.md, "session 9, lead"). The float's own rounding does the work: below 2^-14 adding 0.5
// leaves the half's subnormal step (2^-24) as the last bit; above, the exponent is rebiased and
// the 13 dropped bits rounded by adding 0xfff plus the kept mantissa's lowest bit.
inline uint16_t encodeHalf(float v) {
  const float c = v != v ? 0.0f : v < -kHalfMax ? -kHalfMax : v > kHalfMax ? kHalfMax : v;
  const uint32_t f = std::bit_cast<uint32_t>(c), sign = (f >> 16) & 0x8000u, magnitude = f & 0x7fffffffu;
  uint32_t h;
  if (magnitude < 0x38800000u) {  // below 2^-14: a subnormal half or zero
    h = std::bit_cast<uint32_t>(std::bit_cast<float>(magnitude) + 0.5f) - 0x3f000000u;
  } else {
    h = (magnitude + 0xc8000fffu + ((magnitude >> 13) & 1u)) >> 13;  // 0xc8000000: (15 - 127) << 23
  }
  return uint16_t(h | sign);
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
