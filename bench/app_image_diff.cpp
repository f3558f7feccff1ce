// Compares two renders of the same size (bench/peer_render.sh): prints how many pixels differ at
// all, the RMSE over the RGB channels (as rmseAgainst, docs/stats.md's error_vs_time) and the
// relative difference of the second image's mean from the first's, per channel and overall;
// then the five pixels that differ most (sum over RGB of the squared difference): where a spike
// or a bias sits. With a mask (an OpenEXR of the same size), only the pixels with non-zero red
// count, as `rayes converge --error-mask` counts them.
//
// usage: bench_app_image_diff A.exr B.exr [MASK.exr]
#include <algorithm>
#include <cmath>
#include <functional>
#include <utility>
#include <vector>
#include <cstdio>
#include "app/image_io.h"
#include "app/renderer.h"
#include "core/error.h"

int main(int argc, char** argv) {
  using namespace rayes;
  if (argc != 3 && argc != 4) {
    std::fprintf(stderr, "usage: %s A.exr B.exr [MASK.exr]\n", argv[0]);
    return 2;
  }
  try {
    int wa = 0, ha = 0, wb = 0, hb = 0;
    const std::vector<float> a = readExrRgb(argv[1], wa, ha), b = readExrRgb(argv[2], wb, hb);
    if (wa != wb || ha != hb) throw InputError(argv[2], "", "size differs from " + std::string(argv[1]));
    std::vector<float> mask;
    if (argc == 4) {
      int wm = 0, hm = 0;
      mask = readExrRgb(argv[3], wm, hm);
      if (wm != wa || hm != ha) throw InputError(argv[3], "", "size differs from " + std::string(argv[1]));
    }
    const auto counted = [&](size_t p) { return mask.empty() || mask[3 * p] != 0; };
    double sq = 0, ma[3] = {0, 0, 0}, mb[3] = {0, 0, 0};
    size_t countedPixels = 0;
    for (size_t i = 0; i < a.size(); ++i) {
      if (!counted(i / 3)) continue;
      countedPixels += i % 3 == 0;
      const double d = double(a[i]) - double(b[i]);
      sq += d * d;
      ma[i % 3] += a[i];
      mb[i % 3] += b[i];
    }
    const double n = double(countedPixels);
    std::vector<std::pair<double, size_t>> worst;
    size_t differing = 0;
    for (size_t p = 0; p < a.size() / 3; ++p) {
      if (!counted(p)) continue;
      double d2 = 0;
      for (int c = 0; c < 3; ++c) d2 += (double(a[3 * p + c]) - b[3 * p + c]) * (double(a[3 * p + c]) - b[3 * p + c]);
      worst.push_back({d2, p});
      differing += d2 > 0;
    }
    const size_t shown = std::min<size_t>(5, worst.size());
    std::partial_sort(worst.begin(), worst.begin() + shown, worst.end(), std::greater<>());
    std::printf("differing_pixels %zu of %zu\n", differing, countedPixels);
    std::printf("rmse %.6g mean_a %.6g %.6g %.6g mean_b %.6g %.6g %.6g relative_mean_diff %+.4f %%\n",
                countedPixels == 0 ? 0.0 : std::sqrt(sq / (3 * n)), ma[0] / n, ma[1] / n, ma[2] / n, mb[0] / n,
                mb[1] / n, mb[2] / n, 100.0 * ((mb[0] + mb[1] + mb[2]) / (ma[0] + ma[1] + ma[2]) - 1.0));
    for (size_t k = 0; k < shown; ++k) {
      const size_t p = worst[k].second;
      std::printf("pixel %zu,%zu a %.6g %.6g %.6g b %.6g %.6g %.6g (share of the squared error %.1f %%)\n", p % size_t(wa),
                  p / size_t(wa), a[3 * p], a[3 * p + 1], a[3 * p + 2], b[3 * p], b[3 * p + 1], b[3 * p + 2],
                  sq > 0 ? 100.0 * worst[k].first / sq : 0.0);
    }
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s\n", e.message().c_str());
    return 2;
  }
  return 0;
}
