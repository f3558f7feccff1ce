#include "shading/medium.h"
#include "shading/grid_reader.h"
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rayes {
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

Medium::Medium(const Transform& indexToWorld, MediumCoefficients c, std::shared_ptr<const BrickSource> source)
    : coefficients_(c), indexToWorld_(indexToWorld), density_(std::move(source)) {
  if (!invertAffine(indexToWorld, worldToIndex_)) throw std::invalid_argument("the volume's transform is not invertible");
}

float Medium::density(int32_t brick, Vec3 p) const {
  GridReader reader(density_, nullptr);
  reader.enter(brick);
  return reader.sample(p);
}

float Medium::voxel(int32_t x, int32_t y, int32_t z) const {
  GridReader reader(density_, nullptr);
  return reader.voxel(x, y, z);
}

Box3 Medium::brickWorldBounds(int32_t brick) const {
  const BrickCoord c = density_.coord(brick);
  Box3 b;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 p{8.0f * float(c.x + (corner & 1 ? 1 : 0)) - 0.5f, 8.0f * float(c.y + (corner & 2 ? 1 : 0)) - 0.5f,
                 8.0f * float(c.z + (corner & 4 ? 1 : 0)) - 0.5f};
    b.extend(indexToWorld_.point(p));
  }
  // A few ulps of the box's magnitude: the transform's rounding, and the slab test's.
  const float pad = 1e-5f * std::max({std::fabs(b.lo.x), std::fabs(b.lo.y), std::fabs(b.lo.z), std::fabs(b.hi.x),
                                      std::fabs(b.hi.y), std::fabs(b.hi.z), b.longestSide()});
  b.lo = b.lo - Vec3{pad, pad, pad};
  b.hi = b.hi + Vec3{pad, pad, pad};
  return b;
}

void Medium::finish() {
  density_.finish();
  if (emission_.intensity) emission_.intensity->finish();
  if (emission_.temperature) emission_.temperature->finish();
  worldBounds_ = Box3{};
  if (density_.bricks() == 0) return;
  const BrickCoord lo = density_.cellLo(), n = density_.cellCount();
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 p{corner & 1 ? 8.0f * float(lo.x + n.x) - 0.5f : 8.0f * float(lo.x) - 0.5f,
                 corner & 2 ? 8.0f * float(lo.y + n.y) - 0.5f : 8.0f * float(lo.y) - 0.5f,
                 corner & 4 ? 8.0f * float(lo.z + n.z) - 0.5f : 8.0f * float(lo.z) - 0.5f};
    worldBounds_.extend(indexToWorld_.point(p));
  }
}

}  // namespace rayes
