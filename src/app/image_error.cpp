#include "app/image_error.h"
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

}  // namespace rayes
