#include "geometry/sub_patch.h"
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace rayes {

SubPatch::SubPatch(PatchPtr parent, int depth, uint32_t x, uint32_t y)
    : parent_(std::move(parent)), depth_(depth), x_(x), y_(y) {
  if (!parent_) throw std::invalid_argument("SubPatch: no parent patch");
  if (depth < 0 || depth > kMaxDepth) throw std::invalid_argument("SubPatch: depth outside [0, kMaxDepth]");
  if (x >= (1u << depth) || y >= (1u << depth)) throw std::invalid_argument("SubPatch: sub-rectangle outside the parent");
  // Both boxes hold every vertex a sub-leaf dices (they are the parent's vertices, and the
  // parent's dicing over the sub-rectangle lies in boundsOver of it), so their overlap does too;
  // the two are computed differently and neither always contains the other.
  const Box3 over = boundsOver(0.0f, 1.0f, 0.0f, 1.0f), whole = parent_->bounds();
  bounds_ = {vmax(over.lo, whole.lo), vmin(over.hi, whole.hi)};
}

// x + u is exact for u on a dyadic grid of level m (m + depth <= 24 bits), and the product by
// 2^-depth is exact: the same bits as the parent's grid parameter (x·2^m + i) / 2^(m+depth).
float SubPatch::parentU(float u) const { return std::ldexp(float(x_) + u, -depth_); }
float SubPatch::parentV(float v) const { return std::ldexp(float(y_) + v, -depth_); }

Box3 SubPatch::boundsOver(float u0, float u1, float v0, float v1) const {
  Box3 b = boundsOverAt(0, u0, u1, v0, v1);
  for (int s = 1; s < timeSamples(); ++s) b.extend(boundsOverAt(s, u0, u1, v0, v1));
  return b;
}

Box3 SubPatch::boundsOverAt(int sample, float u0, float u1, float v0, float v1) const {
  return parent_->boundsOverAt(sample, parentU(u0), parentU(u1), parentV(v0), parentV(v1));
}

float SubPatch::sizeBound() const { return std::ldexp(parent_->sizeBound(), -depth_); }

float SubPatch::dicingErrorCoefficient() const { return std::ldexp(parent_->dicingErrorCoefficient(), -2 * depth_); }

SurfacePoint SubPatch::evaluateAt(int sample, float u, float v) const {
  return parent_->evaluateAt(sample, parentU(u), parentV(v));
}

// Per vertex from the parent's integer grid indices; the parent's evaluate() equals its dice()
// bit for bit, so this is its finer grid's block. (Row kernels of the parent kinds would be
// faster; not measured yet, see bench/history/2026-11.md "Sub-leaves".)
void SubPatch::diceAt(int sample, int level, Vec3* positions, Vec3* normals) const {
  if (level < 0 || level + depth_ > 24) throw std::invalid_argument("SubPatch::dice: level + depth outside [0, 24]");
  const int n = 1 << level, fine = level + depth_;
  const uint32_t i0 = x_ << level, j0 = y_ << level;
  for (int j = 0; j <= n; ++j) {
    const float v = std::ldexp(float(j0 + uint32_t(j)), -fine);
    for (int i = 0; i <= n; ++i) {
      const float u = std::ldexp(float(i0 + uint32_t(i)), -fine);
      const SurfacePoint p = parent_->evaluateAt(sample, u, v);
      const size_t k = size_t(j) * size_t(n + 1) + size_t(i);
      positions[k] = p.p;
      normals[k] = p.n;
    }
  }
}

bool SubPatch::onParentBorder(int e) const {
  const uint32_t last = (1u << depth_) - 1;
  switch (e) {
    case 0: return y_ == 0;
    case 1: return x_ == last;
    case 2: return y_ == last;
    default: return x_ == 0;
  }
}

void SubPatch::borderPieceBoundsAt(int sample, int e, int k, uint32_t j, int split, Box3* out) const {
  if (!onParentBorder(e)) {
    Patch::borderPieceBoundsAt(sample, e, k, j, split, out);
    return;
  }
  // Segment j of level k along this border is segment (offset·2^k + j) of level k + depth
  // along the parent's: the same pieces, so the same regions as the parent would have there.
  const uint32_t offset = (e == 0 || e == 2) ? x_ : y_;
  parent_->borderPieceBoundsAt(sample, e, k + depth_, (offset << k) + j, split, out);
}

int subLeafDepth(int level, int residentMaxLevel) {
  return std::max(0, level - std::max(0, residentMaxLevel));
}

}  // namespace rayes
