// Photon mapping (`--method pm`) and progressive photon mapping (`--method ppm`) against the
// light tracer on the mirror caustic (mirror_caustic_scene.h), where the light tracer sees
// every path the camera can.
//  - Both converge to the light tracer's image: the image mean and every 4 x 3 block mean agree
//    within 4 standard errors measured over 32 independent seeds of each method (Student-t
//    with 31 degrees of freedom). The kernel's blur moves flux only across the caustic's
//    edges; the gather radius (r0: the median 32nd-neighbour distance) is a few percent of a
//    block, which the test's resolution of the standard error does not see -- if it did, the
//    test would fail, which is the point.
//  - ppm's bias shrinks with passes: its mean absolute block error against the light tracer
//    falls from 2 to 64 samples per pixel.
//  - Images are bit-identical for 1 and 2 threads, every ray alone, and a budget of 37 paths.
//  - max_depth bounds the whole path, camera and photon sides together, as in the path tracer
//    pm complements: at max_depth 1 the mirror caustic (floor, mirror, light: 2 bounces) is no
//    path at all, and pm is the path tracer without caustic paths, bit for bit. (This scene has
//    no diffuse vertex after the first hit, so it checks the photon side's bound; the camera
//    side's share, bounce + photon vertex <= max_depth, is the same comparison in the gather.)
#include <cmath>
#include <gtest/gtest.h>
#include "support/mirror_caustic_scene.h"
#include "support/render_fixtures.h"

namespace rayes {
namespace {

RenderOptions method(const std::string& m) {
  RenderOptions o;
  o.method.name = m;
  o.lod = LodRule::Fixed;
  o.maxLod = 3;
  o.method.photons.photonsPerSample = 4000;
  return o;
}

void expectMatchesLightTracer(const std::string& m) {
  const Scene scene = testing::mirrorCausticScene(16, 12, 4);
  constexpr int kSeeds = 32;
  const testing::BlockEstimate lt = testing::blockEstimate(scene, method("lt"), kSeeds);
  const testing::BlockEstimate pm = testing::blockEstimate(scene, method(m), kSeeds);
  for (size_t b = 0; b < lt.mean.size(); ++b) {
    const double se = std::hypot(lt.se[b], pm.se[b]);
    EXPECT_LE(std::fabs(pm.mean[b] - lt.mean[b]), 4 * se)
        << "block " << b << ": " << pm.mean[b] << " +- " << pm.se[b] << ", lt " << lt.mean[b] << " +- " << lt.se[b];
  }
}

TEST(PhotonMapping, ConvergesToTheLightTracer) { expectMatchesLightTracer("pm"); }

TEST(ProgressivePhotonMapping, ConvergesToTheLightTracer) {
  expectMatchesLightTracer("ppm");
}

TEST(ProgressivePhotonMapping, BiasShrinksWithPasses) {
  const testing::BlockEstimate lt =
      testing::blockEstimate(testing::mirrorCausticScene(16, 12, 16), method("lt"), 16);
  auto error = [&](int spp) {
    const testing::BlockEstimate e =
        testing::blockEstimate(testing::mirrorCausticScene(16, 12, spp), method("ppm"), 4);
    double sum = 0;
    for (size_t b = 0; b + 1 < e.mean.size(); ++b) sum += std::fabs(e.mean[b] - lt.mean[b]);
    return sum;
  };
  EXPECT_LT(error(64), error(2));
}

TEST(PhotonMapping, MaxDepthBoundsCameraAndPhotonBouncesTogether) {
  for (const char* m : {"pm", "ppm"}) {
    Scene scene = testing::mirrorCausticScene(12, 9, 2);
    RenderOptions without = method("pt");
    without.method.causticPaths = CausticPaths::Without;
    scene.integrator.maxDepth = 1;
    EXPECT_EQ(testing::renderBeauty(scene, method(m), 2), testing::renderBeauty(scene, without, 2));
    // One bounce more and the caustic is there (the check above is not vacuous).
    scene.integrator.maxDepth = 2;
    EXPECT_NE(testing::renderBeauty(scene, method(m), 2), testing::renderBeauty(scene, without, 2));
  }
}

TEST(PhotonMapping, OrderIndependent) {
  testing::expectOrderIndependent(testing::mirrorCausticScene(12, 9, 2), 37, method("pm"));
  testing::expectOrderIndependent(testing::mirrorCausticScene(12, 9, 4), 37,
                                  method("ppm"));
}

}  // namespace
}  // namespace rayes
