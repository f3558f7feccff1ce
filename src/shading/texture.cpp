#include "shading/texture.h"
#include <cmath>

namespace rayes {
namespace {

// Repeat wrap of a texel index.
int wrap(int i, int n) {
  const int r = i % n;
  return r < 0 ? r + n : r;
}

Rgb bilinear(const Image& im, float u, float v) {
  if (im.width <= 0 || im.height <= 0) return {};
  // Texel centres at (x + 0.5) / w; image row 0 at the top (v = 1).
  const float x = u * float(im.width) - 0.5f, y = (1.0f - v) * float(im.height) - 0.5f;
  if (!std::isfinite(x) || !std::isfinite(y)) return {};
  const float fx = std::floor(x), fy = std::floor(y);
  const float ax = x - fx, ay = y - fy;
  // Reduce before converting so huge (u, v) cannot overflow an int.
  const int x0 = wrap(int(std::fmod(fx, float(im.width))), im.width), y0 = wrap(int(std::fmod(fy, float(im.height))), im.height);
  const int x1 = wrap(x0 + 1, im.width), y1 = wrap(y0 + 1, im.height);
  return (im.at(x0, y0) * (1 - ax) + im.at(x1, y0) * ax) * (1 - ay) +
         (im.at(x0, y1) * (1 - ax) + im.at(x1, y1) * ax) * ay;
}

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
    case Kind::Image:
      return image ? bilinear(*image, u * scale, v * scale) : Rgb{};
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
