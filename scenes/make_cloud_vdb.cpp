// Writes scenes/cloud.vdb, the density grid of scenes/cloud.json: a cumulus-like cloud of a few
// overlapping soft blobs on a flat base, 96 x 48 x 64 voxels of size 0.05, with a hashed
// value-noise erosion so the null-collision trackers see a heterogeneous medium. Built by the
// project (target make_cloud_vdb) so no binary grid is kept in git:
//   build/bin/make_cloud_vdb scenes/cloud.vdb
// With --temperature, a "temperature" grid too (equal to the density on the same voxels), for
// an emitting cloud ("temperature_grid": "temperature"; bench/RESULTS.md's emission figure).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

namespace {

float hash3(int x, int y, int z) {
  uint32_t h = uint32_t(x) * 73856093u ^ uint32_t(y) * 19349663u ^ uint32_t(z) * 83492791u;
  h ^= h >> 13;
  h *= 0x5bd1e995u;
  h ^= h >> 15;
  return float(h & 0xffffff) / float(0xffffff);
}

// Trilinear value noise with a lattice of `cell` voxels, in [0, 1].
float valueNoise(float x, float y, float z) {
  const int ix = int(std::floor(x)), iy = int(std::floor(y)), iz = int(std::floor(z));
  const float fx = x - float(ix), fy = y - float(iy), fz = z - float(iz);
  float v = 0;
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int k = 0; k < 2; ++k)
        v += hash3(ix + i, iy + j, iz + k) * (i ? fx : 1 - fx) * (j ? fy : 1 - fy) * (k ? fz : 1 - fz);
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  const bool temperature = argc == 3 && std::string(argv[2]) == "--temperature";
  if (argc != 2 && !temperature) {
    std::fprintf(stderr, "usage: make_cloud_vdb OUT.vdb [--temperature]\n");
    return 2;
  }
  openvdb::initialize();
  openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
  grid->setName("density");
  grid->setTransform(openvdb::math::Transform::createLinearTransform(0.05));
  grid->setGridClass(openvdb::GRID_FOG_VOLUME);
  struct Blob { float x, y, z, r; };
  const Blob blobs[] = {{30, 18, 32, 16}, {52, 22, 30, 19}, {70, 17, 34, 14}, {45, 30, 36, 13}, {60, 14, 20, 11}};
  auto acc = grid->getAccessor();
  for (int x = 0; x < 96; ++x)
    for (int y = 0; y < 48; ++y)
      for (int z = 0; z < 64; ++z) {
        float d = 0;
        for (const Blob& b : blobs) {
          const float dx = float(x) - b.x, dy = float(y) - b.y, dz = float(z) - b.z;
          const float q = 1 - (dx * dx + dy * dy + dz * dz) / (b.r * b.r);
          if (q > 0) d = std::max(d, q);
        }
        if (y < 8) d *= float(y) / 8;  // a soft flat base
        const float n = 0.6f * valueNoise(x / 6.0f, y / 6.0f, z / 6.0f) + 0.4f * valueNoise(x / 2.5f, y / 2.5f, z / 2.5f);
        const float density = std::max(0.0f, 2 * d - 0.5f * n);
        if (density > 0) acc.setValue({x, y, z}, std::min(1.0f, density));
      }
  grid->pruneGrid();
  openvdb::GridPtrVec grids{grid};
  if (temperature) {
    openvdb::FloatGrid::Ptr t = grid->deepCopy();
    t->setName("temperature");
    grids.push_back(t);
  }
  openvdb::io::File(argv[1]).write(grids);
  std::printf("%s: %zu leaf nodes, %zu active voxels\n", argv[1], size_t(grid->tree().leafCount()),
              size_t(grid->tree().activeVoxelCount()));
  return 0;
}
