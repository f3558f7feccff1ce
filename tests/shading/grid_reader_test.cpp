// Reading a brick grid (shading/grid_reader.h): a lookup through the brick cache, whose slots
// hold each brick with a one-voxel apron filled from the neighbours, returns the same bits as the
// uncached reader and as the trilinear interpolation written out here, at points exactly on a
// brick cell's faces, edges and corners (where the lookup reads the apron), under a cache far
// smaller than the grid (slots evicted and their aprons filled again), and from many threads at
// once (several readers filling one slot's apron); a grid of one voxel reads zeros beyond it.
#include <gtest/gtest.h>
#include <atomic>
#include <cmath>
#include <functional>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include "shading/grid_reader.h"

namespace rayes {
namespace {

using VoxelFn = std::function<float(int32_t, int32_t, int32_t)>;

// Stored brick i is the brick at cell coords[i], its voxel v the function's value there.
class FunctionSource final : public BrickSource {
 public:
  FunctionSource(VoxelFn f, std::vector<BrickCoord> coords) : f_(std::move(f)), coords_(std::move(coords)) {}
  void read(uint32_t stored, float* voxels) const override {
    const BrickCoord c = coords_[stored];
    for (int32_t x = 0; x < 8; ++x)
      for (int32_t y = 0; y < 8; ++y)
        for (int32_t z = 0; z < 8; ++z) voxels[(x * 8 + y) * 8 + z] = f_(8 * c.x + x, 8 * c.y + y, 8 * c.z + z);
  }
  uint64_t residentBytes() const override { return 0; }

 private:
  VoxelFn f_;
  std::vector<BrickCoord> coords_;
};

// A grid of stored bricks at `coords` with voxels f (0 outside them).
struct StoredGrid {
  StoredGrid(const VoxelFn& f, std::vector<BrickCoord> coords) : coords(coords) {
    auto source = std::make_shared<FunctionSource>(f, coords);
    grid = std::make_unique<BrickGrid>(source);
    for (uint32_t i = 0; i < coords.size(); ++i) {
      float m = 0;
      for (int32_t x = 0; x < 8; ++x)
        for (int32_t y = 0; y < 8; ++y)
          for (int32_t z = 0; z < 8; ++z) m = std::max(m, f(8 * coords[i].x + x, 8 * coords[i].y + y, 8 * coords[i].z + z));
      grid->addStored(coords[i], i, m);
    }
    grid->finish();
    value = [f, this](int32_t x, int32_t y, int32_t z) {
      const auto div8 = [](int32_t v) { return v >= 0 ? v / 8 : -((-v + 7) / 8); };
      return grid->brickAt(div8(x), div8(y), div8(z)) >= 0 ? f(x, y, z) : 0.0f;
    };
  }
  std::vector<BrickCoord> coords;
  std::unique_ptr<BrickGrid> grid;
  VoxelFn value;  // the grid's voxel, 0 where no brick holds it
};

// The trilinear interpolation of the voxels around p, in the reader's order of operations.
float trilinear(const VoxelFn& v, Vec3 p) {
  const float fx = std::floor(p.x), fy = std::floor(p.y), fz = std::floor(p.z);
  const int32_t x = int32_t(fx), y = int32_t(fy), z = int32_t(fz);
  const float tx = p.x - fx, ty = p.y - fy, tz = p.z - fz;
  const auto lerp = [](float a, float b, float t) { return a + (b - a) * t; };
  const float c00 = lerp(v(x, y, z), v(x + 1, y, z), tx), c01 = lerp(v(x, y, z + 1), v(x + 1, y, z + 1), tx);
  const float c10 = lerp(v(x, y + 1, z), v(x + 1, y + 1, z), tx), c11 = lerp(v(x, y + 1, z + 1), v(x + 1, y + 1, z + 1), tx);
  return std::max(0.0f, lerp(lerp(c00, c10, ty), lerp(c01, c11, ty), tz));
}

// Distinct, positive voxel values: a wrong voxel read changes the result.
float hashed(int32_t x, int32_t y, int32_t z) {
  const uint32_t h = (uint32_t(x) * 73856093u) ^ (uint32_t(y) * 19349663u) ^ (uint32_t(z) * 83492791u);
  return float(h % 1009) / 97.0f + 0.25f;
}

// A 3 × 3 × 3 block of bricks with the centre's lower-x neighbour missing (zeros read there).
std::vector<BrickCoord> blockWithAHole() {
  std::vector<BrickCoord> c;
  for (int32_t x = -1; x <= 1; ++x)
    for (int32_t y = -1; y <= 1; ++y)
      for (int32_t z = -1; z <= 1; ++z)
        if (!(x == -1 && y == 0 && z == 0)) c.push_back({x, y, z});
  return c;
}

// Points of brick cell c on its faces, edges and corners ([8c − ½, 8c + 7.5) per axis: the low
// bound itself, the last voxel 8c + 7, just below the high bound) and within.
std::vector<Vec3> pointsOnTheCellsBoundary(BrickCoord c) {
  const auto axis = [](int32_t cc) {
    const float lo = 8.0f * float(cc) - 0.5f;
    return std::vector<float>{lo, lo + 0.25f, lo + 0.5f, lo + 3.3f, lo + 7.5f, lo + 7.75f, std::nextafter(lo + 8, lo)};
  };
  std::vector<Vec3> points;
  for (float x : axis(c.x))
    for (float y : axis(c.y))
      for (float z : axis(c.z)) points.push_back({x, y, z});
  return points;
}

TEST(GridReader, CachedLookupsOnACellsFacesEdgesAndCornersReadTheNeighboursVoxelsBitForBit) {
  const StoredGrid g(hashed, blockWithAHole());
  // Room for a reader's pins and little more: bricks are evicted and their aprons refilled.
  BrickCache cache(BrickCache::minimumBytes(1), 1, g.coords.size());
  ASSERT_LT(cache.stats().slots, g.coords.size());
  GridReader cached(*g.grid, &cache), uncached(*g.grid, nullptr);
  size_t points = 0;
  for (int round = 0; round < 2; ++round)
    for (const BrickCoord& c : g.coords) {
      const int32_t brick = g.grid->brickAt(c.x, c.y, c.z);
      for (const Vec3& p : pointsOnTheCellsBoundary(c)) {
        cached.enter(brick);
        uncached.enter(brick);
        const float expected = trilinear(g.value, p);
        ASSERT_EQ(cached.sample(p), expected) << "cell " << c.x << " " << c.y << " " << c.z << " at " << p.x << " "
                                              << p.y << " " << p.z;
        ASSERT_EQ(uncached.sample(p), expected);
        ++points;
      }
    }
  EXPECT_EQ(points, 2 * g.coords.size() * 343);
  EXPECT_GT(cache.stats().evictions, 0u);
}

TEST(GridReader, ManyThreadsFillingTheSameAprons) {
  const StoredGrid g(hashed, blockWithAHole());
  const int threads = 4;
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  // Room for every thread's pins, one brick short of the grid: slots are reused now and then.
  BrickCache cache(BrickCache::minimumBytes(threads), threads, g.coords.size());
  ASSERT_LT(cache.stats().slots, g.coords.size());
  const BrickCoord centre{0, 0, 0};
  const std::vector<Vec3> points = pointsOnTheCellsBoundary(centre);
  std::atomic<int> wrong{0};
  tbb::parallel_for(0, 2000, [&](int i) {
    // Every task reads the centre brick's apron and then another brick's, in its own order.
    GridReader reader(*g.grid, &cache);
    const BrickCoord other = g.coords[size_t(i) % g.coords.size()];
    for (const BrickCoord c : {centre, other}) {
      reader.enter(g.grid->brickAt(c.x, c.y, c.z));
      const std::vector<Vec3> ps = c.x == 0 && c.y == 0 && c.z == 0 ? points : pointsOnTheCellsBoundary(c);
      for (size_t k = 0; k < ps.size(); ++k) {
        const Vec3 p = ps[(k * 37 + size_t(i)) % ps.size()];
        if (reader.sample(p) != trilinear(g.value, p)) wrong.fetch_add(1);
      }
    }
  });
  EXPECT_EQ(wrong.load(), 0);
}

TEST(GridReader, AGridOfOneVoxelReadsItAndZerosAcrossEveryFace) {
  // One stored brick whose only non-zero voxel, (3, 0, 7), touches two of its faces.
  const StoredGrid g([](int32_t x, int32_t y, int32_t z) { return x == 3 && y == 0 && z == 7 ? 2.5f : 0.0f; },
                     {BrickCoord{0, 0, 0}});
  BrickCache cache(BrickCache::minimumBytes(1), 1, 1);
  GridReader reader(*g.grid, &cache);
  reader.enter(0);
  EXPECT_EQ(reader.sample({3, 0, 7}), 2.5f);
  // On the cell's lower y face and a quarter voxel short of the upper z one: the absent
  // neighbours' voxels are 0, so the value is 2.5 · ½ (y) · ¾ (z), exactly.
  EXPECT_EQ(reader.sample({3, -0.5f, 7.25f}), 0.9375f);
  // The cell's corner (−½, −½, −½) reaches only absent voxels and zeros.
  EXPECT_EQ(reader.sample({-0.5f, -0.5f, -0.5f}), 0.0f);
  for (const Vec3& p : pointsOnTheCellsBoundary({0, 0, 0})) EXPECT_EQ(reader.sample(p), trilinear(g.value, p));
  // The majorant is the voxel: it bounds every lookup of the cell.
  EXPECT_EQ(g.grid->majorant(0), 2.5f);
}

}  // namespace
}  // namespace rayes
