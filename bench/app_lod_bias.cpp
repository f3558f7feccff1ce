// The mean radiance of a scene with per-ray level of detail against the thesis's density rule
// (every ray of a leaf at the level its ray count needs: much finer for secondary rays), with
// the standard error of the relative difference from independent seeds, each seed rendered
// both ways. Not a timing: the figures go to bench/RESULTS.md with the command.
//   bench_app_lod_bias SCENE WIDTH HEIGHT SPP SEEDS
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include "app/renderer.h"
#include "core/parallel.h"
#include "scene/scene_loader.h"

namespace {

double meanRadiance(const rayes::Scene& scene, const rayes::RenderOptions& options) {
  rayes::Renderer r(scene, options);
  const std::vector<float> rgba = r.render().beautyRgba();
  double sum = 0;
  for (size_t i = 0; i < rgba.size(); i += 4) sum += (double(rgba[i]) + rgba[i + 1] + rgba[i + 2]) / 3;
  return sum / double(rgba.size() / 4);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 6) {
    std::fprintf(stderr, "usage: %s SCENE WIDTH HEIGHT SPP SEEDS\n", argv[0]);
    return 2;
  }
  rayes::Scene scene = rayes::loadScene(argv[1]);
  scene.width = std::atoi(argv[2]);
  scene.height = std::atoi(argv[3]);
  scene.samplesPerPixel = std::atoi(argv[4]);
  const int seeds = std::atoi(argv[5]);
  rayes::RenderOptions perRay, density;
  density.lod = rayes::LodRule::Density;
  // Paired by seed: the two renders share their random numbers, so the difference has a far
  // smaller standard error than either mean.
  double sa = 0, sb = 0, sd = 0, sdd = 0, saa = 0;
  for (int s = 0; s < seeds; ++s) {
    scene.integrator.seed = uint64_t(s) + 1000;
    const double a = meanRadiance(scene, perRay), b = meanRadiance(scene, density);
    const double d = a / b - 1;
    sa += a; saa += a * a; sb += b; sd += d; sdd += d * d;
    std::printf("seed %d: per-ray %.6f density %.6f relative difference %+.4f %%\n", s, a, b, 100 * d);
    std::fflush(stdout);
  }
  const double n = seeds, md = sd / n, seD = std::sqrt(std::max(0.0, (sdd - n * md * md) / (n - 1)) / n);
  const double ma = sa / n, seA = std::sqrt(std::max(0.0, (saa - n * ma * ma) / (n - 1)) / n);
  std::printf("per-ray mean %.6f (SE %.6f), density mean %.6f; per-ray / density - 1 = %+.3f %% +- %.3f %% (SE)\n",
              ma, seA, sb / n, 100 * md, 100 * seD);
  return 0;
}
