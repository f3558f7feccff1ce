#include "shading/light.h"
#include <algorithm>
#include <cmath>
#include <numbers>
#include "shading/sampling.h"

namespace rayes {

LightSampler::LightSampler(std::vector<PointLight> points, std::vector<PatchLight> patches)
    : points_(std::move(points)), patches_(std::move(patches)) {
  std::vector<double> power;
  for (const auto& p : points_) power.push_back(4.0 * std::numbers::pi * std::max(0.0f, luminance(p.intensity)));
  for (const auto& p : patches_) {
    // Area by a 8x8 midpoint rule: only used to balance the choice between lights, so an
    // estimate is enough; any positive weights keep the estimator unbiased.
    double area = 0;
    for (int j = 0; j < 8; ++j)
      for (int i = 0; i < 8; ++i) {
        Vec3 pos, n;
        p.evaluate((i + 0.5f) / 8, (j + 0.5f) / 8, pos, n);
        area += length(n) / 64.0;
      }
    const double sides = p.twoSided ? 2.0 : 1.0;
    power.push_back(std::numbers::pi * sides * area * std::max(0.0f, luminance(p.radiance)));
  }
  double total = 0;
  for (double w : power) total += w;
  if (power.empty()) return;
  // All lights dark (or a zero-area light): fall back to a uniform choice.
  if (!(total > 0)) { std::fill(power.begin(), power.end(), 1.0); total = double(power.size()); }
  double acc = 0;
  for (double w : power) { acc += w; cdf_.push_back(float(acc / total)); }
  cdf_.back() = 1.0f;
  uint32_t maxLeaf = 0;
  for (const auto& p : patches_) maxLeaf = std::max(maxLeaf, p.leaf + 1);
  leafToPatchLight_.assign(maxLeaf, -1);
  for (size_t i = 0; i < patches_.size(); ++i) leafToPatchLight_[patches_[i].leaf] = int(i);
}

int LightSampler::patchLightOfLeaf(uint32_t leaf) const {
  return leaf < leafToPatchLight_.size() ? leafToPatchLight_[leaf] : -1;
}

bool LightSampler::sample(float u0, float u1, float u2, LightSample& out) const {
  if (cdf_.empty()) return false;
  const size_t k = std::min<size_t>(std::upper_bound(cdf_.begin(), cdf_.end(), u0) - cdf_.begin(),
                                    cdf_.size() - 1);
  out.pickPdf = cdf_[k] - (k > 0 ? cdf_[k - 1] : 0.0f);
  if (!(out.pickPdf > 0)) return false;
  if (k < points_.size()) {
    out.position = points_[k].position;
    out.normal = {0, 0, 0};
    out.radiance = points_[k].intensity;
    out.pdfArea = 0;
    out.delta = true;
    out.leaf = 0xffffffffu;
    return true;
  }
  const PatchLight& l = patches_[k - points_.size()];
  Vec3 n;
  l.evaluate(u1, u2, out.position, n);
  const float jacobian = length(n);
  if (!(jacobian > 0) || !std::isfinite(jacobian)) return false;
  out.normal = n * (1.0f / jacobian);
  out.radiance = l.radiance;
  out.pdfArea = 1.0f / jacobian;
  out.delta = false;
  out.twoSided = l.twoSided;
  out.leaf = l.leaf;
  return true;
}

}  // namespace rayes
