#include "shading/grid_reader.h"
#include <algorithm>
#include <cmath>

namespace rayes {
namespace {
int32_t floorDiv8(int32_t v) { return v >= 0 ? v / 8 : -((-v + 7) / 8); }
}  // namespace

GridReader::~GridReader() {
  drop(current_);
  drop(neighbour_);
}

void GridReader::drop(Held& h) {
  if (h.slot) cache_->release(h.slot);
  h.slot = nullptr;
  h.brick = -1;
}

void GridReader::fetch(int32_t brick, Held& h) {
  if (h.brick == brick) return;
  drop(h);
  h.brick = brick;
  switch (grid_.kind(brick)) {
    case BrickGrid::Kind::Resident:
      h.voxels = grid_.residentVoxels(brick);
      break;
    case BrickGrid::Kind::Constant:
      h.voxels = nullptr;
      h.constant = grid_.constantValue(brick);
      break;
    case BrickGrid::Kind::Stored:
      if (cache_) {
        h.voxels = cache_->acquire(grid_.id(), grid_.storedIndex(brick), *grid_.source(), h.slot);
      } else {
        grid_.source()->read(grid_.storedIndex(brick), h.scratch.data());
        h.voxels = h.scratch.data();
      }
      break;
  }
}

float GridReader::voxel(int32_t x, int32_t y, int32_t z) {
  const int32_t b = grid_.brickAt(floorDiv8(x), floorDiv8(y), floorDiv8(z));
  if (b < 0) return 0.0f;
  Held& h = b == current_.brick ? current_ : neighbour_;
  fetch(b, h);
  const BrickCoord& o = grid_.coord(b);
  return h.at(x - 8 * o.x, y - 8 * o.y, z - 8 * o.z);
}

float GridReader::at(Vec3 p) {
  // Cell c covers [8c − ½, 8c + 7.5): c = floor((p + ½) / 8).
  const int32_t b = grid_.brickAt(int32_t(std::floor((p.x + 0.5f) / 8)), int32_t(std::floor((p.y + 0.5f) / 8)),
                                  int32_t(std::floor((p.z + 0.5f) / 8)));
  if (b < 0) return 0.0f;
  enter(b);
  return sample(p);
}

float GridReader::sample(Vec3 p) {
  const float fx = std::floor(p.x), fy = std::floor(p.y), fz = std::floor(p.z);
  const int32_t x = int32_t(fx), y = int32_t(fy), z = int32_t(fz);
  const float tx = p.x - fx, ty = p.y - fy, tz = p.z - fz;
  const BrickCoord& o = grid_.coord(current_.brick);
  const int32_t lx = x - 8 * o.x, ly = y - 8 * o.y, lz = z - 8 * o.z;
  float c[2][2][2];
  if (lx >= 0 && ly >= 0 && lz >= 0 && lx < 7 && ly < 7 && lz < 7) {
    // All eight inside the brick (the common case): no table lookups. A constant brick's
    // interpolation is its value exactly (a + (a − a)·t = a).
    if (!current_.voxels) return current_.constant;
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j)
        for (int k = 0; k < 2; ++k) c[i][j][k] = current_.at(lx + i, ly + j, lz + k);
  } else {
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j)
        for (int k = 0; k < 2; ++k) c[i][j][k] = voxel(x + i, y + j, z + k);
  }
  const auto lerp = [](float a, float b, float t) { return a + (b - a) * t; };
  const float c00 = lerp(c[0][0][0], c[1][0][0], tx), c01 = lerp(c[0][0][1], c[1][0][1], tx);
  const float c10 = lerp(c[0][1][0], c[1][1][0], tx), c11 = lerp(c[0][1][1], c[1][1][1], tx);
  // Clamped at 0: a convex combination of non-negative voxels, rounding cannot make it negative.
  return std::max(0.0f, lerp(lerp(c00, c10, ty), lerp(c01, c11, ty), tz));
}

}  // namespace rayes
