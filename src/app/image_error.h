// The error of a render against a reference image, over a set of pixels: the one RMSE of the
// program (the renderer's error curve, `rayes converge`), and what converge reports beside it
// (which pixels hold the squared error; an RMSE with outliers clamped). Pure functions;
// thread-safe. Linear in the pixels, but clampedRmse (a selection, O(n) on average).
#pragma once
#include <cstddef>
#include <vector>

namespace rayes {

// Pixels [x0, x1) x [y0, y1), or a mask (non-zero red) when `mask` is not empty. The whole
// image as {0, 0, width, height}.
struct PixelRegion {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  std::vector<float> mask;  // RGB per pixel
  bool contains(int x, int y, int width) const {
    if (!mask.empty()) return mask[3 * (size_t(y) * size_t(width) + size_t(x))] != 0;
    return x >= x0 && x < x1 && y >= y0 && y < y1;
  }
};

// Over the pixels of `pixels` and the RGB channels of `rgba` (RGBA) against `referenceRgb`
// (RGB): the root-mean-square error, and the mean of (x - r)² / (r² + 0.01) (the 0.01 keeps
// black pixels finite). An empty set gives 0.
struct ImageError {
  double rmse = 0, relMse = 0;
};
ImageError errorAgainst(const std::vector<float>& rgba, const std::vector<float>& referenceRgb,
                        const PixelRegion& pixels, int width, int height);

// One counted pixel's squared error: the mean over its RGB channels of (x - r)², so that the
// RMSE is the square root of the mean of `squared` over the counted pixels.
struct PixelError {
  int x = 0, y = 0;
  double squared = 0;
  double value = 0, reference = 0;  // the render's and the reference's mean over RGB (which one is off)
};

// Over the pixels of `pixels` (arguments as errorAgainst): the `k` largest squared errors
// (largest first; ties: the earlier pixel in scan order) and their share of the sum over every
// counted pixel (0 when that sum is 0). One pass, no memory beyond the k pixels.
struct LargestErrors {
  std::vector<PixelError> pixels;
  double share = 0;
  double total = 0;    // the sum of every counted pixel's squared error
  size_t counted = 0;  // pixels counted
};
LargestErrors largestErrors(const std::vector<float>& rgba, const std::vector<float>& referenceRgb,
                            const PixelRegion& pixels, int width, int height, size_t k);

// The RMSE with each pixel's squared error clamped at the `quantile` of them (nearest rank:
// over the n counted pixels sorted by squared error, the ceil(quantile n)-th; 0 < quantile <= 1),
// so at most floor((1 - quantile) n) pixels are clamped, none below 1 / (1 - quantile) pixels;
// never above the RMSE. An empty set gives 0. Holds n doubles while it runs.
double clampedRmse(const std::vector<float>& rgba, const std::vector<float>& referenceRgb, const PixelRegion& pixels,
                   int width, int height, double quantile);

}  // namespace rayes
