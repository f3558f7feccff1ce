// A patch in motion: K >= 2 time samples of one surface (thesis §6.3). Each sample is a
// complete patch of the same kind and parametrisation (the scene loader builds one per
// keyframe); the surface at time t is the point-wise linear interpolation of the two samples
// bracketing t, which is what the bottom level traces (DiceBuffer::diceInterval).
//
// bounds() is the union of the samples' bounds: a point interpolated between two samples lies
// in the box spanned by them, so one box covers every time of the keyframe range and the top
// level needs no motion of its own. Immutable and thread-safe like every Patch.
#pragma once
#include <vector>
#include "geometry/patch.h"

namespace rayes {

class MovingPatch final : public Patch {
 public:
  // samples.size() >= 2, same kind, times strictly increasing and finite (std::invalid_argument
  // otherwise).
  MovingPatch(std::vector<PatchPtr> samples, std::vector<float> times);

  Box3 bounds() const override { return bounds_; }
  Box3 boundsOver(float u0, float u1, float v0, float v1) const override;
  float sizeBound() const override { return sizeBound_; }
  SurfacePoint evaluate(float u, float v) const override { return samples_[0]->evaluate(u, v); }
  void dice(int level, Vec3* positions, Vec3* normals) const override {
    samples_[0]->dice(level, positions, normals);
  }
  float dicingErrorCoefficient() const override { return errorCoefficient_; }
  bool needsBorderClosure() const override { return needsClosure_; }
  const char* kind() const override { return samples_[0]->kind(); }
  bool isDisplaced() const override { return samples_[0]->isDisplaced(); }
  bool isSubdivision() const override { return samples_[0]->isSubdivision(); }

  int timeSamples() const override { return int(samples_.size()); }
  float sampleTime(int s) const override { return times_[size_t(s)]; }
  void diceAt(int s, int level, Vec3* positions, Vec3* normals) const override {
    samples_[size_t(s)]->dice(level, positions, normals);
  }
  SurfacePoint evaluateAt(int s, float u, float v) const override { return samples_[size_t(s)]->evaluate(u, v); }
  Box3 boundsOverAt(int s, float u0, float u1, float v0, float v1) const override {
    return samples_[size_t(s)]->boundsOver(u0, u1, v0, v1);
  }
  void borderPieceBoundsAt(int s, int e, int k, uint32_t j, int split, Box3* out) const override {
    samples_[size_t(s)]->borderPieceBoundsAt(0, e, k, j, split, out);
  }

  const Patch& sample(int s) const { return *samples_[size_t(s)]; }

 private:
  std::vector<PatchPtr> samples_;
  std::vector<float> times_;
  Box3 bounds_;
  float sizeBound_ = 0, errorCoefficient_ = 0;
  bool needsClosure_ = false;
};

// Where time t falls among a patch's samples: the interval [t_i, t_i+1] and the weight of
// sample i+1 (alpha in [0, 1]); t outside the keyframe range clamps. A static patch gives
// (0, 0). A pure function of (patch, t): every ray at time t sees the same surface.
struct TimeInterval {
  int interval = 0;
  float alpha = 0;
};
TimeInterval timeInterval(const Patch& patch, float t);

}  // namespace rayes
