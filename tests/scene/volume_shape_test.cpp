// The `volume` shape kind (docs/scene-format.md): a float grid of a .vdb file, written here with
// OpenVDB itself, becomes a Medium of 8³ bricks (one per leaf node, one per 8³ block of an active
// tile) with the file's voxels, the grid's and the scene's transforms, and the coefficients times
// the density scale; every bad file, grid or value is one InputError naming the file and the grid.
#include <gtest/gtest.h>
#include <filesystem>
#include <fstream>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include "scene/scene_loader.h"
#include "scene_text.h"
#include "support/temp_folder.h"

namespace rayes {
namespace {

namespace fs = std::filesystem;

// The test's own folder (support/temp_folder.h), removed after it.
class VolumeShape : public ::testing::Test {
 protected:
  testing::TempFolder folder;
};

// A density grid with voxel (x, y, z) = 0.01·(x + 2y + 3z) + 0.1 for x, y, z in [0, 12) (two
// leaves per axis, partly filled), voxel size 0.25, written as `name` into `file`.
fs::path writeGrid(const fs::path& dir, const std::string& file, const std::string& name = "density",
                   float negativeAt = 0) {
  openvdb::initialize();
  openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.0f);
  g->setName(name);
  g->setTransform(openvdb::math::Transform::createLinearTransform(0.25));
  auto acc = g->getAccessor();
  for (int x = 0; x < 12; ++x)
    for (int y = 0; y < 12; ++y)
      for (int z = 0; z < 12; ++z) acc.setValue({x, y, z}, 0.01f * float(x + 2 * y + 3 * z) + 0.1f);
  if (negativeAt != 0) acc.setValue({5, 5, 5}, negativeAt);
  const fs::path p = dir / file;
  openvdb::io::File(p.string()).write({g});
  return p;
}

std::string volumeScene(const fs::path& vdb, const std::string& extra = "") {
  const std::string base = test::minimalScene();
  return base.substr(0, base.rfind("}]")) + R"(}, {"type": "volume", "file": ")" + vdb.string() + "\"" + extra + "}]}";
}

TEST_F(VolumeShape, LeavesBecomeBricksWithTheFilesVoxels) {
  const fs::path vdb = writeGrid(folder.dir(), "grid.vdb");
  const Scene s = parseScene(volumeScene(vdb, R"(, "density_scale": 2, "sigma_a": 0.5, "sigma_s": 3, "g": 0.4)"),
                             "scene.json");
  ASSERT_EQ(s.media.size(), 1u);
  const Medium& m = *s.media[0];
  EXPECT_EQ(m.bricks(), 8u);  // voxels [0, 12)³ touch 2 leaves per axis
  EXPECT_EQ(s.leaves.size(), 1u);  // a volume adds no leaf
  for (int x = 0; x < 16; x += 3)
    for (int y = 0; y < 16; y += 5)
      for (int z = 0; z < 16; z += 7) {
        const float expected = x < 12 && y < 12 && z < 12 ? 0.01f * float(x + 2 * y + 3 * z) + 0.1f : 0.0f;
        EXPECT_EQ(m.voxel(x, y, z), expected) << x << " " << y << " " << z;
      }
  EXPECT_FLOAT_EQ(m.coefficients().sigmaA, 1.0f);
  EXPECT_FLOAT_EQ(m.coefficients().sigmaS, 6.0f);
  EXPECT_FLOAT_EQ(m.coefficients().g, 0.4f);
  // Index space [−½, 15.5)³ at voxel size 0.25, in the render frame (world minus the camera).
  EXPECT_FLOAT_EQ(m.worldBounds().lo.x, float(-0.125 - s.frame.origin.x));
  EXPECT_FLOAT_EQ(m.worldBounds().hi.z, float(3.875 - s.frame.origin.z));
}

TEST_F(VolumeShape, SceneTransformAppliesAfterTheGridsOwn) {
  const fs::path vdb = writeGrid(folder.dir(), "moved.vdb");
  const Scene s = parseScene(volumeScene(vdb, R"(, "transform": [{"translate": [10, 0, 0]}])"), "scene.json");
  const Vec3 at10 = (Vec3d{10, 0, 0} - s.frame.origin).toFloat();  // world (10, 0, 0) in the render frame
  EXPECT_FLOAT_EQ(s.media[0]->worldBounds().lo.x, float(9.875 - s.frame.origin.x));
  EXPECT_FLOAT_EQ(s.media[0]->worldToIndex().point(at10).x, 0.0f);
}

TEST_F(VolumeShape, ActiveTileBecomesBricksOfItsValue) {
  openvdb::initialize();
  openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.0f);
  g->setName("density");
  g->tree().addTile(2, openvdb::Coord(0), 0.5f, true);  // one 128³ tile (level 2): 16³ bricks
  const fs::path p = folder.dir() / "tile.vdb";
  openvdb::io::File(p.string()).write({g});
  const Scene s = parseScene(volumeScene(p), "scene.json");
  EXPECT_EQ(s.media[0]->bricks(), 16u * 16u * 16u);
  EXPECT_EQ(s.media[0]->voxel(100, 3, 127), 0.5f);
}

// The message of each bad input names the .vdb file and the grid.
void expectRefused(const std::string& sceneText, const std::string& file, const std::string& words) {
  const std::string msg = test::errorOf(sceneText);
  EXPECT_NE(msg.find(file), std::string::npos) << msg;
  EXPECT_NE(msg.find(words), std::string::npos) << msg;
}

TEST_F(VolumeShape, BadInputIsOneInputErrorNamingFileAndGrid) {
  const fs::path good = writeGrid(folder.dir(), "good.vdb");
  expectRefused(volumeScene(folder.dir() / "missing.vdb"), "missing.vdb", "cannot open file");
  expectRefused(volumeScene(good, R"(, "grid": "smoke")"), "good.vdb", "no grid named 'smoke' (it has: density)");
  expectRefused(volumeScene(good, R"(, "density_scale": -1)"), "density_scale", "not negative");
  // Singular to float precision, with voxel edges of ordinary length (an exactly singular matrix
  // is the transform reader's refusal; a vanishing edge the precision check's).
  expectRefused(volumeScene(good, R"(, "transform": [{"matrix": [1, 0, 1, 0, 0, 1, 1, 0, 0, 0, 1e-13, 0]}])"),
                "grid 'density'", "not invertible");
  expectRefused(volumeScene(good, R"(, "transform": [{"matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1e-14, 0]}])"),
                "grid 'density'", "cannot be represented");
  expectRefused(volumeScene(good, R"(, "transform": [{"translate": [1e5, 0, 0]}])"), "grid 'density'",
                "cannot be represented");
  expectRefused(volumeScene(writeGrid(folder.dir(), "negative.vdb", "density", -2)), "negative.vdb", "at voxel (5, 5, 5)");

  const fs::path garbage = folder.dir() / "garbage.vdb";
  std::ofstream(garbage) << "not a vdb file at all, just some bytes that are long enough to read a header from";
  expectRefused(volumeScene(garbage), "garbage.vdb", "cannot read");

  // A file cut in half.
  const fs::path cut = folder.dir() / "cut.vdb";
  fs::copy_file(good, cut, fs::copy_options::overwrite_existing);
  fs::resize_file(cut, fs::file_size(good) / 2);
  expectRefused(volumeScene(cut), "cut.vdb", "cannot read");

  // A grid of vectors.
  openvdb::Vec3SGrid::Ptr v = openvdb::Vec3SGrid::create();
  v->setName("density");
  v->tree().setValue({0, 0, 0}, openvdb::Vec3s(1, 2, 3));
  const fs::path vec = folder.dir() / "vector.vdb";
  openvdb::io::File(vec.string()).write({v});
  expectRefused(volumeScene(vec), "vector.vdb", "holds vec3s values");

  // A non-zero background.
  openvdb::FloatGrid::Ptr b = openvdb::FloatGrid::create(0.3f);
  b->setName("density");
  const fs::path bg = folder.dir() / "background.vdb";
  openvdb::io::File(bg.string()).write({b});
  expectRefused(volumeScene(bg), "background.vdb", "background");
}

TEST_F(VolumeShape, LeavesAreStoredBricksReadOnDemandWithTheirLargestVoxelKnown) {
  const fs::path vdb = writeGrid(folder.dir(), "stored.vdb");
  const Scene s = parseScene(volumeScene(vdb), "scene.json");
  const BrickGrid& g = s.media[0]->densityGrid();
  EXPECT_EQ(g.storedBricks(), 8u);
  // The brick at the far corner holds voxels up to (11, 11, 11): 0.01 · 66 + 0.1; its majorant
  // is the largest of it and its neighbours, the same voxel.
  const int32_t far = g.brickAt(1, 1, 1);
  ASSERT_GE(far, 0);
  EXPECT_EQ(g.kind(far), BrickGrid::Kind::Stored);
  EXPECT_FLOAT_EQ(g.majorant(far), 0.01f * 66 + 0.1f);
  EXPECT_FLOAT_EQ(g.majorant(g.brickAt(0, 0, 0)), 0.01f * 66 + 0.1f);
}

TEST_F(VolumeShape, WhatStaysResidentIsFarLessThanTheVoxels) {
  openvdb::initialize();
  openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.0f);
  g->setName("density");
  g->denseFill(openvdb::CoordBBox({0, 0, 0}, {127, 127, 127}), 0.5f, true);  // 4096 leaves, 8 MiB of voxels
  const fs::path p = folder.dir() / "big.vdb";
  openvdb::io::File(p.string()).write({g});
  const Scene s = parseScene(volumeScene(p), "scene.json");
  const BrickGrid& grid = s.media[0]->densityGrid();
  ASSERT_EQ(grid.storedBricks(), 4096u);
  // The brick table and OpenVDB's tree with every leaf out of core (its internal nodes' dense
  // child tables, about 150 bytes per leaf), not the voxels: those are the brick cache's.
  EXPECT_LT(grid.bytes(), grid.storedBricks() * sizeof(BrickGrid::BrickVoxels) / 4) << grid.bytes();
}

TEST_F(VolumeShape, EmissionAndTemperatureGridsOfTheSameFile) {
  openvdb::initialize();
  const auto transform = openvdb::math::Transform::createLinearTransform(0.25);
  openvdb::GridPtrVec grids;
  for (const char* name : {"density", "heat", "glow"}) {
    openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.0f);
    g->setName(name);
    g->setTransform(transform->copy());
    g->denseFill(openvdb::CoordBBox({0, 0, 0}, {7, 7, 7}), name[0] == 'h' ? 1500.0f : 1.0f, true);
    grids.push_back(g);
  }
  const fs::path p = folder.dir() / "fire.vdb";
  openvdb::io::File(p.string()).write(grids);
  const Scene s = parseScene(volumeScene(p, R"(, "temperature_grid": "heat", "temperature_scale": 2, "blackbody_scale": 3,
      "emission_grid": "glow", "emission": [1, 0.5, 0.25])"), "scene.json");
  const Medium& m = *s.media[0];
  ASSERT_TRUE(m.emits());
  EXPECT_EQ(m.emission().temperature->bricks(), 1u);
  EXPECT_EQ(m.emission().intensity->bricks(), 1u);
  EXPECT_FLOAT_EQ(m.emission().temperatureScale, 2.0f);
  EXPECT_FLOAT_EQ(m.emission().blackbodyScale, 3.0f);
  EXPECT_FLOAT_EQ(m.emission().color.y, 0.5f);
  EXPECT_FALSE(parseScene(volumeScene(p), "scene.json").media[0]->emits());
  // Keys of an absent grid, a missing grid and a grid elsewhere are refused naming the place.
  expectRefused(volumeScene(p, R"(, "emission": [1, 1, 1])"), "/emission", "emission_grid");
  expectRefused(volumeScene(p, R"(, "temperature_scale": 2)"), "/temperature_scale", "temperature_grid");
  expectRefused(volumeScene(p, R"(, "emission_grid": "smoke")"), "fire.vdb", "no grid named 'smoke'");
  openvdb::FloatGrid::Ptr moved = openvdb::FloatGrid::create(0.0f);
  moved->setName("glow");
  moved->setTransform(openvdb::math::Transform::createLinearTransform(0.5));
  moved->tree().setValue({0, 0, 0}, 1.0f);
  openvdb::GridPtrVec two{grids[0], moved};
  const fs::path q = folder.dir() / "moved.vdb";
  openvdb::io::File(q.string()).write(two);
  expectRefused(volumeScene(q, R"(, "emission_grid": "glow")"), "moved.vdb", "transform other than the density grid's");
}

TEST_F(VolumeShape, TransmittanceEstimatorIsAnIntegratorSwitch) {
  const std::string base = test::minimalScene();
  EXPECT_FALSE(parseScene(base, "scene.json").integrator.deltaTransmittance);
  const auto with = [&](const std::string& value) {
    std::string t = base;
    return t.insert(1, R"("integrator": {"transmittance": )" + value + "}, ");
  };
  EXPECT_TRUE(parseScene(with("\"delta\""), "scene.json").integrator.deltaTransmittance);
  EXPECT_FALSE(parseScene(with("\"ratio\""), "scene.json").integrator.deltaTransmittance);
  expectRefused(with("\"both\""), "/integrator/transmittance", "\"ratio\" or \"delta\"");
}

TEST_F(VolumeShape, SceneWithoutVolumesHasNoMedia) {
  EXPECT_TRUE(parseScene(test::minimalScene(), "scene.json").media.empty());
}

}  // namespace
}  // namespace rayes
