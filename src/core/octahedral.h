// Unit vectors packed by the octahedral mapping, at two precisions:
// - 32 bits (2 x 16-bit snorm): the two normals of a ray's hit record (core/ray_batch.h, RayHit),
//   which keeps it at 28 bytes per ray slot. Worst-case angular error about 3e-5 rad.
// - 48 bits (2 x 24-bit snorm, OctahedralCode48): a ray's direction (core/ray_batch.h, Ray): worst
//   case kOctahedral48MaxError = 3.1e-7 rad over the whole sphere (folds and poles included)
//   between decode(encode(d)) and d, of which 2^-24 is the decoded float vector's own rounding
//   (tests/core/octahedral_test.cpp checks it on a dense set and at the edges).
// decode() always returns a unit vector, for every code; a zero, infinite or NaN input encodes
// to +z. Pure functions: thread-safe, O(1).
#pragma once
#include <cmath>
#include <cstdint>
#include "core/vec.h"

namespace rayes {

// The fold of the lower hemisphere onto the octahedron's outer triangles, shared by both
// precisions (its own inverse on the plane: it maps (x, y) with |x| + |y| <= 1 to the square's
// corners and back).
template <class T>
inline void foldOctahedral(T& x, T& y) {
  const T ox = (1 - std::fabs(y)) * std::copysign(T(1), x);
  const T oy = (1 - std::fabs(x)) * std::copysign(T(1), y);
  x = ox; y = oy;
}

inline uint32_t encodeOctahedral(Vec3 n) {
  const float l1 = std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z);
  float x = 0, y = 0;
  if (l1 > 0 && std::isfinite(l1)) {
    x = n.x / l1; y = n.y / l1;
    if (n.z < 0) foldOctahedral(x, y);
  }
  auto q = [](float f) {
    const float c = std::fmax(-1.0f, std::fmin(1.0f, f));
    return static_cast<uint32_t>(static_cast<int32_t>(std::lround(c * 32767.0f)) & 0xffff);
  };
  return q(x) | (q(y) << 16);
}

inline Vec3 decodeOctahedral(uint32_t e) {
  const float x = static_cast<int16_t>(e & 0xffff) / 32767.0f;
  const float y = static_cast<int16_t>(e >> 16) / 32767.0f;
  Vec3 n{x, y, 1.0f - std::fabs(x) - std::fabs(y)};
  if (n.z < 0) foldOctahedral(n.x, n.y);
  const Vec3 u = normalize(n);
  return u.z == 0 && u.x == 0 && u.y == 0 ? Vec3{0, 0, 1} : u;
}

// Two 24-bit snorm coordinates on the octahedron in 48 bits (6 bytes, 2-byte aligned).
struct OctahedralCode48 {
  uint16_t w[3] = {0, 0, 0};  // x in the low 24 bits, y in the high 24; (0, 0): +z
  bool operator==(const OctahedralCode48&) const = default;
};

// The snorm scale: a coordinate c in [-1, 1] is round(c * kOctahedral48Scale).
inline constexpr int32_t kOctahedral48Scale = (1 << 23) - 1;
// Worst-case angle (radians) between a finite nonzero d and decodeOctahedral48(encodeOctahedral48(d)):
// the code's half step 1 / (2 kOctahedral48Scale) moves the octahedron's point by at most sqrt(6)
// of it (x, y and the z = 1 - |x| - |y| they move), which normalising stretches by at most
// sqrt(3) (|p| >= 1/sqrt(3)): 2.53e-7; rounding the unit result to float adds at most 2^-24
// (each component within 2^-24 of itself): 3.1e-7 in all, five times float's own resolution of
// a unit vector.
inline constexpr double kOctahedral48MaxError = 4.2426406871 * 0.5 / kOctahedral48Scale + 5.9604644775e-8;

// Computed in double: the float input is exact there. A direction in a coordinate plane stays in
// it: a zero x or y codes to 0, and on the equator (z = ±0) y's code is what makes |x| + |y|
// exactly 1, so a ray parallel to an axis-aligned surface stays parallel to it, as in float.
inline OctahedralCode48 encodeOctahedral48(Vec3 n) {
  const double ax = n.x, ay = n.y, az = n.z;
  const double l1 = std::fabs(ax) + std::fabs(ay) + std::fabs(az);
  const bool usable = l1 > 0 && std::isfinite(l1);
  double x = 0, y = 0;
  if (usable) {
    x = ax / l1; y = ay / l1;
    if (az < 0) foldOctahedral(x, y);
  }
  // Rounded half away from zero, by hand: std::llround and std::fmin / fmax are library calls here,
  // 0.9 % of a forest-1 render's instructions (bench/history/2026-11.md, "a compact Ray").
  auto q = [](double f) {
    const double c = (f < -1.0 ? -1.0 : f > 1.0 ? 1.0 : f) * kOctahedral48Scale;
    return static_cast<int32_t>(c < 0 ? c - 0.5 : c + 0.5);
  };
  const int32_t qx = q(x);
  int32_t qy = q(y);
  if (usable && az == 0 && y != 0) qy = y < 0 ? -(kOctahedral48Scale - std::abs(qx)) : kOctahedral48Scale - std::abs(qx);
  const uint64_t bits = (uint64_t(uint32_t(qx)) & 0xffffffu) | ((uint64_t(uint32_t(qy)) & 0xffffffu) << 24);
  return {{uint16_t(bits), uint16_t(bits >> 16), uint16_t(bits >> 32)}};
}

// In integers up to the normalisation: the point (x, y, z) * kOctahedral48Scale is exact, so a
// zero coordinate decodes to exactly zero. Every code decodes to a finite unit vector.
inline Vec3 decodeOctahedral48(OctahedralCode48 e) {
  const uint64_t bits = uint64_t(e.w[0]) | (uint64_t(e.w[1]) << 16) | (uint64_t(e.w[2]) << 32);
  auto signExtend = [](uint64_t v) { return int32_t(uint32_t(v << 8)) >> 8; };  // 24 -> 32 bits
  const int32_t s = kOctahedral48Scale;
  int32_t x = signExtend(bits & 0xffffffu), y = signExtend(bits >> 24);
  const int32_t ax = std::abs(x), ay = std::abs(y);
  const int32_t z = s - ax - ay;  // >= -s - 2: |x|, |y| <= s + 1 for every code
  if (z < 0) {
    x = x < 0 ? -(s - ay) : s - ay;
    y = y < 0 ? -(s - ax) : s - ax;
  }
  const double dx = x, dy = y, dz = z;
  // The l1 norm of the point is s (up to 2 more for codes outside [-s, s]): its l2 norm >= s/sqrt(3).
  const double inv = 1.0 / std::sqrt(dx * dx + dy * dy + dz * dz);
  return {float(dx * inv), float(dy * inv), float(dz * inv)};
}

}  // namespace rayes
