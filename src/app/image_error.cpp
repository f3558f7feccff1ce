#include "app/image_error.h"
#include <algorithm>
#include <cmath>

namespace rayes {

ImageError errorAgainst(const std::vector<float>& rgba, const std::vector<float>& ref, const PixelRegion& pixels,
                        int width, int height) {
  double squares = 0, relative = 0;
  size_t count = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      if (!pixels.contains(x, y, width)) continue;
      const size_t p = size_t(y) * size_t(width) + size_t(x);
      for (int c = 0; c < 3; ++c) {
        const double r = ref[3 * p + c], d = double(rgba[4 * p + c]) - r;
        squares += d * d;
        relative += d * d / (r * r + 0.01);
      }
      count += 3;
    }
  if (count == 0) return {};
  return {std::sqrt(squares / double(count)), relative / double(count)};
}

namespace {

// Calls f(PixelError) for every pixel of `pixels`, in scan order.
template <class F>
void forEachPixelError(const std::vector<float>& rgba, const std::vector<float>& ref, const PixelRegion& pixels,
                       int width, int height, F&& f) {
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      if (!pixels.contains(x, y, width)) continue;
      const size_t p = size_t(y) * size_t(width) + size_t(x);
      double sum = 0, value = 0, reference = 0;
      for (int c = 0; c < 3; ++c) {
        const double d = double(rgba[4 * p + c]) - double(ref[3 * p + c]);
        sum += d * d;
        value += rgba[4 * p + c];
        reference += ref[3 * p + c];
      }
      f(PixelError{x, y, sum / 3, value / 3, reference / 3});
    }
}

}  // namespace

LargestErrors largestErrors(const std::vector<float>& rgba, const std::vector<float>& ref, const PixelRegion& pixels,
                            int width, int height, size_t k) {
  LargestErrors out;
  double& total = out.total;
  // Insertion into a list of at most k: k is a handful, the pixels many.
  forEachPixelError(rgba, ref, pixels, width, height, [&](const PixelError& e) {
    total += e.squared;
    ++out.counted;
    auto at = std::find_if(out.pixels.begin(), out.pixels.end(), [&](const PixelError& o) { return e.squared > o.squared; });
    if (at == out.pixels.end() && out.pixels.size() >= k) return;
    out.pixels.insert(at, e);
    if (out.pixels.size() > k) out.pixels.pop_back();
  });
  double held = 0;
  for (const PixelError& e : out.pixels) held += e.squared;
  out.share = total > 0 ? held / total : 0;
  return out;
}

double clampedRmse(const std::vector<float>& rgba, const std::vector<float>& ref, const PixelRegion& pixels, int width,
                   int height, double quantile) {
  std::vector<double> squared;
  forEachPixelError(rgba, ref, pixels, width, height, [&](const PixelError& e) { squared.push_back(e.squared); });
  if (squared.empty()) return 0;
  const size_t n = squared.size();
  // Nearest rank, 1-based ceil(q n), kept in [1, n].
  const size_t rank = std::clamp<size_t>(size_t(std::ceil(quantile * double(n))), 1, n);
  std::nth_element(squared.begin(), squared.begin() + ptrdiff_t(rank - 1), squared.end());
  const double cap = squared[rank - 1];
  double sum = 0;
  for (const double e : squared) sum += std::min(e, cap);
  return std::sqrt(sum / double(n));
}

}  // namespace rayes
