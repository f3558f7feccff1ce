// Height maps with a min-max MIP pyramid (see geometry/displacement.h).
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include "geometry/displacement.h"

namespace rayes {

namespace {
inline float clampUnit(float x) { return x > 0.0f ? (x < 1.0f ? x : 1.0f) : 0.0f; }  // NaN -> 0
inline float lerp1(float a, float b, float s) { return a + (b - a) * s; }
}  // namespace

HeightMap::HeightMap(int width, int height, std::vector<float> texels) : width_(width), height_(height) {
  if (width <= 0 || height <= 0 || width > (1 << 16) || height > (1 << 16))
    throw std::invalid_argument("height map size must be in 1..65536 per side");
  if (texels.size() != size_t(width) * size_t(height)) throw std::invalid_argument("height map texel count does not match its size");
  float mag = 0;
  for (float t : texels) {
    if (!std::isfinite(t)) throw std::invalid_argument("height map has a non-finite texel");
    mag = std::max(mag, std::fabs(t));
  }
  // Three float lerps of values of magnitude <= mag with weights in [0, 1] stay within a few
  // ulps of the exact bilinear blend, which lies between the 4 texels' min and max.
  roundingMargin_ = 2e-6f * mag;
  double diff = 0;
  size_t count = 0;
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i) {
      const float t = texels[size_t(j) * width + i];
      if (i + 1 < width) { diff += std::fabs(texels[size_t(j) * width + i + 1] - t); ++count; }
      if (j + 1 < height) { diff += std::fabs(texels[size_t(j + 1) * width + i] - t); ++count; }
    }
  meanDiff_ = count ? float(diff / double(count)) : 0.0f;

  mins_.push_back(texels);
  maxs_.push_back(std::move(texels));
  levelWidth_.push_back(width);
  levelHeight_.push_back(height);
  while (levelWidth_.back() > 1 || levelHeight_.back() > 1) {
    const int w = levelWidth_.back(), h = levelHeight_.back();
    const int nw = (w + 1) / 2, nh = (h + 1) / 2;  // ceil: level L is ceil(width / 2^L) wide
    const std::vector<float>& lo = mins_.back();
    const std::vector<float>& hi = maxs_.back();
    std::vector<float> nlo(size_t(nw) * nh), nhi(size_t(nw) * nh);
    for (int j = 0; j < nh; ++j)
      for (int i = 0; i < nw; ++i) {
        float a = std::numeric_limits<float>::infinity(), b = -a;
        for (int dj = 0; dj < 2; ++dj)
          for (int di = 0; di < 2; ++di) {
            const int ci = std::min(2 * i + di, w - 1), cj = std::min(2 * j + dj, h - 1);
            a = std::min(a, lo[size_t(cj) * w + ci]);
            b = std::max(b, hi[size_t(cj) * w + ci]);
          }
        nlo[size_t(j) * nw + i] = a;
        nhi[size_t(j) * nw + i] = b;
      }
    mins_.push_back(std::move(nlo));
    maxs_.push_back(std::move(nhi));
    levelWidth_.push_back(nw);
    levelHeight_.push_back(nh);
  }
}

float HeightMap::sample(float u, float v, float* dhdu, float* dhdv) const {
  const float x = clampUnit(u) * float(width_) - 0.5f, y = clampUnit(v) * float(height_) - 0.5f;
  const float fx = std::floor(x), fy = std::floor(y);
  const float tx = x - fx, ty = y - fy;
  const int ix = int(fx), iy = int(fy);
  const int i0 = std::clamp(ix, 0, width_ - 1), i1 = std::clamp(ix + 1, 0, width_ - 1);
  const int j0 = std::clamp(iy, 0, height_ - 1), j1 = std::clamp(iy + 1, 0, height_ - 1);
  const std::vector<float>& t = mins_[0];
  const float t00 = t[size_t(j0) * width_ + i0], t10 = t[size_t(j0) * width_ + i1];
  const float t01 = t[size_t(j1) * width_ + i0], t11 = t[size_t(j1) * width_ + i1];
  const float b0 = lerp1(t00, t10, tx), b1 = lerp1(t01, t11, tx);
  if (dhdu) *dhdu = i0 == i1 ? 0.0f : (lerp1(t10, t11, ty) - lerp1(t00, t01, ty)) * float(width_);
  if (dhdv) *dhdv = j0 == j1 ? 0.0f : (b1 - b0) * float(height_);
  return lerp1(b0, b1, ty);
}

Interval HeightMap::texelRange(int i0, int i1, int j0, int j1) const {
  i0 = std::clamp(i0, 0, width_ - 1);
  i1 = std::clamp(i1, i0, width_ - 1);
  j0 = std::clamp(j0, 0, height_ - 1);
  j1 = std::clamp(j1, j0, height_ - 1);
  // The finest level at which the range spans at most 2 x 2 nodes.
  int L = 0;
  while ((i1 >> L) - (i0 >> L) > 1 || (j1 >> L) - (j0 >> L) > 1) ++L;
  const int w = levelWidth_[size_t(L)];
  Interval r{std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity()};
  for (int j = j0 >> L; j <= j1 >> L; ++j)
    for (int i = i0 >> L; i <= i1 >> L; ++i) {
      r.lo = std::min(r.lo, mins_[size_t(L)][size_t(j) * w + i]);
      r.hi = std::max(r.hi, maxs_[size_t(L)][size_t(j) * w + i]);
    }
  return r;
}

Interval HeightMap::range(float u0, float u1, float v0, float v1) const {
  // The texels a sample can read: x = u * width - 0.5 is monotone in u (as rounded in
  // sample()), so floor(x) runs from floor(x(u0)) to floor(x(u1)), and sample() reads that
  // index and the next one.
  const float x0 = clampUnit(std::min(u0, u1)) * float(width_) - 0.5f, x1 = clampUnit(std::max(u0, u1)) * float(width_) - 0.5f;
  const float y0 = clampUnit(std::min(v0, v1)) * float(height_) - 0.5f, y1 = clampUnit(std::max(v0, v1)) * float(height_) - 0.5f;
  const float fx0 = std::floor(x0), fx1 = std::floor(x1), fy0 = std::floor(y0), fy1 = std::floor(y1);
  if ((double(fx1) - fx0 + 1) * (double(fy1) - fy0 + 1) <= 16) {
    // Few cells: per cell, the bilinear blend over a rectangle of weights takes its extremes
    // at the rectangle's corners (it is linear along each edge and has no interior extremum
    // but a saddle). The weights t = x - floor(x) are those sample() computes, monotone in x.
    double lo = 1e300, hi = -1e300;
    for (int iy = int(fy0); iy <= int(fy1); ++iy)
      for (int ix = int(fx0); ix <= int(fx1); ++ix) {
        const int i0 = std::clamp(ix, 0, width_ - 1), i1 = std::clamp(ix + 1, 0, width_ - 1);
        const int j0 = std::clamp(iy, 0, height_ - 1), j1 = std::clamp(iy + 1, 0, height_ - 1);
        const std::vector<float>& t = mins_[0];
        const double t00 = t[size_t(j0) * width_ + i0], t10 = t[size_t(j0) * width_ + i1];
        const double t01 = t[size_t(j1) * width_ + i0], t11 = t[size_t(j1) * width_ + i1];
        const float ax = ix == int(fx0) ? x0 - fx0 : 0.0f, bx = ix == int(fx1) ? x1 - fx1 : 1.0f;
        const float ay = iy == int(fy0) ? y0 - fy0 : 0.0f, by = iy == int(fy1) ? y1 - fy1 : 1.0f;
        for (double wx : {double(ax), double(bx)})
          for (double wy : {double(ay), double(by)}) {
            const double b0 = t00 + (t10 - t00) * wx, b1 = t01 + (t11 - t01) * wx;
            const double val = b0 + (b1 - b0) * wy;
            lo = std::min(lo, val);
            hi = std::max(hi, val);
          }
      }
    return widened({float(lo), float(hi)}, roundingMargin_);
  }
  const Interval r = texelRange(int(fx0), int(fx1) + 1, int(fy0), int(fy1) + 1);
  return widened(r, roundingMargin_);
}

HeightMapDisplacement::HeightMapDisplacement(std::shared_ptr<const HeightMap> map, float amplitude, float offset)
    : map_(std::move(map)), amplitude_(amplitude), offset_(offset) {
  if (!map_) throw std::invalid_argument("height map displacement needs a map");
  if (!std::isfinite(amplitude) || !std::isfinite(offset)) throw std::invalid_argument("height map amplitude and offset must be finite");
}

HeightSample HeightMapDisplacement::sample(Vec3, Vec3, Vec3, float u, float v) const {
  float du = 0, dv = 0;
  const float t = map_->sample(u, v, &du, &dv);
  return {offset_ + amplitude_ * t, amplitude_ * du, amplitude_ * dv};
}

Interval HeightMapDisplacement::range(const Box3&, float u0, float u1, float v0, float v1) const {
  const Interval t = map_->range(u0, u1, v0, v1);
  const Interval h = Interval(offset_) + Interval(amplitude_) * t;
  return widened(h, 1e-6f * (std::fabs(offset_) + std::fabs(amplitude_) * t.magnitude()));
}

float HeightMapDisplacement::meanSlopePerParameter() const {
  return std::fabs(amplitude_) * map_->meanNeighbourDifference() * float(std::max(map_->width(), map_->height()));
}

}  // namespace rayes
