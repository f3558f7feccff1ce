#include "shading/film.h"

namespace rayes {

Film::Film(int width, int height) : width_(width), height_(height) {
  const size_t n = size_t(width) * size_t(height);
  rgb_.assign(3 * n, 0.0); alpha_.assign(n, 0.0); depth_.assign(n, 0.0); normal_.assign(3 * n, 0.0);
  lod_.assign(n, 0.0); count_.assign(n, 0); hits_.assign(n, 0); albedo_.assign(3 * n, 0.0);
  material_.assign(n, -1);
  splat_.assign(3 * n, 0.0);
}

void Film::addSplat(uint32_t p, Rgb v) {
  splat_[3 * p] += v.x; splat_[3 * p + 1] += v.y; splat_[3 * p + 2] += v.z;
}

void Film::add(uint32_t p, const PixelSample& s) {
  rgb_[3 * p] += s.radiance.x; rgb_[3 * p + 1] += s.radiance.y; rgb_[3 * p + 2] += s.radiance.z;
  ++count_[p];
  if (!s.hitSurface) return;
  alpha_[p] += 1.0;
  depth_[p] += s.depth;
  normal_[3 * p] += s.normal.x; normal_[3 * p + 1] += s.normal.y; normal_[3 * p + 2] += s.normal.z;
  lod_[p] += s.lod;
  albedo_[3 * p] += s.albedo.x; albedo_[3 * p + 1] += s.albedo.y; albedo_[3 * p + 2] += s.albedo.z;
  if (!hits_[p]) material_[p] = s.materialId;
  ++hits_[p];
}

std::vector<float> Film::beautyRgba() const {
  const size_t n = count_.size();
  std::vector<float> out(4 * n, 0.0f);
  const double splatScale = splatPaths_ ? double(n) / double(splatPaths_) : 0.0;
  for (size_t p = 0; p < n; ++p) {
    if (!count_[p]) {
      for (int c = 0; c < 3; ++c) out[4 * p + c] = float(splat_[3 * p + c] * splatScale);
      out[4 * p + 3] = 1.0f;
      continue;
    }
    const double inv = 1.0 / count_[p];
    for (int c = 0; c < 3; ++c) {
      double v = rgb_[3 * p + c] * inv;
      if (splatPaths_) v += splat_[3 * p + c] * splatScale;
      out[4 * p + c] = float(v);
    }
    out[4 * p + 3] = float(alpha_[p] * inv);
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

std::vector<float> Film::depth() const { return meanOverHits(depth_, hits_, 1); }
std::vector<float> Film::normal() const { return meanOverHits(normal_, hits_, 3); }
std::vector<float> Film::lod() const { return meanOverHits(lod_, hits_, 1); }
std::vector<float> Film::albedo() const { return meanOverHits(albedo_, hits_, 3); }
std::vector<float> Film::materialId() const { return std::vector<float>(material_.begin(), material_.end()); }
std::vector<float> Film::sampleCount() const { return std::vector<float>(count_.begin(), count_.end()); }

size_t Film::bytes() const {
  const size_t doubles = rgb_.capacity() + alpha_.capacity() + depth_.capacity() + normal_.capacity() +
                         lod_.capacity() + albedo_.capacity() + splat_.capacity();
  return doubles * sizeof(double) + material_.capacity() * sizeof(int32_t) +
         (count_.capacity() + hits_.capacity()) * sizeof(uint32_t);
}

}  // namespace rayes
