// A disk light's surface as a Patch kind. Planar, so its dicing error is zero and it needs no
// crack closure; immutable and thread-safe like every Patch.
#pragma once
#include <cmath>
#include <numbers>
#include "core/disk_mapping.h"
#include "geometry/patch.h"

namespace rayes {

// A disk light's surface: the concentric map of the unit square onto the disk (exactly the
// disk, constant |dP/du x dP/dv| = π R², so next-event estimation samples its area uniformly
// and exactly). Camera and BSDF rays see its dicing: at level m an inscribed polygon of
// 2^(m+2) sides (area 2R² at m = 0, 0.99 πR² at m = 3). Planar: dicing error 0.
class DiskPatch final : public Patch {
 public:
  DiskPatch(Vec3 centre, Vec3 normal, float radius) : c_(centre), n_(normalize(normal)), r_(radius) {
    orthonormalBasis(n_, t_, b_);
    Box3 box;
    for (int i = 0; i < 3; ++i) {
      const float e = r_ * std::sqrt(std::max(0.0f, 1.0f - n_[i] * n_[i]));
      box.lo[i] = c_[i] - e;
      box.hi[i] = c_[i] + e;
    }
    // The box of the exact disk (e = r sin of the normal's angle to the axis, 4 roundings); a
    // diced vertex c + (t x + b y) r rounds by gamma(5) r plus half an ulp of the centre
    // (grownBy's own term), and t, b, n are unit to within gamma(6).
    bounds_ = box.grownBy(gammaBound(16) * r_);
  }
  Box3 bounds() const override { return bounds_; }
  float sizeBound() const override { return 2 * std::numbers::pi_v<float> * r_; }
  SurfacePoint evaluate(float u, float v) const override {
    float x, y;
    concentricDisk(u, v, x, y);
    return {c_ + (t_ * x + b_ * y) * r_, n_ * (std::numbers::pi_v<float> * r_ * r_)};
  }
  float dicingErrorCoefficient() const override { return 0; }
  const char* kind() const override { return "disk"; }

 private:
  Vec3 c_, n_, t_, b_;
  float r_;
  Box3 bounds_;
};

}  // namespace rayes
