// Turns a rendered coverage mask into the binary error mask `rayes converge --error-mask` takes
// (bench/lbt_references.sh): a pixel is 1 (counted) where the mask's red is at least THRESHOLD,
// else 0. The mask scene of bench/lbt_error_mask_scene.py renders the fraction of each pixel
// where the camera sees a diffuse surface (or the background) first, so a threshold just below
// 1 keeps only the pixels that see no scatterer anywhere: at a scatterer's edge the light tracer
// connects near-delta lobes to the camera through the pixel, fireflies no method can match.
//
// usage: bench_app_mask_threshold COVERAGE.exr OUT.exr [THRESHOLD, default 0.999]
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>
#include "app/image_io.h"
#include "core/error.h"
#include "rgb_exr.h"

int main(int argc, char** argv) {
  using namespace rayes;
  if (argc != 3 && argc != 4) {
    std::fprintf(stderr, "usage: %s COVERAGE.exr OUT.exr [THRESHOLD]\n", argv[0]);
    return 2;
  }
  try {
    char* end = nullptr;
    const double threshold = argc == 4 ? std::strtod(argv[3], &end) : 0.999;
    if (argc == 4 && (*end != '\0' || !(threshold > 0 && threshold <= 1)))
      throw InputError(argv[3], "", "the threshold must be a number in (0, 1]");
    int w = 0, h = 0;
    const std::vector<float> in = readExrRgb(argv[1], w, h);
    std::vector<float> out(in.size());
    size_t kept = 0;
    for (size_t p = 0; p < in.size() / 3; ++p) {
      const float v = in[3 * p] >= threshold ? 1.0f : 0.0f;
      out[3 * p] = out[3 * p + 1] = out[3 * p + 2] = v;
      kept += v != 0;
    }
    writeRgbExr(argv[2], w, h, out);
    std::printf("%zu of %zu pixels counted (red >= %g)\n", kept, in.size() / 3, threshold);
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s\n", e.message().c_str());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", argv[2], e.what());
    return 2;
  }
  return 0;
}
