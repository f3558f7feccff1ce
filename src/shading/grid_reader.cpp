#include "shading/grid_reader.h"
#include <algorithm>
#include <bit>
#include <cmath>

namespace rayes {
namespace {
int32_t floorDiv8(int32_t v) { return v >= 0 ? v / 8 : -((-v + 7) / 8); }

// The apron regions a lookup with lower corner at local (lx, ly, lz) reads, each coordinate in
// [−1, 7]: per axis part 0 when it reaches −1, part 2 when it reaches 8, part 1 always.
uint32_t regionsRead(int32_t lx, int32_t ly, int32_t lz) {
  const auto parts = [](int32_t l) -> uint32_t { return l < 0 ? 0b011u : l >= 7 ? 0b110u : 0b010u; };
  const uint32_t px = parts(lx), py = parts(ly), pz = parts(lz);
  uint32_t need = 0;
  for (int ax = 0; ax < 3; ++ax)
    for (int ay = 0; ay < 3; ++ay)
      for (int az = 0; az < 3; ++az)
        if ((px >> ax & 1) && (py >> ay & 1) && (pz >> az & 1)) need |= 1u << BrickCache::apronRegion(ax, ay, az);
  return need;
}
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
        h.apron = BrickCache::apronFilled(h.slot);
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

void GridReader::fillApron(uint32_t need) {
  current_.apron = BrickCache::apronFilled(current_.slot);  // other readers may have filled some
  const BrickCoord o = grid_.coord(current_.brick);
  for (uint32_t missing = need & ~current_.apron; missing != 0; missing &= missing - 1) {
    const uint32_t region = uint32_t(std::countr_zero(missing));
    const BrickCache::ApronBox box = BrickCache::apronBox(region);
    const int32_t* part = box.part;
    float values[64];  // a face's 8 × 8 at most
    size_t n = 0;
    const int32_t b = grid_.brickAt(o.x + part[0] - 1, o.y + part[1] - 1, o.z + part[2] - 1);
    if (b >= 0) fetch(b, neighbour_);
    for (int32_t x = box.lo[0]; x <= box.hi[0]; ++x)
      for (int32_t y = box.lo[1]; y <= box.hi[1]; ++y)
        for (int32_t z = box.lo[2]; z <= box.hi[2]; ++z)
          values[n++] = b < 0 ? 0.0f
                              : neighbour_.at(x - 8 * (part[0] - 1), y - 8 * (part[1] - 1), z - 8 * (part[2] - 1));
    cache_->fillApron(current_.slot, region, values);
  }
  current_.apron = BrickCache::apronFilled(current_.slot);
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
  const bool interior = lx >= 0 && ly >= 0 && lz >= 0 && lx < 7 && ly < 7 && lz < 7;
  // All eight inside the brick (the common case): no table lookups. A constant brick's
  // interpolation is its value exactly (a + (a − a)·t = a).
  if (interior && !current_.voxels) return current_.constant;
  // Or within the padded slot: its apron, filled from the neighbours the first time it is read.
  const bool padded = !interior && current_.slot && lx >= -1 && ly >= -1 && lz >= -1 && lx <= 7 && ly <= 7 && lz <= 7;
  if (padded)
    if (const uint32_t need = regionsRead(lx, ly, lz); need & ~current_.apron) fillApron(need);
  if (interior || padded) {
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j)
        for (int k = 0; k < 2; ++k) c[i][j][k] = current_.at(lx + i, ly + j, lz + k);
  } else {
    // A resident or constant brick's edge, or a point rounding put outside the cell: voxel by
    // voxel from whichever brick holds it (the same values the apron holds).
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
