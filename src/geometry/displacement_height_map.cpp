// Height maps read through a texel reader (the texture cache), with a min-max pyramid built
// in one streaming pass (see geometry/displacement.h).
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include "geometry/displacement.h"
#include "texture/texture_cache.h"

namespace rayes {

namespace {
inline float clampUnit(float x) { return x > 0.0f ? (x < 1.0f ? x : 1.0f) : 0.0f; }  // NaN -> 0
inline float lerp1(float a, float b, float s) { return a + (b - a) * s; }
}  // namespace

HeightMap::HeightMap(int width, int height, HeightTexelReader read)
    : read_(std::move(read)), width_(width), height_(height) {
  build();
}

HeightMap::HeightMap(int width, int height, std::vector<float> texels) : width_(width), height_(height) {
  if (width > 0 && height > 0 && texels.size() != size_t(width) * size_t(height))
    throw std::invalid_argument("height map texel count does not match its size");
  auto image = std::make_shared<const std::vector<float>>(std::move(texels));
  read_ = [image, width](int x0, int x1, int y0, int y1, float* out) {
    for (int y = y0; y < y1; ++y, out += x1 - x0)
      std::copy(image->begin() + (ptrdiff_t(y) * width + x0), image->begin() + (ptrdiff_t(y) * width + x1), out);
  };
  build();
}

HeightMap::HeightMap(std::shared_ptr<const TextureImage> image, int channel)
    : width_(image ? image->width() : 0), height_(image ? image->height() : 0) {
  if (!image) throw std::invalid_argument("height map needs an image");
  read_ = [image, channel](int x0, int x1, int y0, int y1, float* out) { image->texels(0, x0, x1, y0, y1, channel, out); };
  build();
}

void HeightMap::build() {
  if (width_ <= 0 || height_ <= 0 || width_ > (1 << 16) || height_ > (1 << 16))
    throw std::invalid_argument("height map size must be in 1..65536 per side");
  const int w = width_, h = height_;
  const int cw = (w + kCell - 1) / kCell, ch = (h + kCell - 1) / kCell;
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<float> cellLo(size_t(cw) * ch, inf), cellHi(size_t(cw) * ch, -inf);
  // One pass over the image, a band of kCell rows (plus the next row, for the differences
  // between neighbours) at a time: memory is a band, not the image. The differences are summed
  // in the same order as over the whole image, so the mean (an LOD input) does not depend on
  // the band height.
  std::vector<float> band(size_t(kCell + 1) * size_t(w));
  float mag = 0;
  double diff = 0;
  size_t count = 0;
  for (int y0 = 0; y0 < h; y0 += kCell) {
    const int y1 = std::min(h, y0 + kCell), yEnd = std::min(h, y1 + 1);
    read_(0, w, y0, yEnd, band.data());
    for (int j = y0; j < yEnd; ++j)
      for (int i = 0; i < w; ++i)
        if (!std::isfinite(band[size_t(j - y0) * w + i]))
          throw std::invalid_argument("height map has a non-finite texel at (" + std::to_string(i) + ", " + std::to_string(j) + ")");
    for (int j = y0; j < y1; ++j) {
      const float* row = band.data() + size_t(j - y0) * w;
      float* lo = cellLo.data() + size_t(j / kCell) * cw;
      float* hi = cellHi.data() + size_t(j / kCell) * cw;
      for (int i = 0; i < w; ++i) {
        const float t = row[i];
        mag = std::max(mag, std::fabs(t));
        lo[i / kCell] = std::min(lo[i / kCell], t);
        hi[i / kCell] = std::max(hi[i / kCell], t);
        if (i + 1 < w) { diff += std::fabs(row[i + 1] - t); ++count; }
        if (j + 1 < h) { diff += std::fabs(row[size_t(w) + i] - t); ++count; }
      }
    }
  }
  // Three float lerps of values of magnitude <= mag with weights in [0, 1] stay within a few
  // ulps of the exact bilinear blend, which lies between the 4 texels' min and max.
  roundingMargin_ = 2e-6f * mag;
  meanDiff_ = count ? float(diff / double(count)) : 0.0f;

  mins_.push_back(std::move(cellLo));
  maxs_.push_back(std::move(cellHi));
  levelWidth_.push_back(cw);
  levelHeight_.push_back(ch);
  while (levelWidth_.back() > 1 || levelHeight_.back() > 1) {
    const int lw = levelWidth_.back(), lh = levelHeight_.back();
    const int nw = (lw + 1) / 2, nh = (lh + 1) / 2;  // ceil: level L is ceil(cells / 2^L) wide
    const std::vector<float>& lo = mins_.back();
    const std::vector<float>& hi = maxs_.back();
    std::vector<float> nlo(size_t(nw) * nh), nhi(size_t(nw) * nh);
    for (int j = 0; j < nh; ++j)
      for (int i = 0; i < nw; ++i) {
        float a = inf, b = -inf;
        for (int dj = 0; dj < 2; ++dj)
          for (int di = 0; di < 2; ++di) {
            const int ci = std::min(2 * i + di, lw - 1), cj = std::min(2 * j + dj, lh - 1);
            a = std::min(a, lo[size_t(cj) * lw + ci]);
            b = std::max(b, hi[size_t(cj) * lw + ci]);
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

size_t HeightMap::pyramidBytes() const {
  size_t n = 0;
  for (const auto& l : mins_) n += 2 * l.size() * sizeof(float);
  return n;
}

float HeightMap::texel(int i, int j) const {
  float t = 0;
  read_(std::clamp(i, 0, width_ - 1), std::clamp(i, 0, width_ - 1) + 1, std::clamp(j, 0, height_ - 1),
        std::clamp(j, 0, height_ - 1) + 1, &t);
  return t;
}

namespace {
// One point's bilinear blend from its four texels: the one formula sample() and sampleRow()
// share, so the two agree bit for bit.
inline float blend(float t00, float t10, float t01, float t11, float tx, float ty, bool flatU, bool flatV, int w, int h,
                   float* dhdu, float* dhdv) {
  const float b0 = lerp1(t00, t10, tx), b1 = lerp1(t01, t11, tx);
  if (dhdu) *dhdu = flatU ? 0.0f : (lerp1(t10, t11, ty) - lerp1(t00, t01, ty)) * float(w);
  if (dhdv) *dhdv = flatV ? 0.0f : (b1 - b0) * float(h);
  return lerp1(b0, b1, ty);
}
}  // namespace

void HeightMap::sampleRow(int n, const float* u, float v, float* out, float* dhdu, float* dhdv) const {
  if (n <= 0) return;
  const float y = clampUnit(v) * float(height_) - 0.5f;
  const float fy = std::floor(y), ty = y - fy;
  const int iy = int(fy);
  const int j0 = std::clamp(iy, 0, height_ - 1), j1 = std::clamp(iy + 1, 0, height_ - 1);
  // The texel columns the row's points read, fetched once for rows j0 and j1.
  int lo = width_ - 1, hi = 0;
  for (int k = 0; k < n; ++k) {
    const int ix = int(std::floor(clampUnit(u[k]) * float(width_) - 0.5f));
    lo = std::min(lo, std::clamp(ix, 0, width_ - 1));
    hi = std::max(hi, std::clamp(ix + 1, 0, width_ - 1));
  }
  if (lo > hi) lo = hi;
  const int cols = hi - lo + 1, rows = j1 - j0 + 1;
  thread_local std::vector<float> block;
  block.resize(size_t(cols) * size_t(rows));
  read_(lo, hi + 1, j0, j1 + 1, block.data());
  const float* r0 = block.data();
  const float* r1 = block.data() + size_t(rows - 1) * size_t(cols);
  for (int k = 0; k < n; ++k) {
    const float x = clampUnit(u[k]) * float(width_) - 0.5f;
    const float fx = std::floor(x), tx = x - fx;
    const int ix = int(fx);
    const int i0 = std::clamp(ix, 0, width_ - 1) - lo, i1 = std::clamp(ix + 1, 0, width_ - 1) - lo;
    out[k] = blend(r0[i0], r0[i1], r1[i0], r1[i1], tx, ty, i0 == i1, j0 == j1, width_, height_, dhdu ? dhdu + k : nullptr,
                   dhdv ? dhdv + k : nullptr);
  }
}

float HeightMap::sample(float u, float v, float* dhdu, float* dhdv) const {
  const float x = clampUnit(u) * float(width_) - 0.5f, y = clampUnit(v) * float(height_) - 0.5f;
  const float fx = std::floor(x), fy = std::floor(y);
  const float tx = x - fx, ty = y - fy;
  const int ix = int(fx), iy = int(fy);
  const int i0 = std::clamp(ix, 0, width_ - 1), i1 = std::clamp(ix + 1, 0, width_ - 1);
  const int j0 = std::clamp(iy, 0, height_ - 1), j1 = std::clamp(iy + 1, 0, height_ - 1);
  float t[4];  // the (i1 - i0 + 1) x (j1 - j0 + 1) texels, row-major
  read_(i0, i1 + 1, j0, j1 + 1, t);
  const int di = i1 - i0, dj = (j1 - j0) * (di + 1);
  return blend(t[0], t[di], t[dj], t[dj + di], tx, ty, i0 == i1, j0 == j1, width_, height_, dhdu, dhdv);
}

Interval HeightMap::texelRange(int i0, int i1, int j0, int j1) const {
  i0 = std::clamp(i0, 0, width_ - 1);
  i1 = std::clamp(i1, i0, width_ - 1);
  j0 = std::clamp(j0, 0, height_ - 1);
  j1 = std::clamp(j1, j0, height_ - 1);
  Interval r{std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity()};
  const int n = (i1 - i0 + 1) * (j1 - j0 + 1);
  if (n <= kDirectTexels) {
    float t[kDirectTexels];
    read_(i0, i1 + 1, j0, j1 + 1, t);
    for (int k = 0; k < n; ++k) {
      r.lo = std::min(r.lo, t[k]);
      r.hi = std::max(r.hi, t[k]);
    }
    return r;
  }
  i0 /= kCell, i1 /= kCell, j0 /= kCell, j1 /= kCell;
  // The finest level at which the range spans at most 2 x 2 nodes.
  int L = 0;
  while ((i1 >> L) - (i0 >> L) > 1 || (j1 >> L) - (j0 >> L) > 1) ++L;
  const int w = levelWidth_[size_t(L)];
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
    // The texels of all the cells, read at once: at most 17 x 2 (16 cells in a row).
    const int bi0 = std::clamp(int(fx0), 0, width_ - 1), bi1 = std::clamp(int(fx1) + 1, 0, width_ - 1);
    const int bj0 = std::clamp(int(fy0), 0, height_ - 1), bj1 = std::clamp(int(fy1) + 1, 0, height_ - 1);
    const int bw = bi1 - bi0 + 1;
    float block[34];
    read_(bi0, bi1 + 1, bj0, bj1 + 1, block);
    auto at = [&](int i, int j) { return double(block[size_t(j - bj0) * bw + (i - bi0)]); };
    double lo = 1e300, hi = -1e300;
    for (int iy = int(fy0); iy <= int(fy1); ++iy)
      for (int ix = int(fx0); ix <= int(fx1); ++ix) {
        const int i0 = std::clamp(ix, 0, width_ - 1), i1 = std::clamp(ix + 1, 0, width_ - 1);
        const int j0 = std::clamp(iy, 0, height_ - 1), j1 = std::clamp(iy + 1, 0, height_ - 1);
        const double t00 = at(i0, j0), t10 = at(i1, j0);
        const double t01 = at(i0, j1), t11 = at(i1, j1);
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

HeightMapDisplacement::HeightMapDisplacement(std::shared_ptr<const HeightMap> map, float amplitude, float offset,
                                             HeightMapOrigin origin)
    : map_(std::move(map)), amplitude_(amplitude), offset_(offset), origin_(std::move(origin)) {
  if (!map_) throw std::invalid_argument("height map displacement needs a map");
  if (!std::isfinite(amplitude) || !std::isfinite(offset)) throw std::invalid_argument("height map amplitude and offset must be finite");
}

HeightSample HeightMapDisplacement::sample(Vec3, Vec3, Vec3, float u, float v) const {
  float du = 0, dv = 0;
  const float t = map_->sample(u, v, &du, &dv);
  return {offset_ + amplitude_ * t, amplitude_ * du, amplitude_ * dv};
}

void HeightMapDisplacement::sampleRow(int n, const Vec3*, const Vec3*, const Vec3*, const float* u, float v,
                                      HeightSample* out) const {
  thread_local std::vector<float> t, du, dv;
  t.resize(size_t(std::max(n, 0)));
  du.resize(t.size());
  dv.resize(t.size());
  map_->sampleRow(n, u, v, t.data(), du.data(), dv.data());
  for (int k = 0; k < n; ++k) out[k] = {offset_ + amplitude_ * t[size_t(k)], amplitude_ * du[size_t(k)], amplitude_ * dv[size_t(k)]};
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
