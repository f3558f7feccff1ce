#include "shading/texture.h"
#include <cmath>

namespace rayes {
namespace {

uint32_t hash2(int32_t x, int32_t y) {
  uint32_t h = uint32_t(x) * 0x8da6b343u ^ uint32_t(y) * 0xd8163841u;
  h ^= h >> 15; h *= 0x2c1b3c6du; h ^= h >> 12; h *= 0x297a2d39u; h ^= h >> 15;
  return h;
}
float lattice(int32_t x, int32_t y) { return float(hash2(x, y) >> 8) * (1.0f / 16777216.0f); }
float smooth(float t) { return t * t * (3 - 2 * t); }

float valueNoise(float x, float y) {
  const float fx = std::floor(x), fy = std::floor(y);
  const int32_t ix = int32_t(std::fmod(fx, 65536.0f)), iy = int32_t(std::fmod(fy, 65536.0f));
  const float tx = smooth(x - fx), ty = smooth(y - fy);
  const float a = lattice(ix, iy), b = lattice(ix + 1, iy), c = lattice(ix, iy + 1), d = lattice(ix + 1, iy + 1);
  return (a * (1 - tx) + b * tx) * (1 - ty) + (c * (1 - tx) + d * tx) * ty;
}

}  // namespace

float Texture::noise(float x, float y, int octaves) {
  if (!std::isfinite(x) || !std::isfinite(y)) return 0;
  float sum = 0, amp = 0.5f, norm = 0;
  for (int o = 0; o < std::max(1, octaves); ++o) {
    sum += amp * valueNoise(x, y);
    norm += amp;
    x = x * 2.0f + 17.3f;
    y = y * 2.0f + 5.1f;
    amp *= 0.5f;
  }
  return std::clamp(sum / norm, 0.0f, 1.0f);
}

Rgb Texture::eval(const TextureQuery& q) const {
  const TexturePoint& at = coordinates == Coordinates::Uv && q.hasUv ? q.uv : q.patch;
  const float u = at.x, v = at.y;
  switch (kind) {
    case Kind::Image: {
      if (!image) return {};
      // OIIO's t runs down the image (row 0 at t = 0), v up: t = 1 - v, and the axes' t parts
      // change sign. Axis A is OIIO's d/dx, axis B its d/dy.
      const Rgb c = image->filtered(u * scale, 1.0f - v * scale, at.dxA * scale, -at.dyA * scale, at.dxB * scale,
                                    -at.dyB * scale, TextureWrap::Periodic);
      return vmin(c, Rgb{maxValue, maxValue, maxValue});
    }
    case Kind::Checker: {
      const float x = std::floor(u * scale), y = std::floor(v * scale);
      if (!std::isfinite(x) || !std::isfinite(y)) return color0;
      const bool odd = std::fmod(std::fabs(x + y), 2.0f) >= 1.0f;
      return odd ? color1 : color0;
    }
    case Kind::Noise: {
      const float t = noise(u * scale, v * scale, octaves);
      return color0 * (1 - t) + color1 * t;
    }
  }
  return {};
}

}  // namespace rayes
