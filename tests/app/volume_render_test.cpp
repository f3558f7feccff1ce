// Volumes end to end through the path tracer (docs/design.md, "Volumes"): an absorbing slab in
// front of a constant sky transmits e^(−τ) of it (the image mean within four standard errors of
// the Bernoulli estimate each camera path makes), a scattering volume with a lit surface inside
// it renders the same bits for any thread count and batch size, a surface-only scene is not
// changed, and the methods that do not carry media refuse a volume with exit code 2.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include "scene/vdb_grid.h"
#include "shading/blackbody.h"
#include "support/rayes_process.h"
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

// A heterogeneous cloud of 64³ voxels (512 leaves, 1 MiB of voxels): a ball of hashed densities.
fs::path writeCloud(const fs::path& dir) {
  openvdb::initialize();
  openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.0f);
  g->setName("density");
  g->setTransform(openvdb::math::Transform::createLinearTransform(3.0 / 64));
  auto acc = g->getAccessor();
  for (int x = 0; x < 64; ++x)
    for (int y = 0; y < 64; ++y)
      for (int z = 0; z < 64; ++z) {
        const uint32_t h = (uint32_t(x) * 73856093u) ^ (uint32_t(y) * 19349663u) ^ (uint32_t(z) * 83492791u);
        acc.setValue({x, y, z}, float(h % 1000) / 500.0f);
      }
  const fs::path p = dir / "cloud.vdb";
  openvdb::io::File(p.string()).write({g});
  return p;
}

TEST(VolumeRender, ACloudEightTimesTheBrickCacheRendersTheSameBitsAsWithEveryBrickInMemory) {
  testing::TempFolder dir;
  const fs::path vdb = writeCloud(dir.dir());
  std::string text = slabScene(vdb, R"(, "sigma_a": 0.1, "sigma_s": 2, "g": 0.3)", true, 2);
  const Scene s = parseScene(text, "cloud.json");
  ASSERT_EQ(s.media.size(), 1u);
  ASSERT_EQ(s.media[0]->densityGrid().storedBricks(), 512u);
  const uint64_t cloudBytes = 512 * BrickCache::kSlotBytes;
  auto render = [&](uint64_t budget, int threads, BrickCacheStats& cache) {
    ThreadLimit limit(threads);
    RenderOptions o;
    o.volumeMemoryBytes = budget;
    Renderer r(s, o);
    const Film film = r.render();
    cache = r.stats().volumeCache.value();
    return film.beautyRgba();
  };
  BrickCacheStats all, small, smallOneThread;
  const std::vector<float> ref = render(RenderOptions::kVolumeMemoryDefault, 2, all);
  EXPECT_EQ(all.evictions, 0u);
  EXPECT_LE(all.loads, 512u);
  EXPECT_EQ(render(cloudBytes / 8, 2, small), ref) << "a cache of an eighth of the cloud, 2 threads";
  EXPECT_EQ(render(cloudBytes / 8, 1, smallOneThread), ref) << "a cache of an eighth of the cloud, 1 thread";
  // The small cache really was small: it evicted, re-read bricks, and held no more than its budget.
  EXPECT_GT(small.evictions, 0u);
  EXPECT_GT(small.loads, all.loads);
  EXPECT_LE(small.slotsUsed * BrickCache::kSlotBytes, cloudBytes / 8);
}

// The bricks are top-level leaves (core/medium_leaves.h): the sorted engine tracks each brick's
// run of rays, a closest ray's collision competing with surface hits and a shadow ray's factors
// multiplied in any order. Rays traced alone (`--trace-mode alone`), and the Embree engine, leave
// the tracking to the path tracer's walk of each ray, through the same per-brick functions with
// the same streams: the same bits. So are other candidate counts and ray budgets (other sort
// orders and batches). The cloud alone for the Embree engine (its surfaces are diced otherwise).
TEST(VolumeRender, BrickLeavesOfTheSortedEngineAndThePerRayWalkRenderTheSameBits) {
  testing::TempFolder dir;
  const fs::path vdb = writeCloud(dir.dir());
  auto render = [&](const Scene& s, RenderOptions o, uint64_t* lookups = nullptr) {
    Renderer r(s, o);
    const Film film = r.render();
    if (lookups) *lookups = r.stats().shade.densityLookups.load();
    return film.beautyRgba();
  };
  for (const bool surface : {true, false}) {
    const Scene s = parseScene(slabScene(vdb, R"(, "sigma_a": 0.1, "sigma_s": 2, "g": 0.3)", surface, 2), "cloud.json");
    uint64_t sortedLookups = 0, walkedLookups = 0;
    const std::vector<float> ref = render(s, {}, &sortedLookups);
    RenderOptions alone;
    alone.sortByLeaf = false;
    EXPECT_EQ(render(s, alone, &walkedLookups), ref) << "rays traced alone: the per-ray walk";
    // Both tracked (their counts differ: the engine may track a brick before it learns of a
    // nearer hit or an occluder, the walk stops at them).
    EXPECT_GT(sortedLookups, 0u);
    EXPECT_GT(walkedLookups, 0u);
    RenderOptions one;
    one.candidatesPerRay = 1;
    EXPECT_EQ(render(s, one), ref) << "one candidate per ray";
    RenderOptions small;
    small.rayMemoryBytes = 64 << 10;
    EXPECT_EQ(render(s, small), ref) << "small batches";
    if (!surface) {
      RenderOptions embree;
      embree.engine = EngineKind::Embree;
      EXPECT_EQ(render(s, embree), ref) << "the Embree engine";
    }
  }
}

TEST(VolumeRender, VolumeMemoryZeroTooSmallOrBeyondMemoryIsRefusedNamingTheOption) {
  testing::TempFolder dir;
  const fs::path vdb = writeCloud(dir.dir());
  const fs::path scene = dir.dir() / "cloud.json";
  std::ofstream(scene) << slabScene(vdb, "", false, 1);
  const fs::path out = dir.dir() / "out.exr";
  for (const char* bytes : {"0", "1K"}) {
    const testing::RunResult r =
        testing::runRayes({"render", scene.string(), "--volume-memory", bytes, "-o", out.string()});
    EXPECT_EQ(r.code, 2) << bytes;
    EXPECT_THAT(r.err, HasSubstr("--volume-memory")) << bytes;
  }
  const testing::RunResult r =
      testing::runRayes({"render", scene.string(), "--volume-memory", "900000G", "-o", out.string()});
  EXPECT_EQ(r.code, 3);
  EXPECT_THAT(r.err, HasSubstr("--volume-memory"));
  EXPECT_FALSE(fs::exists(out));
}

// OpenVDB is a module the program loads at a scene's first volume (scene/vdb_grid.h,
// core/plugin_module.h): a scene without a volume never maps OpenVDB -- by the dynamic loader's
// own record of what it loaded (LD_DEBUG=files) -- and its stats list the volumes as skipped; a
// scene with one loads the module and OpenVDB. Without the module (RAYES_MODULE_DIR names a
// folder without it, standing for a program copied without it) a volume is refused with one
// message naming the module and where it was looked for, exit code 2 and nothing written.
TEST(VolumeRender, OpenVdbIsLoadedOnlyForASceneWithAVolume) {
  testing::TempFolder dir;
  const fs::path vdb = writeSlab(dir.dir());
  std::ofstream(dir.dir() / "volume.json") << slabScene(vdb, "", false, 1);
  std::ofstream(dir.dir() / "plain.json") << R"({"camera": {"position": [0, 0, -10], "look_at": [0, 0, 0], "up": [0, 1, 0]},
  "film": {"resolution": [16, 16], "spp": 1}, "materials": {"m": {"type": "diffuse", "albedo": 0.5}},
  "shapes": [{"type": "bilinear", "material": "m", "quads": [[[-1, -1, 0], [1, -1, 0], [-1, 1, 0], [1, 1, 0]]]}],
  "lights": [{"type": "environment", "radiance": [1, 1, 1]}]})";
  auto run = [&](const std::string& scene, const fs::path& out) {
    const auto r = testing::runRayesProcess({"render", (dir.dir() / scene).string(), "-o", out.string(), "--stats",
                                             (dir.dir() / (scene + ".stats.json")).string(), "-q"},
                                            {.env = {"LD_DEBUG=files"}});
    EXPECT_EQ(r.code, 0) << r.err;
    return r.err;
  };
  const std::string plain = run("plain.json", dir.dir() / "plain.exr");
  EXPECT_THAT(plain, ::testing::Not(HasSubstr("libopenvdb")));
  EXPECT_THAT(plain, ::testing::Not(HasSubstr(kVdbModuleName)));
  EXPECT_THAT(plain, HasSubstr("libembree3")) << "LD_DEBUG=files lists the libraries loaded";
  std::ifstream in(dir.dir() / "plain.json.stats.json");
  const nlohmann::json stats = nlohmann::json::parse(in);
  EXPECT_THAT(stats.at("skipped").at("volumes").get<std::string>(), HasSubstr("OpenVDB not loaded"));
  const std::string volume = run("volume.json", dir.dir() / "volume.exr");
  EXPECT_THAT(volume, HasSubstr(std::string("file=") + (fs::path(testing::rayesBinary()).parent_path() / kVdbModuleName).string()));
  EXPECT_THAT(volume, HasSubstr("file=libopenvdb"));

  const testing::TempFolder empty;
  const fs::path out = empty.dir() / "o.exr";
  const auto refused = testing::runRayesProcess({"render", (dir.dir() / "volume.json").string(), "-o", out.string(), "-q"},
                                                {.env = {"RAYES_MODULE_DIR=" + empty.dir().string()}});
  EXPECT_EQ(refused.code, 2) << refused.err;
  EXPECT_THAT(refused.err, HasSubstr((empty.dir() / kVdbModuleName).string() + ": no such file"));
  EXPECT_EQ(std::count(refused.err.begin(), refused.err.end(), '\n'), 1) << "one message: " << refused.err;
  EXPECT_FALSE(fs::exists(out));
}

// The mean of an image's red channel and its standard error (the pixels are independent
// estimates of the same value: their spread over √pixels).
struct MeanAndError {
  double mean, se;
};
MeanAndError redMean(const std::vector<float>& rgba) {
  const double n = double(rgba.size() / 4);
  double sum = 0, sq = 0;
  for (size_t i = 0; i < rgba.size(); i += 4) sum += rgba[i], sq += double(rgba[i]) * rgba[i];
  const double mean = sum / n;
  return {mean, std::sqrt(std::max(0.0, sq / n - mean * mean) / (n - 1))};
}

// The slab of writeSlab, and an emission grid of 1 on voxels [−8, 40)³ (covering every point
// where the slab's density is not 0), in one file.
fs::path writeEmittingSlab(const fs::path& dir) {
  openvdb::initialize();
  auto transform = openvdb::math::Transform::createLinearTransform(0.1);
  openvdb::FloatGrid::Ptr density = openvdb::FloatGrid::create(0.0f), emission = openvdb::FloatGrid::create(0.0f);
  density->setName("density");
  density->setTransform(transform);
  density->denseFill(openvdb::CoordBBox({0, 0, 0}, {31, 31, 15}), 1.0f, true);
  emission->setName("emission");
  emission->setTransform(transform->copy());
  emission->denseFill(openvdb::CoordBBox({-8, -8, -8}, {39, 39, 39}), 1.0f, true);
  const fs::path p = dir / "emitting_slab.vdb";
  openvdb::io::File(p.string()).write({density, emission});
  return p;
}

// A purely absorbing, emitting slab in front of black: along a ray the radiance L(s) (s from
// the far side toward the camera) obeys dL/ds = −σ_a ρ(s) L + σ_a ρ(s) Le, with L = 0 behind
// the slab (nothing there emits or reflects). With τ(s) = ∫₀^s σ_a ρ, d/ds (L e^τ) = σ_a ρ Le e^τ,
// so L = Le ∫ σ_a ρ e^(τ(s) − τ) ds = Le (1 − e^(−τ)) whatever the profile ρ, τ the slab's whole
// optical depth (0.6 × 0.1 × 15.75 along z: the test above). Le = 2 (the emission colour times
// a grid of 1 wherever ρ > 0).
TEST(VolumeRender, EmittingAbsorbingSlabGivesLeTimesOneMinusExpOfMinusOpticalDepth) {
  testing::TempFolder dir;
  const fs::path vdb = writeEmittingSlab(dir.dir());
  const std::string scene = R"({"camera": {"position": [0, 0, -10], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 4},
  "film": {"resolution": [32, 32], "spp": 64},
  "materials": {"black": {"type": "diffuse", "albedo": [0, 0, 0]}},
  "shapes": [{"type": "bilinear", "material": "black", "quads": [[[-1, -1, 50], [1, -1, 50], [-1, 1, 50], [1, 1, 50]]]},
             {"type": "volume", "file": ")" + vdb.string() + R"(", "transform": [{"translate": [-1.55, -1.55, -0.75]}],
              "sigma_a": 0.6, "sigma_s": 0, "emission_grid": "emission", "emission": [2, 2, 2]}],
  "lights": [{"type": "point", "position": [0, 0, -20], "intensity": [1, 1, 1]}]})";
  const Scene s = parseScene(scene, "emitting_slab.json");
  const MeanAndError m = redMean(testing::renderBeauty(s, {}, 2));
  const double expected = 2 * (1 - std::exp(-0.6 * 0.1 * 15.75));
  // Rays off the axis by at most 2.9° travel at most 1.0013 times as far: τ at most 0.0013 τ
  // larger, L at most 2 e^(−τ) · 0.0013 τ = 9e-4 larger.
  EXPECT_NEAR(m.mean, expected, 4 * m.se + 9e-4);
  EXPECT_GT(m.se, 0);
  // The test can see a 3 % error (an emission term off by a factor, a lost transmittance would be far more).
  EXPECT_LT(4 * m.se + 9e-4, 0.03 * expected) << "se " << m.se;
}

// The same slab emitting as a blackbody: a temperature grid of 1 wherever ρ > 0, at 3000 K
// per unit and a blackbody scale of 2, so Le = 2 · blackbodyRgb(3000 K) per channel and, by the
// derivation above, L = Le (1 − e^(−τ)) in each of red, green and blue (a warm colour: red
// above green above blue, which a swapped channel or a wrong temperature would break).
TEST(VolumeRender, BlackbodySlabGivesItsPlanckColourTimesOneMinusExpOfMinusOpticalDepth) {
  testing::TempFolder dir;
  openvdb::initialize();
  auto transform = openvdb::math::Transform::createLinearTransform(0.1);
  openvdb::FloatGrid::Ptr density = openvdb::FloatGrid::create(0.0f), temperature = openvdb::FloatGrid::create(0.0f);
  density->setName("density");
  density->setTransform(transform);
  density->denseFill(openvdb::CoordBBox({0, 0, 0}, {31, 31, 15}), 1.0f, true);
  temperature->setName("temperature");
  temperature->setTransform(transform->copy());
  temperature->denseFill(openvdb::CoordBBox({-8, -8, -8}, {39, 39, 39}), 1.0f, true);
  const fs::path vdb = dir.dir() / "blackbody_slab.vdb";
  openvdb::io::File(vdb.string()).write({density, temperature});
  const std::string scene = R"({"camera": {"position": [0, 0, -10], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 4},
  "film": {"resolution": [32, 32], "spp": 64},
  "materials": {"black": {"type": "diffuse", "albedo": [0, 0, 0]}},
  "shapes": [{"type": "bilinear", "material": "black", "quads": [[[-1, -1, 50], [1, -1, 50], [-1, 1, 50], [1, 1, 50]]]},
             {"type": "volume", "file": ")" + vdb.string() + R"(", "transform": [{"translate": [-1.55, -1.55, -0.75]}],
              "sigma_a": 0.6, "sigma_s": 0, "temperature_grid": "temperature", "temperature_scale": 3000,
              "blackbody_scale": 2}],
  "lights": [{"type": "point", "position": [0, 0, -20], "intensity": [1, 1, 1]}]})";
  const Scene s = parseScene(scene, "blackbody_slab.json");
  const std::vector<float> rgba = testing::renderBeauty(s, {}, 2);
  const Rgb Le = blackbodyRgb(3000) * 2.0f;
  ASSERT_GT(Le.x, Le.y);
  ASSERT_GT(Le.y, Le.z);
  ASSERT_GT(Le.z, 0);
  const double opacity = 1 - std::exp(-0.6 * 0.1 * 15.75);
  const double le[3] = {Le.x, Le.y, Le.z};
  for (int c = 0; c < 3; ++c) {
    const double n = double(rgba.size() / 4);
    double sum = 0, sq = 0;
    for (size_t i = size_t(c); i < rgba.size(); i += 4) sum += rgba[i], sq += double(rgba[i]) * rgba[i];
    const double mean = sum / n, se = std::sqrt(std::max(0.0, sq / n - mean * mean) / (n - 1));
    // As above: rays off the axis add at most Le e^(−τ) · 0.0013 τ.
    const double bound = le[c] * std::exp(-0.6 * 0.1 * 15.75) * 0.0013 * (0.6 * 0.1 * 15.75);
    EXPECT_NEAR(mean, le[c] * opacity, 4 * se + bound) << "channel " << c;
    EXPECT_GT(se, 0) << "channel " << c;
  }
}

// A furnace: inside a uniform environment of radiance 1, a non-absorbing medium (albedo 1) and a
// white diffuse quad (albedo 1) change nothing: every point sees radiance 1 from every direction,
// so every pixel's expectation is exactly 1 (energy is conserved through any number of
// scatterings). Russian roulette is unbiased; the depth cap of 200 vertices leaves out paths of
// more scatterings than the slab's optical depth (2 × 1.575 along z) makes likely at all.
TEST(VolumeRender, ScatteringMediumOfAlbedoOneInAUniformEnvironmentConservesEnergy) {
  testing::TempFolder dir;
  const fs::path vdb = writeSlab(dir.dir());
  for (const char* g : {"0", "0.6"}) {
    const std::string scene = R"({"camera": {"position": [0, 0, -4], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 40},
    "film": {"resolution": [24, 24], "spp": 16},
    "integrator": {"max_depth": 200},
    "materials": {"white": {"type": "diffuse", "albedo": [1, 1, 1]}},
    "shapes": [{"type": "bilinear", "material": "white", "quads": [[[-1, -1, 0.3], [1, -1, 0.3], [-1, 1, 0.9], [1, 1, 0.9]]]},
               {"type": "volume", "file": ")" + vdb.string() + R"(", "transform": [{"translate": [-1.55, -1.55, -0.75]}],
                "sigma_a": 0, "sigma_s": 2, "g": )" + g + R"(}],
    "lights": [{"type": "environment", "radiance": [1, 1, 1]}]})";
    const Scene s = parseScene(scene, "furnace.json");
    const MeanAndError m = redMean(testing::renderBeauty(s, {}, 2));
    EXPECT_NEAR(m.mean, 1.0, 4 * m.se) << "g " << g;
    EXPECT_GT(m.se, 0) << "g " << g;  // something scattered: the pixels are not all exactly 1
    EXPECT_LT(4 * m.se, 0.03) << "g " << g << ": the test can see a 3 % loss or gain of energy";
  }
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
