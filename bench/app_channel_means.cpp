// Reference values for the end-to-end tests that check a render's per-channel means
// (tests/app/render_fixtures.h, expectChannelMeans): renders a scene at the given size with
// seeds 5000.. and prints, per channel, the mean over seeds of the image mean and the standard
// deviation of one render's image mean. Not a timing.
//   bench_app_channel_means SCENE WIDTH HEIGHT SPP SEEDS
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include "app/renderer.h"
#include "scene/scene_loader.h"
int main(int argc, char** argv) {
  if (argc < 6) {
    std::fprintf(stderr, "usage: %s SCENE WIDTH HEIGHT SPP SEEDS\n", argv[0]);
    return 2;
  }
  rayes::Scene scene = rayes::loadScene(argv[1]);
  scene.width = std::atoi(argv[2]); scene.height = std::atoi(argv[3]); scene.samplesPerPixel = std::atoi(argv[4]);
  const int seeds = std::atoi(argv[5]);
  double s[3] = {0, 0, 0}, ss[3] = {0, 0, 0};
  for (int k = 0; k < seeds; ++k) {
    scene.integrator.seed = 5000 + k;
    rayes::RenderOptions o;
    rayes::Renderer r(scene, o);
    const auto rgba = r.render().beautyRgba();
    for (int c = 0; c < 3; ++c) {
      double m = 0;
      for (size_t i = c; i < rgba.size(); i += 4) m += rgba[i];
      m /= double(rgba.size() / 4);
      s[c] += m; ss[c] += m * m;
    }
  }
  for (int c = 0; c < 3; ++c) {
    const double mu = s[c] / seeds, sd = std::sqrt((ss[c] - seeds * mu * mu) / (seeds - 1));
    std::printf("%s ch%d mean %.6f sd %.6f\n", argv[1], c, mu, sd);
  }
}
