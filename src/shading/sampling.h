// Warping functions from [0,1)^2 to directions. Each returns a finite result for every input
// in [0,1)^2 (tests/shading checks the edges u = 0 and u -> 1).
#pragma once
#include <cmath>
#include <numbers>
#include "core/disk_mapping.h"
#include "core/vec.h"

namespace rayes {

// Cosine-weighted direction about +z (Malley's method); pdf = cos(theta) / pi.
inline Vec3 sampleCosineHemisphere(float u1, float u2) {
  const float r = std::sqrt(std::max(0.0f, u1));
  const float phi = 2.0f * std::numbers::pi_v<float> * u2;
  const float z = std::sqrt(std::max(0.0f, 1.0f - u1));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// concentricDisk (core/disk_mapping.h) maps [0,1]^2 onto the unit disk: area preserving
// (constant Jacobian π), continuous; (0.5, 0.5) is the centre.

inline Vec3 toWorld(Vec3 local, Vec3 n) {
  Vec3 t, b;
  orthonormalBasis(n, t, b);
  return t * local.x + b * local.y + n * local.z;
}

// The direction at polar angle (cosA, sinA) and azimuth phi about the unit axis a.
inline Vec3 aroundAxis(Vec3 a, float cosA, float sinA, float phi) {
  Vec3 t, b;
  orthonormalBasis(a, t, b);
  return normalize(t * (sinA * std::cos(phi)) + b * (sinA * std::sin(phi)) + a * cosA);
}

// Uniform in the cone of directions within acos(1 - oneMinusCos) of the unit axis (2: the
// whole sphere); density 1 / (2π oneMinusCos). oneMinusCos is a double: the sun's is 1e-5.
inline Vec3 sampleUniformCone(Vec3 axis, double oneMinusCos, float u1, float u2) {
  const double c = 1.0 - double(u1) * oneMinusCos;
  const float s = float(std::sqrt(std::max(0.0, (1.0 - c) * (1.0 + c))));
  return aroundAxis(axis, float(c), s, 2.0f * std::numbers::pi_v<float> * u2);
}

inline bool isBlack(Rgb c) { return !(c.x > 0 || c.y > 0 || c.z > 0); }

inline float luminance(Rgb c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

}  // namespace rayes
