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

float Texture::noise(float x, float y, int octaves, float width) {
  if (!std::isfinite(x) || !std::isfinite(y)) return 0;
  // Octave o has lattice spacing 2^-o; a footprint wider than half of it would alias it, so it
  // fades to its mean (0.5) between spacing 2 width (kept) and width (gone): keep =
  // clamp(log2(spacing / width), 0, 1) = clamp(-log2(width) - o, 0, 1). width <= 0: every octave.
  const bool filtered = width > 0;
  const float firstFade = filtered ? -std::log2(std::min(width, 1e30f)) : 0.0f;  // o where spacing = width
  float sum = 0, amp = 0.5f, norm = 0;
  for (int o = 0; o < std::max(1, octaves); ++o) {
    if (filtered) {
      const float keep = std::clamp(firstFade - float(o), 0.0f, 1.0f);
      sum += amp * (keep > 0 ? keep * valueNoise(x, y) + (1 - keep) * 0.5f : 0.5f);
    } else {
      sum += amp * valueNoise(x, y);
    }
    norm += amp;
    x = x * 2.0f + 17.3f;
    y = y * 2.0f + 5.1f;
    amp *= 0.5f;
  }
  return std::clamp(sum / norm, 0.0f, 1.0f);
}

int Texture::checkerProbes(float lx, float ly, float shortAxis) {
  // The box around the whole parallelogram exceeds it by L's smaller coordinate (its slant);
  // n boxes along L cut that excess to 1/n, so n = slant / |S| leaves it at most |S|.
  const float slant = std::min(std::fabs(lx), std::fabs(ly));
  if (!(slant > 0)) return 1;
  const float ratio = slant / std::max(shortAxis, 1e-30f);
  return std::isfinite(ratio) ? int(std::clamp(std::ceil(ratio), 1.0f, float(kMaxCheckerProbes))) : kMaxCheckerProbes;
}

float Texture::checkerFootprintWeight(float x, float y, float ax, float ay, float bx, float by) {
  // L the longer axis, S the shorter; n boxes along L, each around 1/n of the parallelogram.
  const double la = std::hypot(double(ax), double(ay)), lb = std::hypot(double(bx), double(by));
  const bool aLong = la >= lb;
  const double Lx = aLong ? ax : bx, Ly = aLong ? ay : by, Sx = aLong ? bx : ax, Sy = aLong ? by : ay;
  const int n = checkerProbes(float(Lx), float(Ly), float(std::min(la, lb)));
  const double hx = 0.5 * (std::fabs(Lx) / n + std::fabs(Sx)), hy = 0.5 * (std::fabs(Ly) / n + std::fabs(Sy));
  double sum = 0;
  for (int k = 0; k < n; ++k) {
    const double f = (k + 0.5) / n - 0.5;
    sum += 0.5 - 0.5 * squareWaveMean(double(x) + f * Lx, hx) * squareWaveMean(double(y) + f * Ly, hy);
  }
  const double w = sum / n;
  return std::isfinite(w) ? float(std::clamp(w, 0.0, 1.0)) : 0.5f;
}

double Texture::squareWaveMean(double x, double h) {
  // (-1)^floor(x), whose antiderivative from 0 is the triangle wave T(x) = 1 - |(x mod 2) - 1|.
  auto sign = [](double c) { return std::fmod(std::fabs(c), 2.0) >= 1.0 ? -1.0 : 1.0; };
  h = std::isfinite(h) ? std::fabs(h) : 0.0;
  if (std::floor(x - h) == std::floor(x + h)) return sign(std::floor(x));  // one cell (or h = 0)
  auto T = [](double t) {
    const double m = t - 2.0 * std::floor(t * 0.5);  // in [0, 2)
    return 1.0 - std::fabs(m - 1.0);
  };
  // |T(a) - T(b)| <= 1, so the mean is within [-1, 1] and shrinks as 1 / h: finite for any h.
  return std::clamp((T(x + h) - T(x - h)) / (2.0 * h), -1.0, 1.0);
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
      const float x = u * scale, y = v * scale;
      if (!std::isfinite(std::floor(x)) || !std::isfinite(std::floor(y))) return color0;
      const float k = std::fabs(scale);
      if (at.dxA == 0 && at.dyA == 0 && at.dxB == 0 && at.dyB == 0) {
        const bool odd = std::fmod(std::fabs(std::floor(x) + std::floor(y)), 2.0f) >= 1.0f;
        return odd ? color1 : color0;
      }
      const float w = checkerFootprintWeight(x, y, at.dxA * k, at.dyA * k, at.dxB * k, at.dyB * k);
      return color0 * (1 - w) + color1 * w;
    }
    case Kind::Noise: {
      // The footprint's larger extent, in noise units.
      const float width = std::max(std::fabs(at.dxA) + std::fabs(at.dxB), std::fabs(at.dyA) + std::fabs(at.dyB)) *
                          std::fabs(scale);
      const float t = noise(u * scale, v * scale, octaves, std::isfinite(width) ? width : 1e30f);
      return color0 * (1 - t) + color1 * t;
    }
  }
  return {};
}

}  // namespace rayes
