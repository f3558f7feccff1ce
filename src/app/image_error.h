// The error of a render against a reference image, over a set of pixels: the one RMSE of the
// program (the renderer's error curve, `rayes converge`). Pure functions; thread-safe.
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

}  // namespace rayes
