#include "shading/medium.h"
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rayes {
namespace {

int32_t floorDiv8(int32_t v) { return v >= 0 ? v / 8 : -((-v + 7) / 8); }

}  // namespace

bool invertAffine(const Transform& m, Transform& inv) {
  double a[3][3], scale = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      a[i][j] = m.m[i][j];
      scale = std::max(scale, std::fabs(a[i][j]));
    }
  const double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                     a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                     a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
  // Relative to the matrix's scale: a determinant this small leaves no float-precise inverse.
  if (!std::isfinite(det) || !(scale > 0) || !(std::fabs(det) > 1e-12 * scale * scale * scale)) return false;
  double r[3][3];
  r[0][0] = (a[1][1] * a[2][2] - a[1][2] * a[2][1]) / det;
  r[0][1] = (a[0][2] * a[2][1] - a[0][1] * a[2][2]) / det;
  r[0][2] = (a[0][1] * a[1][2] - a[0][2] * a[1][1]) / det;
  r[1][0] = (a[1][2] * a[2][0] - a[1][0] * a[2][2]) / det;
  r[1][1] = (a[0][0] * a[2][2] - a[0][2] * a[2][0]) / det;
  r[1][2] = (a[0][2] * a[1][0] - a[0][0] * a[1][2]) / det;
  r[2][0] = (a[1][0] * a[2][1] - a[1][1] * a[2][0]) / det;
  r[2][1] = (a[0][1] * a[2][0] - a[0][0] * a[2][1]) / det;
  r[2][2] = (a[0][0] * a[1][1] - a[0][1] * a[1][0]) / det;
  for (int i = 0; i < 3; ++i) {
    double t = 0;
    for (int j = 0; j < 3; ++j) {
      inv.m[i][j] = float(r[i][j]);
      t -= r[i][j] * m.m[j][3];
    }
    inv.m[i][3] = float(t);
  }
  return true;
}

Medium::Medium(const Transform& indexToWorld, MediumCoefficients c) : coefficients_(c), indexToWorld_(indexToWorld) {
  if (!invertAffine(indexToWorld, worldToIndex_)) throw std::invalid_argument("the volume's transform is not invertible");
}

void Medium::addBrick(BrickCoord c, const BrickVoxels& voxels) {
  coords_.push_back(c);
  voxels_.push_back(voxels);
}

int32_t Medium::brickAt(int32_t cx, int32_t cy, int32_t cz) const {
  const int64_t x = int64_t(cx) - cellLo_.x, y = int64_t(cy) - cellLo_.y, z = int64_t(cz) - cellLo_.z;
  if (x < 0 || y < 0 || z < 0 || x >= cellCount_.x || y >= cellCount_.y || z >= cellCount_.z) return -1;
  return cells_[size_t((x * cellCount_.y + y) * cellCount_.z + z)];
}

float Medium::voxel(int32_t x, int32_t y, int32_t z) const {
  const int32_t b = brickAt(floorDiv8(x), floorDiv8(y), floorDiv8(z));
  if (b < 0) return 0.0f;
  const BrickCoord& o = coords_[size_t(b)];
  return voxels_[size_t(b)][size_t(((x - 8 * o.x) * 8 + (y - 8 * o.y)) * 8 + (z - 8 * o.z))];
}

float Medium::density(int32_t brick, Vec3 p) const {
  const float fx = std::floor(p.x), fy = std::floor(p.y), fz = std::floor(p.z);
  const int32_t x = int32_t(fx), y = int32_t(fy), z = int32_t(fz);
  const float tx = p.x - fx, ty = p.y - fy, tz = p.z - fz;
  const BrickCoord& o = coords_[size_t(brick)];
  const int32_t lx = x - 8 * o.x, ly = y - 8 * o.y, lz = z - 8 * o.z;
  float c[2][2][2];
  if (lx >= 0 && ly >= 0 && lz >= 0 && lx < 7 && ly < 7 && lz < 7) {
    // All eight inside the brick (the common case): no table lookups.
    const BrickVoxels& v = voxels_[size_t(brick)];
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j)
        for (int k = 0; k < 2; ++k) c[i][j][k] = v[size_t(((lx + i) * 8 + (ly + j)) * 8 + (lz + k))];
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

void Medium::finish() {
  if (coords_.empty()) {
    cellCount_ = {};
    return;
  }
  BrickCoord lo = coords_[0], hi = coords_[0];
  for (const BrickCoord& c : coords_) {
    lo = {std::min(lo.x, c.x), std::min(lo.y, c.y), std::min(lo.z, c.z)};
    hi = {std::max(hi.x, c.x), std::max(hi.y, c.y), std::max(hi.z, c.z)};
  }
  cellLo_ = lo;
  cellCount_ = {hi.x - lo.x + 1, hi.y - lo.y + 1, hi.z - lo.z + 1};
  cells_.assign(size_t(cellCount_.x) * size_t(cellCount_.y) * size_t(cellCount_.z), -1);
  std::vector<float> ownMax(coords_.size());
  for (size_t b = 0; b < coords_.size(); ++b) {
    const BrickCoord& c = coords_[b];
    cells_[size_t((int64_t(c.x - lo.x) * cellCount_.y + (c.y - lo.y)) * cellCount_.z + (c.z - lo.z))] = int32_t(b);
    ownMax[b] = *std::max_element(voxels_[b].begin(), voxels_[b].end());
  }
  // Trilinear interpolation in a cell reads voxels one beyond it: the neighbours' maxima count.
  majorant_.assign(coords_.size(), 0.0f);
  for (size_t b = 0; b < coords_.size(); ++b) {
    const BrickCoord& c = coords_[b];
    float m = 0;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const int32_t n = brickAt(c.x + dx, c.y + dy, c.z + dz);
          if (n >= 0) m = std::max(m, ownMax[size_t(n)]);
        }
    majorant_[b] = m;
  }
  worldBounds_ = Box3{};
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 p{corner & 1 ? 8.0f * float(hi.x + 1) - 0.5f : 8.0f * float(lo.x) - 0.5f,
                 corner & 2 ? 8.0f * float(hi.y + 1) - 0.5f : 8.0f * float(lo.y) - 0.5f,
                 corner & 4 ? 8.0f * float(hi.z + 1) - 0.5f : 8.0f * float(lo.z) - 0.5f};
    worldBounds_.extend(indexToWorld_.point(p));
  }
}

size_t Medium::bytes() const {
  return voxels_.capacity() * sizeof(BrickVoxels) + coords_.capacity() * sizeof(BrickCoord) +
         majorant_.capacity() * sizeof(float) + cells_.capacity() * sizeof(int32_t);
}

}  // namespace rayes
