// Unit vectors packed into 32 bits (octahedral mapping, 2 x 16-bit snorm). Used for the two
// normals of a ray's hit record (core/ray_batch.h, RayHit), which keeps it at 28 bytes per ray
// slot. Worst-case angular error about 3e-5 rad. decode() always returns a unit vector, for
// every code; a zero, infinite or NaN input encodes to +z.
#pragma once
#include <cmath>
#include <cstdint>
#include "core/vec.h"

namespace rayes {

inline uint32_t encodeOctahedral(Vec3 n) {
  const float l1 = std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z);
  float x = 0, y = 0;
  if (l1 > 0 && std::isfinite(l1)) {
    x = n.x / l1; y = n.y / l1;
    if (n.z < 0) {
      const float ox = (1 - std::fabs(y)) * std::copysign(1.0f, x);
      const float oy = (1 - std::fabs(x)) * std::copysign(1.0f, y);
      x = ox; y = oy;
    }
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
  if (n.z < 0) {
    const float ox = (1 - std::fabs(y)) * std::copysign(1.0f, x);
    const float oy = (1 - std::fabs(x)) * std::copysign(1.0f, y);
    n.x = ox; n.y = oy;
  }
  const Vec3 u = normalize(n);
  return u.z == 0 && u.x == 0 && u.y == 0 ? Vec3{0, 0, 1} : u;
}

}  // namespace rayes
