// The concentric map of the unit square onto the unit disk (Shirley and Chiu): area
// preserving, so a uniform (u, v) gives a uniform point on the disk. Used by the disk patch
// (geometry) and by disk sampling (shading); it lives here so neither includes the other.
#pragma once
#include <cmath>
#include <numbers>

namespace rayes {

inline void concentricDisk(float u, float v, float& x, float& y) {
  const float a = 2 * u - 1, b = 2 * v - 1;
  x = y = 0;
  if (a == 0 && b == 0) return;
  const float q = std::numbers::pi_v<float> / 4;
  float r, phi;
  if (std::fabs(a) > std::fabs(b)) { r = a; phi = q * (b / a); }
  else { r = b; phi = 2 * q - q * (a / b); }
  x = r * std::cos(phi);
  y = r * std::sin(phi);
}

}  // namespace rayes
