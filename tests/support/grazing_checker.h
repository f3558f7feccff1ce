// A checkerboard on the ground seen at grazing angles, for the texture-filter test
// (tests/shading/texture_filter_test.cpp) and its benchmark (bench/shading_texture_filter.cpp):
// the scene, each pixel's box-filtered reference with its error bound, and a pixel rendered as
// the path tracer shades a camera hit (filtered over the footprint, or point-sampled).
#pragma once
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>
#include "core/rng.h"
#include "shading/camera.h"
#include "shading/footprint.h"
#include "shading/texture.h"

namespace rayes::test {

inline Texture checkerTexture(float scale) {
  Texture t;
  t.kind = Texture::Kind::Checker;
  t.color0 = {0, 0, 0};
  t.color1 = {1, 1, 1};
  t.scale = scale;
  return t;
}

// --- The grazing checkerboard ---------------------------------------------------------------
//
// The ground z = 0 as one patch P(u, v) = (2000 u - 1000, 2000 v, 0), a checkerboard of 1 m
// checks (scale 2000); a pinhole camera 1 m above it looking along +y, pitched down just past
// half its field of view, so the top row meets the ground ~100 m away at 89.4° from the normal.
// The camera has no roll and no yaw, so along one image row the ground point moves in x alone:
// the checker's integral over a row is closed form (Texture::squareWaveMean), and over the
// pixel's rows a 1D integral split where y crosses a check border.
inline constexpr int kW = 48, kH = 24;
inline constexpr float kFov = 20;
inline constexpr float kHeight = 1;

struct Ground {
  PerspectiveCamera camera;
  Vec3 forward;
  float tanHalf;
  Ground() {
    const float pitch = (0.5f * kFov + 0.6f) * std::numbers::pi_v<float> / 180;
    forward = {0, std::cos(pitch), -std::sin(pitch)};
    camera = PerspectiveCamera(Vec3{0.3f, 0, kHeight}, Vec3{0.3f, 0, kHeight} + forward, Vec3{0, 0, 1}, kFov, kW, kH);
    tanHalf = std::tan(0.5f * kFov * std::numbers::pi_v<float> / 180);
  }
  // sy of a film row py (as PerspectiveCamera::generate), the ray parameter to the ground for
  // the unnormalised direction forward + right sx + up sy (right = x, up = (0, -fz, fy)), and y.
  double sy(double py) const { return (1 - 2 * py / kH) * tanHalf; }
  double tOf(double s) const { return -kHeight / (double(forward.z) + double(forward.y) * s); }
  double yOf(double s) const { return tOf(s) * (double(forward.y) - double(forward.z) * s); }
  // x of film column px at row sy s.
  double xOf(double px, double s) const {
    const double sx = (2 * px / kW - 1) * tanHalf * (double(kW) / kH);
    return 0.3 + tOf(s) * sx;
  }
};

// The reference: the weight of colour 1 averaged over pixel (i, j), i.e. 1/2 - 1/2 of the
// pixel's mean of sq(x) sq(y). Along a row sq(x) integrates exactly (squareWaveMean over the
// row's x interval); over the pixel's rows, the midpoint rule with n points on each piece
// between y's check borders (sq(y) constant there), whose error per piece is at most
// L * (piece length) / (4 n) with L a bound of |d/dpy| of the row integral (checked against the
// samples' differences, doubled).
inline double referenceWeight(const Ground& g, int i, int j, double& errorBound) {
  const int n = 2048;
  auto rowMean = [&](double py) {
    const double s = g.sy(py);
    const double x0 = g.xOf(i, s), x1 = g.xOf(i + 1, s);
    return Texture::squareWaveMean(0.5 * (x0 + x1), 0.5 * std::fabs(x1 - x0));
  };
  // Check borders in y inside the pixel's rows (y grows upward in the image: decreasing py).
  std::vector<double> cuts{double(j), double(j + 1)};
  const double ya = g.yOf(g.sy(j + 1)), yb = g.yOf(g.sy(j));
  for (double y = std::ceil(ya); y < yb; y += 1) {
    // Solve yOf(s) = y for s, then py.
    const double fy = g.forward.y, fz = g.forward.z;
    const double s = (-kHeight * fy - y * fz) / (y * fy - kHeight * fz);
    cuts.push_back(0.5 * kH * (1 - s / g.tanHalf));
  }
  std::sort(cuts.begin(), cuts.end());
  double sum = 0;
  errorBound = 0;
  for (size_t c = 0; c + 1 < cuts.size(); ++c) {
    const double a = std::clamp(cuts[c], double(j), double(j + 1)), b = std::clamp(cuts[c + 1], double(j), double(j + 1));
    if (!(b > a)) continue;
    const double mid = 0.5 * (a + b);
    const double sy = std::fmod(std::fabs(std::floor(g.yOf(g.sy(mid)))), 2.0) >= 1.0 ? -1.0 : 1.0;
    double piece = 0, lipschitz = 0, previous = rowMean(a);
    for (int k = 0; k < n; ++k) {
      const double v = rowMean(a + (k + 0.5) * (b - a) / n);
      piece += v;
      lipschitz = std::max(lipschitz, std::fabs(v - previous) / ((b - a) / n));
      previous = v;
    }
    sum += sy * piece * (b - a) / n;
    errorBound += 2 * lipschitz * (b - a) / (4 * n);
  }
  errorBound *= 0.5;  // the weight is 1/2 - 1/2 of the mean
  return 0.5 - 0.5 * sum;
}

struct PixelEstimate {
  double mean = 0, standardError = 0;
  // A bound on the filter's bias against the pixel's box: the mean over the filter's kernel of
  // |zx| + |zy|, z its offset in pixels (largest over the samples). For a weight in [0, 1] the
  // pixel's mean widened by a kernel k differs from the box's by at most
  // (1/2) ∫|box ⊗ k - box| <= E_k(|zx| + |zy|) (to first order in the kernel's change across
  // the pixel).
  double filterBias = 0;
  // The mean over the samples of the bound on |weight - 1/2| of their filtered lookups.
  double attenuation = 0;
};

// A pixel rendered as the path tracer shades a camera hit: spp stratified film samples, each
// ray's hit on the ground, the footprint of its cone (scaled by cameraFootprintScale) solved
// against the patch's dP/du, dP/dv, the checker evaluated (filtered, or point-sampled).
inline PixelEstimate renderPixel(const Ground& g, const Texture& tex, int i, int j, int strata, bool filtered) {
  const int spp = strata * strata;
  const HitDerivatives dpd{Vec3{2000, 0, 0}, Vec3{0, 2000, 0}};
  double s = 0, s2 = 0;
  PixelEstimate e;
  for (int k = 0; k < spp; ++k) {
    const RngKey key{uint32_t(j * kW + i), uint32_t(k), 0, 5};
    const float px = float(i) + (float(k % strata) + sampleUniform(key, 0)) / float(strata);
    const float py = float(j) + (float(k / strata) + sampleUniform(key, 1)) / float(strata);
    const CameraRay r = g.camera.generate(px, py, 0.5f, 0.5f, 0);
    const float t = -r.org.z / r.dir.z;
    const Vec3 p = r.org + r.dir * t;
    const float u = (p.x + 1000) / 2000, v = p.y / 2000;
    const float width = (r.coneWidth + t * r.coneSpread) * cameraFootprintScale(spp);
    const TextureQuery q = footprintQuery(u, v, r.dir, Vec3{0, 0, 1}, width, filtered ? &dpd : nullptr, nullptr);
    const double w = tex.eval(q).x;
    s += w;
    s2 += w * w;
    if (filtered) {
      // Where the filter reaches, in pixels: each of the checker's probe boxes
      // (Texture::checkerFootprintWeight), its corners taken back to the film through the
      // inverse of the map (px, py) -> (x, y) at the sample (y does not depend on px).
      const double ax = q.patch.dxA * 2000, ay = q.patch.dyA * 2000, bx = q.patch.dxB * 2000, by = q.patch.dyB * 2000;
      const bool aLong = std::hypot(ax, ay) >= std::hypot(bx, by);
      const double Lx = aLong ? ax : bx, Ly = aLong ? ay : by, Sx = aLong ? bx : ax, Sy = aLong ? by : ay;
      const int n = Texture::checkerProbes(float(Lx), float(Ly), float(std::min(std::hypot(ax, ay), std::hypot(bx, by))));
      const double hx = 0.5 * (std::fabs(Lx) / n + std::fabs(Sx)), hy = 0.5 * (std::fabs(Ly) / n + std::fabs(Sy));
      const double sy = g.sy(py), dsy = 1e-3;
      const double dxdpx = g.xOf(px + 1, sy) - g.xOf(px, sy);
      const double dydpy = (g.yOf(g.sy(py + dsy)) - g.yOf(g.sy(py - dsy))) / (2 * dsy);
      const double dxdpy = (g.xOf(px, g.sy(py + dsy)) - g.xOf(px, g.sy(py - dsy))) / (2 * dsy);
      double meanReach = 0;
      for (int probe = 0; probe < n; ++probe) {
        const double f = (probe + 0.5) / n - 0.5;
        double rx = 0, ry = 0;
        for (const double cx : {-hx, hx})
          for (const double cy : {-hy, hy}) {
            const double dy = f * Ly + cy, dx = f * Lx + cx;
            const double dpy = dy / dydpy, dpx = (dx - dxdpy * dpy) / dxdpx;
            rx = std::max(rx, std::fabs(dpx));
            ry = std::max(ry, std::fabs(dpy));
          }
        meanReach += (rx + ry) / n;
      }
      e.filterBias = std::max(e.filterBias, meanReach);
      // Each probe's |weight - 1/2| is (1/2) |m(x, hx)| |m(y, hy)| <= (1/2) min(1, 1 / 2hx) min(1, 1 / 2hy)
      // (|T(a) - T(b)| <= 1): how far a footprint over many checks can stray from grey.
      e.attenuation += 0.5 * std::min(1.0, 1 / (2 * hx)) * std::min(1.0, 1 / (2 * hy)) / spp;
    }
  }
  e.mean = s / spp;
  e.standardError = std::sqrt(std::max(0.0, s2 / spp - e.mean * e.mean) / std::max(1, spp - 1));
  return e;
}

}  // namespace rayes::test
