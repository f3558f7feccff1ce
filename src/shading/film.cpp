#include "shading/film.h"
#include <cmath>
#include <limits>

namespace rayes {
namespace {

constexpr __int128 kSplatMax = ~(__int128(1) << 127);  // 2^127 - 1
constexpr __int128 kSplatMin = -kSplatMax;
// A splat's fixed-point value must stay below this (2^126) to be taken as it is.
constexpr double kSplatScale = 18446744073709551616.0;  // 2^kSplatFractionBits
constexpr double kSplatLimit = 85070591730234615865843651857942052864.0;  // 2^126

__int128 toFixed(double v, uint64_t& saturations) {
  const double scaled = v * kSplatScale;
  if (std::fabs(scaled) < kSplatLimit) return __int128(std::nearbyint(scaled));
  if (std::isnan(scaled)) return 0;  // the light tracer drops non-finite splats before this
  ++saturations;
  return scaled > 0 ? kSplatMax : kSplatMin;
}

void addSaturating(__int128& sum, __int128 v, uint64_t& saturations) {
  if (__builtin_add_overflow(sum, v, &sum)) {
    sum = v > 0 ? kSplatMax : kSplatMin;
    ++saturations;
  }
}

double fromFixed(__int128 v) { return double(v) / kSplatScale; }

}  // namespace

Film::Film(int width, int height) : Film(width, height, PixelWindow::whole(width, height)) {}

Film::Film(int width, int height, PixelWindow window)
    : fullWidth_(width), fullHeight_(height), window_(window),
      wholeImage_(window == PixelWindow::whole(width, height)) {
  const size_t n = window.pixels();
  Sums& s = sums_;
  s.rgb.assign(3 * n, 0.0); s.alpha.assign(n, 0.0); s.depth.assign(n, 0.0); s.normal.assign(3 * n, 0.0);
  s.lod.assign(n, 0.0); s.count.assign(n, 0); s.hits.assign(n, 0); s.albedo.assign(3 * n, 0.0);
  s.material.assign(n, -1);
  s.splat.assign(3 * n, 0);
}

void Film::addSplat(uint32_t pixel, Rgb v) {
  __int128* s = &sums_.splat[3 * index(pixel)];
  addSaturating(s[0], toFixed(v.x, sums_.splatSaturations), sums_.splatSaturations);
  addSaturating(s[1], toFixed(v.y, sums_.splatSaturations), sums_.splatSaturations);
  addSaturating(s[2], toFixed(v.z, sums_.splatSaturations), sums_.splatSaturations);
}

void Film::addRadiance(uint32_t pixel, Rgb radiance) {
  const size_t p = index(pixel);
  Sums& f = sums_;
  f.rgb[3 * p] += radiance.x; f.rgb[3 * p + 1] += radiance.y; f.rgb[3 * p + 2] += radiance.z;
  ++f.count[p];
}

void Film::addFirstHit(uint32_t pixel, const FirstHit& s) {
  if (!s.hitSurface) return;
  const size_t p = index(pixel);
  Sums& f = sums_;
  f.alpha[p] += 1.0;
  f.depth[p] += s.depth;
  f.normal[3 * p] += s.normal.x; f.normal[3 * p + 1] += s.normal.y; f.normal[3 * p + 2] += s.normal.z;
  f.lod[p] += s.lod;
  f.albedo[3 * p] += s.albedo.x; f.albedo[3 * p + 1] += s.albedo.y; f.albedo[3 * p + 2] += s.albedo.z;
  if (!f.hits[p]) f.material[p] = s.materialId;
  ++f.hits[p];
}

bool Film::addFilm(const Film& part) {
  if (part.fullWidth_ != fullWidth_ || part.fullHeight_ != fullHeight_ || !part.window_.inside(window_)) return false;
  const PixelWindow& w = part.window_;
  auto at = [&](int x, int y) { return size_t(y - window_.y0) * size_t(window_.width()) + size_t(x - window_.x0); };
  const Sums& src = part.sums_;
  for (int y = w.y0; y < w.y1; ++y)
    for (int x = w.x0; x < w.x1; ++x) {
      const size_t q = size_t(y - w.y0) * size_t(w.width()) + size_t(x - w.x0);
      if (src.count[q] && sums_.count[at(x, y)]) return false;
    }
  for (int y = w.y0; y < w.y1; ++y)
    for (int x = w.x0; x < w.x1; ++x) {
      const size_t q = size_t(y - w.y0) * size_t(w.width()) + size_t(x - w.x0), p = at(x, y);
      for (int c = 0; c < 3; ++c)
        addSaturating(sums_.splat[3 * p + c], src.splat[3 * q + c], sums_.splatSaturations);
      if (!src.count[q]) continue;
      // A pixel's camera samples come from this part alone: its sums are copied as they are.
      for (int c = 0; c < 3; ++c) {
        sums_.rgb[3 * p + c] = src.rgb[3 * q + c];
        sums_.normal[3 * p + c] = src.normal[3 * q + c];
        sums_.albedo[3 * p + c] = src.albedo[3 * q + c];
      }
      sums_.alpha[p] = src.alpha[q];
      sums_.depth[p] = src.depth[q];
      sums_.lod[p] = src.lod[q];
      sums_.material[p] = src.material[q];
      sums_.count[p] = src.count[q];
      sums_.hits[p] = src.hits[q];
    }
  sums_.splatPaths += src.splatPaths;
  sums_.splatSaturations += src.splatSaturations;
  return true;
}

std::vector<float> Film::beautyRgba() const {
  const Sums& f = sums_;
  const size_t n = f.count.size();
  std::vector<float> out(4 * n, 0.0f);
  const double fullPixels = double(fullWidth_) * double(fullHeight_);
  const double splatScale = f.splatPaths ? fullPixels / double(f.splatPaths) : 0.0;
  for (size_t p = 0; p < n; ++p) {
    if (!f.count[p]) {
      for (int c = 0; c < 3; ++c) out[4 * p + c] = float(fromFixed(f.splat[3 * p + c]) * splatScale);
      out[4 * p + 3] = 1.0f;
      continue;
    }
    const double inv = 1.0 / f.count[p];
    for (int c = 0; c < 3; ++c) {
      double v = f.rgb[3 * p + c] * inv;
      if (f.splatPaths) v += fromFixed(f.splat[3 * p + c]) * splatScale;
      out[4 * p + c] = float(v);
    }
    out[4 * p + 3] = float(f.alpha[p] * inv);
  }
  return out;
}

namespace {
std::vector<float> meanOverHits(const std::vector<double>& sum, const std::vector<uint32_t>& hits, int comps) {
  std::vector<float> out(sum.size(), 0.0f);
  for (size_t p = 0; p < hits.size(); ++p)
    if (hits[p])
      for (int c = 0; c < comps; ++c) out[comps * p + c] = float(sum[comps * p + c] / hits[p]);
  return out;
}
}  // namespace

std::vector<float> Film::depth() const { return meanOverHits(sums_.depth, sums_.hits, 1); }
std::vector<float> Film::normal() const { return meanOverHits(sums_.normal, sums_.hits, 3); }
std::vector<float> Film::lod() const { return meanOverHits(sums_.lod, sums_.hits, 1); }
std::vector<float> Film::albedo() const { return meanOverHits(sums_.albedo, sums_.hits, 3); }
std::vector<float> Film::materialId() const { return std::vector<float>(sums_.material.begin(), sums_.material.end()); }
std::vector<float> Film::sampleCount() const { return std::vector<float>(sums_.count.begin(), sums_.count.end()); }

size_t Film::bytes() const {
  const Sums& f = sums_;
  const size_t doubles = f.rgb.capacity() + f.alpha.capacity() + f.depth.capacity() + f.normal.capacity() +
                         f.lod.capacity() + f.albedo.capacity();
  return doubles * sizeof(double) + f.splat.capacity() * sizeof(__int128) + f.material.capacity() * sizeof(int32_t) +
         (f.count.capacity() + f.hits.capacity()) * sizeof(uint32_t);
}

}  // namespace rayes
