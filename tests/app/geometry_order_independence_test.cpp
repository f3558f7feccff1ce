// docs/design.md, invariant 2 for the geometry of issue 3: subdivision faces (per-thread Bfr surface
// caches), displaced patches (interval bounds, border regions) and the thin lens give
// bit-identical images for 1 and 2 threads, with every ray traced alone, and under a ray
// budget small enough to force many batches and iterations.
#include <gtest/gtest.h>
#include "support/render_fixtures.h"

namespace rayes {
namespace {

class GeometryOrderIndependence : public ::testing::TestWithParam<const char*> {};

TEST_P(GeometryOrderIndependence, SameBitsForAnyThreadsModeAndBudget) {
  Scene s = loadScene(testing::sourcePath(GetParam()));
  s.width = 24;
  s.height = 18;
  s.samplesPerPixel = 1;
  testing::expectOrderIndependent(s, 97);
}

INSTANTIATE_TEST_SUITE_P(Scenes, GeometryOrderIndependence,
                         ::testing::Values("scenes/subdiv-creature.json", "scenes/displaced-terrain.json",
                                           "scenes/displaced-teapot.json", "scenes/dof.json"));

}  // namespace
}  // namespace rayes
