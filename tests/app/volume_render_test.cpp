// Volumes end to end through the path tracer (docs/design.md, "Volumes"): an absorbing slab in
// front of a constant sky transmits e^(−τ) of it (the image mean within four standard errors of
// the Bernoulli estimate each camera path makes), a scattering volume with a lit surface inside
// it renders the same bits for any thread count and batch size, a surface-only scene is not
// changed, and the methods that do not carry media refuse a volume with exit code 2.
#include <filesystem>
#include <fstream>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include "support/render_fixtures.h"
#include "support/temp_folder.h"

namespace rayes {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// Density 1 on voxels [0, 32) × [0, 32) × [0, 16), voxel size 0.1, centred on the origin.
fs::path writeSlab(const fs::path& dir) {
  openvdb::initialize();
  openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.0f);
  g->setName("density");
  g->setTransform(openvdb::math::Transform::createLinearTransform(0.1));
  g->denseFill(openvdb::CoordBBox({0, 0, 0}, {31, 31, 15}), 1.0f, true);
  const fs::path p = dir / "slab.vdb";
  openvdb::io::File(p.string()).write({g});
  return p;
}

// The camera on −z looks through the slab at the sky; `volume` is the volume shape's extra keys;
// a quad far behind the camera (a scene needs a shape), or `insideQuad` one inside the slab.
std::string slabScene(const fs::path& vdb, const std::string& volume, bool insideQuad, int spp) {
  const std::string quad = insideQuad ? R"([[-0.5, -0.5, 0.2], [0.5, -0.5, 0.2], [-0.5, 0.5, -0.3], [0.5, 0.5, -0.3]])"
                                      : R"([[-1, -1, -50], [1, -1, -50], [-1, 1, -50], [1, 1, -50]])";
  return R"({"camera": {"position": [0, 0, -10], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 4},
  "film": {"resolution": [32, 32], "spp": )" + std::to_string(spp) + R"(},
  "materials": {"m": {"type": "diffuse", "albedo": [0.7, 0.7, 0.7]}},
  "shapes": [{"type": "bilinear", "material": "m", "quads": [)" + quad + R"(]},
             {"type": "volume", "file": ")" + vdb.string() + R"(", "transform": [{"translate": [-1.55, -1.55, -0.75]}])" +
         volume + R"(}],
  "lights": [{"type": "environment", "radiance": [1, 1, 1]},
             {"type": "point", "position": [0, 3, 0], "intensity": [4, 4, 4]}]})";
}

TEST(VolumeRender, AbsorbingSlabTransmitsExpOfMinusOpticalDepth) {
  testing::TempFolder dir;
  const fs::path vdb = writeSlab(dir.dir());
  const Scene s = parseScene(slabScene(vdb, R"(, "sigma_a": 0.6, "sigma_s": 0)", false, 16), "slab.json");
  RenderOptions o;
  const std::vector<float> rgba = testing::renderBeauty(s, o, 2);
  double sum = 0;
  for (size_t i = 0; i < rgba.size(); i += 4) sum += rgba[i];
  const double n = double(rgba.size() / 4) * 16;  // camera paths, each 1 (escaped) or 0
  const double mean = sum / double(rgba.size() / 4);
  // Along z the density is 1 on index [0, 15] and the trilinear ramp of the half voxels at
  // either end adds 2 × 3/8: τ = 0.6 × 0.1 × 15.75. Rays off the axis by at most 2.9° travel
  // 1/cos ≤ 1.0013 times as far: a bias below 4e-4, a tenth of the tolerance.
  const double expected = std::exp(-0.6 * 0.1 * 15.75);
  const double se = std::sqrt(expected * (1 - expected) / n);
  EXPECT_NEAR(mean, expected, 4 * se + 4e-4);
}

TEST(VolumeRender, ScatteringVolumeWithASurfaceInsideIsTheSameForAnyThreadsAndBatches) {
  testing::TempFolder dir;
  const fs::path vdb = writeSlab(dir.dir());
  const Scene s = parseScene(slabScene(vdb, R"(, "sigma_a": 0.2, "sigma_s": 4, "g": 0.5)", true, 4), "slab.json");
  testing::expectOrderIndependent(s, 300);
  // Something scattered and something reached the film through the medium.
  const std::vector<float> rgba = testing::renderBeauty(s, {}, 2);
  double sum = 0;
  for (size_t i = 0; i < rgba.size(); i += 4) sum += rgba[i];
  EXPECT_GT(sum, 0);
}

TEST(VolumeRender, OtherMethodsRefuseAVolumeWithExitCode2AndNoOutput) {
  testing::TempFolder dir;
  const fs::path vdb = writeSlab(dir.dir());
  const fs::path scene = dir.dir() / "slab.json";
  std::ofstream(scene) << slabScene(vdb, "", false, 1);
  for (const char* method : {"lt", "pm", "ppm", "lbt"}) {
    const fs::path out = dir.dir() / (std::string(method) + ".exr");
    const testing::RunResult r = testing::runRayes({"render", scene.string(), "--method", method, "-o", out.string()});
    EXPECT_EQ(r.code, 2) << method;
    EXPECT_THAT(r.err, HasSubstr("does not render volumes yet")) << method;
    EXPECT_FALSE(fs::exists(out)) << method;
  }
}

}  // namespace
}  // namespace rayes
