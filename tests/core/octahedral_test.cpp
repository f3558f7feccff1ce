// A ray's compact record (core/ray_batch.h, Ray) keeps its direction as a 48-bit octahedral code
// and its cone's spread as a half. Every direction, on a dense set over the sphere and at the
// code's edges (axes, signed zeros, the fold |x| + |y| = 1, the poles, one ulp from an axis),
// decodes within kOctahedral48MaxError of itself; a direction in a coordinate plane stays in it.
// The halves keep core/half.h's bound and clamp at its ends. Ray::aim rescales tmax and the
// spread by |d|, finite for |d| from 1e-20 to 1e20.
#include <bit>
#include <cfloat>
#include <cmath>
#include <limits>
#include <gtest/gtest.h>
#include "core/half.h"
#include "core/octahedral.h"
#include "core/ray_batch.h"

namespace rayes {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// The angle between d (any length) and u, in double, well conditioned near zero.
double angleBetween(Vec3 d, Vec3 u) {
  const double a[3] = {d.x, d.y, d.z}, b[3] = {u.x, u.y, u.z};
  const double cx = a[1] * b[2] - a[2] * b[1], cy = a[2] * b[0] - a[0] * b[2], cz = a[0] * b[1] - a[1] * b[0];
  return std::atan2(std::sqrt(cx * cx + cy * cy + cz * cz), a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
}

double decodedLength(Vec3 u) { return std::sqrt(double(u.x) * u.x + double(u.y) * u.y + double(u.z) * u.z); }

// Checks one direction; returns its error.
double roundTripError(Vec3 d) {
  const Vec3 u = decodeOctahedral48(encodeOctahedral48(d));
  EXPECT_NEAR(decodedLength(u), 1.0, 2 * FLT_EPSILON) << d.x << " " << d.y << " " << d.z;
  const double e = angleBetween(d, u);
  EXPECT_LE(e, kOctahedral48MaxError) << d.x << " " << d.y << " " << d.z;
  return e;
}

TEST(Octahedral48, EveryDirectionOfADenseSetDecodesWithinTheBound) {
  // 2048 x 1024 directions by latitude and longitude (the poles and the equator included), and
  // the same count spread over the octahedron's square, which is denser near the folds.
  double worst = 0;
  for (int i = 0; i <= 1024; ++i) {
    const double theta = M_PI * i / 1024;
    for (int j = 0; j < 2048; ++j) {
      const double phi = 2 * M_PI * j / 2048;
      worst = std::max(worst, roundTripError(Vec3{float(std::sin(theta) * std::cos(phi)),
                                                  float(std::sin(theta) * std::sin(phi)), float(std::cos(theta))}));
    }
  }
  for (int i = 0; i <= 1448; ++i) {
    for (int j = 0; j <= 1448; ++j) {
      const float x = -1 + 2 * float(i) / 1448, y = -1 + 2 * float(j) / 1448;
      Vec3 p{x, y, 1 - std::fabs(x) - std::fabs(y)};
      if (p.z < 0) {
        p.x = (1 - std::fabs(y)) * std::copysign(1.0f, x);
        p.y = (1 - std::fabs(x)) * std::copysign(1.0f, y);
      }
      if (p.x != 0 || p.y != 0 || p.z != 0) worst = std::max(worst, roundTripError(p));
    }
  }
  // The bound is reached to within a factor of two (it is not loose), never exceeded.
  EXPECT_GT(worst, 0.5 * kOctahedral48MaxError);
  EXPECT_LE(worst, kOctahedral48MaxError);
}

TEST(Octahedral48, AxesAndSignedZerosDecodeExactly) {
  for (float a : {1.0f, -1.0f})
    for (float z0 : {0.0f, -0.0f}) {
      EXPECT_EQ(decodeOctahedral48(encodeOctahedral48({a, z0, z0})), (Vec3{a, 0, 0}));
      EXPECT_EQ(decodeOctahedral48(encodeOctahedral48({z0, a, z0})), (Vec3{0, a, 0}));
      EXPECT_EQ(decodeOctahedral48(encodeOctahedral48({z0, z0, a})), (Vec3{0, 0, a}));
      EXPECT_EQ(decodeOctahedral48(encodeOctahedral48({z0, a * 1e-30f, a})), (Vec3{0, 0, a}));
    }
}

// On the fold (z = ±0, |x| + |y| = 1) and beside it, near the poles, and one ulp from each axis.
TEST(Octahedral48, TheFoldThePolesAndDirectionsOneUlpFromAnAxisStayWithinTheBound) {
  for (int k = 0; k <= 4096; ++k) {
    const float x = -1 + 2 * float(k) / 4096, y = 1 - std::fabs(x);
    for (float sy : {1.0f, -1.0f})
      for (float z : {0.0f, -0.0f, 1e-7f, -1e-7f, 1e-30f, -1e-30f}) roundTripError({x, sy * y, z});
  }
  const float tiny[] = {FLT_TRUE_MIN, FLT_MIN, 1e-20f, FLT_EPSILON / 2, FLT_EPSILON};
  for (float t : tiny)
    for (float s : {1.0f, -1.0f}) {
      for (float a : {1.0f, -1.0f, std::nextafter(1.0f, 0.0f), -std::nextafter(1.0f, 0.0f)}) {
        roundTripError({a, s * t, 0});
        roundTripError({a, 0, s * t});
        roundTripError({s * t, a, 0});
        roundTripError({0, a, s * t});
        roundTripError({s * t, 0, a});
        roundTripError({s * t, s * t, a});
      }
    }
}

// A direction in a coordinate plane decodes in it, so a ray parallel to an axis-aligned surface
// does not drift into it (a grazing ray along a floor stays above it).
TEST(Octahedral48, DirectionsInACoordinatePlaneStayInIt) {
  for (int k = 1; k < 1000; ++k) {
    const float a = std::cos(6.2831853f * k / 1000), b = std::sin(6.2831853f * k / 1000);
    EXPECT_EQ(decodeOctahedral48(encodeOctahedral48({a, b, 0})).z, 0.0f) << k;
    EXPECT_EQ(decodeOctahedral48(encodeOctahedral48({a, 0, b})).y, 0.0f) << k;
    EXPECT_EQ(decodeOctahedral48(encodeOctahedral48({0, a, b})).x, 0.0f) << k;
  }
}

// The code of the 24-bit coordinates x and y, whatever they are.
OctahedralCode48 codeOf(int32_t x, int32_t y) {
  const uint64_t bits = (uint64_t(uint32_t(x)) & 0xffffffu) | ((uint64_t(uint32_t(y)) & 0xffffffu) << 24);
  return {{uint16_t(bits), uint16_t(bits >> 16), uint16_t(bits >> 32)}};
}

TEST(Octahedral48, EveryCodeDecodesToAFiniteUnitVectorAndBadInputToPlusZ) {
  const int32_t s = kOctahedral48Scale;
  const int32_t edges[] = {-s - 1, -s, -s / 2, -1, 0, 1, s / 2 + 1, s};
  for (int32_t x : edges)
    for (int32_t y : edges) {
      const Vec3 u = decodeOctahedral48(codeOf(x, y));
      EXPECT_TRUE(std::isfinite(u.x) && std::isfinite(u.y) && std::isfinite(u.z));
      EXPECT_NEAR(decodedLength(u), 1.0, 2 * FLT_EPSILON);
    }
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (Vec3 bad : {Vec3{0, 0, 0}, Vec3{kInf, 0, 0}, Vec3{nan, 1, 0}})
    EXPECT_EQ(decodeOctahedral48(encodeOctahedral48(bad)), (Vec3{0, 0, 1}));
}

TEST(Half, KeepsItsRelativeBoundInRangeAndItsAbsoluteBoundBelow) {
  for (float v = 6.103515625e-05f; v <= kHalfMax; v *= 1.0001f)
    for (float s : {1.0f, -1.0f}) EXPECT_LE(std::fabs(decodeHalf(encodeHalf(s * v)) - s * v), std::ldexp(v, -11)) << v;
  for (float v = 1e-12f; v < 6.103515625e-05f; v *= 1.001f)
    EXPECT_LE(std::fabs(decodeHalf(encodeHalf(v)) - v), std::ldexp(1.0f, -25)) << v;
}

TEST(Half, EveryCodeDecodesAsTheCompilersHalfDoes) {
  for (uint32_t c = 0; c < 65536; ++c) {
    const float mine = decodeHalf(uint16_t(c)), ref = static_cast<float>(std::bit_cast<_Float16>(uint16_t(c)));
    if (std::isnan(ref))
      EXPECT_TRUE(std::isnan(mine)) << c;
    else
      EXPECT_EQ(std::bit_cast<uint32_t>(mine), std::bit_cast<uint32_t>(ref)) << c;
  }
}

// Every rounding case of encodeHalf against the compiler's conversion: each float in the half's
// range (every sign, exponent and upper mantissa) with the 13 bits a half drops at their edges
// (exact, just above, just below, exactly and around a tie) and a pseudo-random middle.
TEST(Half, EncodesEveryRoundingCaseAsTheCompilersHalfDoes) {
  uint32_t lcg = 12345;
  for (uint32_t upper = 0; upper < (1u << 19); ++upper) {
    lcg = lcg * 1664525u + 1013904223u;
    for (uint32_t low : {0u, 1u, 0xfffu, 0x1000u, 0x1001u, 0x1fffu, lcg >> 19}) {
      const float v = std::bit_cast<float>((upper << 13) | low);
      if (!(std::fabs(v) <= kHalfMax)) continue;
      ASSERT_EQ(encodeHalf(v), std::bit_cast<uint16_t>(static_cast<_Float16>(v))) << std::hexfloat << v;
    }
  }
}

TEST(Half, RangeEndsAreExactOrClampedAndNeverInfinite) {
  EXPECT_EQ(decodeHalf(encodeHalf(0.0f)), 0.0f);
  EXPECT_TRUE(std::signbit(decodeHalf(encodeHalf(-0.0f))));
  EXPECT_EQ(decodeHalf(encodeHalf(std::ldexp(1.0f, -24))), std::ldexp(1.0f, -24));  // the least subnormal
  EXPECT_EQ(decodeHalf(encodeHalf(std::ldexp(1.0f, -26))), 0.0f);                   // below half of it
  EXPECT_EQ(decodeHalf(encodeHalf(kHalfMax)), kHalfMax);
  for (float big : {65520.0f, 1e30f, kInf}) {
    EXPECT_EQ(decodeHalf(encodeHalf(big)), kHalfMax) << big;
    EXPECT_EQ(decodeHalf(encodeHalf(-big)), -kHalfMax) << big;
  }
  EXPECT_EQ(decodeHalf(encodeHalf(std::numeric_limits<float>::quiet_NaN())), 0.0f);
}

// t and the spread are per unit of the direction aimed; the record keeps them per unit of
// distance along its unit direction.
TEST(Ray, AimRescalesTmaxAndTheSpreadByTheDirectionsLength) {
  Ray r;
  r.aim({0, 0, 2}, 3, 0.3f, 0.5f);
  EXPECT_EQ(r.dir(), (Vec3{0, 0, 1}));
  EXPECT_EQ(r.tmax, 6.0f);
  EXPECT_EQ(r.coneWidth, 0.3f);  // a length, kept as a float
  EXPECT_EQ(r.coneSpread(), 0.25f);
  r.aim({0, -4, 0}, kInf, 0, -0.5f);  // a cone narrowing toward a focus keeps its sign
  EXPECT_EQ(r.tmax, kInf);
  EXPECT_EQ(r.coneSpread(), -0.125f);
  EXPECT_EQ(Ray::traced({0, -4, 0}), r.dir());
}

TEST(Ray, TinyAndHugeDirectionsStayFinite) {
  Ray r;
  r.aim({1e-20f, 0, 0}, 1e20f, 1e-3f, 1e-3f);
  EXPECT_EQ(r.dir(), (Vec3{1, 0, 0}));
  EXPECT_FLOAT_EQ(r.tmax, 1.0f);
  EXPECT_EQ(r.coneSpread(), kHalfMax);  // 1e17 per unit distance: clamped, not infinite
  r.aim({1e20f, 1e20f, 0}, 1e-20f, 0, 1e-3f);
  EXPECT_NEAR(angleBetween({1, 1, 0}, r.dir()), 0, kOctahedral48MaxError);
  EXPECT_FLOAT_EQ(r.tmax, std::sqrt(2.0f));
  EXPECT_EQ(r.coneSpread(), 0.0f);  // 7e-24: below half the least subnormal
  EXPECT_TRUE(std::isfinite(r.tmax));
  // |d| = 1e-20 is still a direction; a zero or non-finite one traces nothing.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (Vec3 bad : {Vec3{0, 0, 0}, Vec3{kInf, 1, 0}, Vec3{nan, 0, 1}}) {
    r.aim(bad, kInf, 0, 0);
    EXPECT_EQ(r.tmax, 0.0f);
    EXPECT_EQ(r.dir(), (Vec3{0, 0, 1}));
    EXPECT_EQ(Ray::traced(bad), (Vec3{0, 0, 0}));
  }
}

// A shadow ray to a point 10^4 units away, aimed with the unnormalised segment and tmax 1 (as a
// shadow segment is): its end lies within the code's bound of the point, plus the roundings of
// the point's coordinates (a few ulps of 10^4).
TEST(Ray, AShadowRayToAFarPointEndsWithinTheBoundOfIt) {
  const Vec3 o{0.3f, -2.7f, 1.1f};
  double worst = 0;
  for (int k = 0; k < 10000; ++k) {
    const float a = 6.2831853f * float(k) / 10000, b = 0.7f * std::sin(float(k));
    const Vec3 target = o + Vec3{std::cos(a) * std::cos(b), std::sin(a) * std::cos(b), std::sin(b)} * 1e4f;
    RayBatch rays;
    rays.resize(1);
    rays.setFromNowhere(0, RayKind::Shadow, o, target - o, 1.0f, 0, 0);
    const Ray& r = rays.ray[0];
    const Vec3 end = r.org + r.dir() * r.tmax;
    const double miss = length(end - target);
    // The code's angle over 10^4 (3.1e-3), and 4 ulps of 10^4 (2^-10 each): tmax's rounding,
    // the end's three components' products and sums, the segment's own rounding.
    const double bound = kOctahedral48MaxError * 1e4 + 4 * std::ldexp(1.0, -10);
    EXPECT_LE(miss, bound) << k;
    worst = std::max(worst, miss);
  }
  EXPECT_GT(worst, 0.0);
}

}  // namespace
}  // namespace rayes
