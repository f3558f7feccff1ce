#include "app/pixel_cost.h"
#include <algorithm>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace rayes {

PixelCost::PixelCost(const PixelWindow& window, int fullWidth)
    : window_(window), fullWidth_(fullWidth), pixelDicings_(window.pixels(), 0), pixelSeconds_(window.pixels(), 0.0) {}

void PixelCost::startBatch(uint32_t paths, uint32_t raysPerPath) {
  raysPerPath_ = raysPerPath;
  pathDicings_.assign(paths, 0);
  pathRays_.assign(paths, 0);
}

void PixelCost::afterTrace(RayBatch& rays) {
  const size_t paths = pathRays_.size();
  const bool shares = rays.chargeDicings && rays.dicingShare.size() == rays.size();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, paths, 4096), [&](const auto& r) {
    for (size_t k = r.begin(); k != r.end(); ++k)
      for (size_t s = k * raysPerPath_, e = std::min(s + raysPerPath_, rays.size()); s < e; ++s) {
        if (rays.ray[s].kind != RayKind::Inactive) ++pathRays_[k];
        if (shares) {
          pathDicings_[k] += rays.dicingShare[s];
          rays.dicingShare[s] = 0;
        }
      }
  });
}

void PixelCost::finishBatch(double seconds, const std::function<int64_t(uint32_t)>& pixelOf) {
  uint64_t rays = 0;
  for (uint32_t n : pathRays_) rays += n;
  const double perRay = rays ? seconds / double(rays) : 0.0;
  for (uint32_t k = 0; k < pathRays_.size(); ++k) {
    const int64_t p = pixelOf(k);
    const int x = p < 0 ? -1 : int(p % fullWidth_), y = p < 0 ? -1 : int(p / fullWidth_);
    if (p < 0 || !window_.contains(x, y)) {
      unchargedFixed_ += pathDicings_[k];
      continue;
    }
    const size_t i = size_t(y - window_.y0) * size_t(window_.width()) + size_t(x - window_.x0);
    pixelDicings_[i] += pathDicings_[k];
    chargedFixed_ += pathDicings_[k];
    const double t = perRay * double(pathRays_[k]);
    pixelSeconds_[i] += t;
    secondsCharged_ += t;
  }
}

std::vector<float> PixelCost::dicings() const {
  std::vector<float> out(pixelDicings_.size());
  for (size_t i = 0; i < out.size(); ++i) out[i] = float(double(pixelDicings_[i]) / double(RayBatch::kDicingShareOne));
  return out;
}

std::vector<float> PixelCost::seconds() const { return {pixelSeconds_.begin(), pixelSeconds_.end()}; }

double PixelCost::dicingsCharged() const { return double(chargedFixed_) / double(RayBatch::kDicingShareOne); }
double PixelCost::dicingsNotCharged() const { return double(unchargedFixed_) / double(RayBatch::kDicingShareOne); }

size_t PixelCost::bytes() const {
  return pixelDicings_.capacity() * sizeof(uint64_t) + pixelSeconds_.capacity() * sizeof(double) +
         pathDicings_.capacity() * sizeof(uint64_t) + pathRays_.capacity() * sizeof(uint32_t);
}

}  // namespace rayes
