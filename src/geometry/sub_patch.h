// A sub-leaf: the part of a parent Patch over one dyadic sub-rectangle of its parameter square,
// [x, x+1] / 2^depth × [y, y+1] / 2^depth (issue 33, item 2: a leaf whose finest level would
// exceed the resident maximum is diced as 4^depth sub-leaves, each at most at that maximum).
//
// Contract: the level-m dicing of sub-leaf (depth, x, y) is the parent's level-(m + depth)
// dicing restricted to grid indices [x·2^m, (x+1)·2^m] × [y·2^m, (y+1)·2^m], bit for bit
// (positions and normals). Every vertex is the parent's evaluate() at parameters made from
// integer grid indices of the parent's finer grid and scaled by an exact power of two, never
// from sub-rectangle arithmetic: a vertex on the edge two sub-leaves share is the same call
// with the same arguments on both sides, and a vertex on the parent's border is the parent's
// own border vertex (every Patch kind's dice() equals its evaluate() bit for bit), which its
// neighbouring leaves already match. So splitting opens no crack, inside or at the border.
// Requires m + depth <= 24 (float holds the indices exactly); depth <= kMaxDepth.
//
// Bounds: the parent's boundsOver() of the sub-rectangle (which holds the true surface and the
// diced vertices over it, Patch::boundsOver), cut to the parent's bounds(); border pieces of a border lying on the parent's
// border are the parent's pieces of that border at level k + depth, so crack-closing regions
// of a sub-leaf there are the parent's regions. Sizes scale exactly: sizeBound / 2^depth,
// dicingErrorCoefficient / 4^depth (the level-m error of the sub-leaf is the parent's at
// m + depth). Immutable and thread-safe like every Patch; it holds the parent alive.
#pragma once
#include <cstdint>
#include "geometry/patch.h"

namespace rayes {

class SubPatch final : public Patch {
 public:
  static constexpr int kMaxDepth = 8;
  // Sub-rectangle (x, y) of the 2^depth × 2^depth split of `parent`; std::invalid_argument
  // for a null parent, depth outside [0, kMaxDepth] or x, y outside [0, 2^depth).
  SubPatch(PatchPtr parent, int depth, uint32_t x, uint32_t y);

  const Patch& parent() const { return *parent_; }
  int depth() const { return depth_; }
  uint32_t x() const { return x_; }
  uint32_t y() const { return y_; }
  // The parent's parameters of this sub-leaf's (u, v) (exact on the dyadic grid of any level
  // m with m + depth <= 24): what a hit on the sub-leaf reports to shading.
  float parentU(float u) const;
  float parentV(float v) const;

  Box3 bounds() const override { return bounds_; }
  Box3 boundsOver(float u0, float u1, float v0, float v1) const override;
  float sizeBound() const override;
  SurfacePoint evaluate(float u, float v) const override { return evaluateAt(0, u, v); }
  void dice(int level, Vec3* positions, Vec3* normals) const override { diceAt(0, level, positions, normals); }
  float dicingErrorCoefficient() const override;
  const char* kind() const override { return parent_->kind(); }
  bool isDisplaced() const override { return parent_->isDisplaced(); }
  bool isSubdivision() const override { return parent_->isSubdivision(); }
  int timeSamples() const override { return parent_->timeSamples(); }
  float sampleTime(int sample) const override { return parent_->sampleTime(sample); }
  void diceAt(int sample, int level, Vec3* positions, Vec3* normals) const override;
  SurfacePoint evaluateAt(int sample, float u, float v) const override;
  Box3 boundsOverAt(int sample, float u0, float u1, float v0, float v1) const override;
  bool needsBorderClosure() const override { return parent_->needsBorderClosure(); }
  void borderPieceBoundsAt(int sample, int e, int k, uint32_t j, int split, Box3* out) const override;

  // Whether border e (0: v = 0, 1: u = 1, 2: v = 1, 3: u = 0) lies on the parent's border e;
  // the others are shared with a sibling sub-leaf, whose vertices there are the same bits.
  bool onParentBorder(int e) const;

 private:
  PatchPtr parent_;
  int depth_;
  uint32_t x_, y_;
  Box3 bounds_;
};

// How many times a leaf needed at `level` must be halved in each direction so that no dicing
// exceeds `residentMaxLevel`: max(0, level - residentMaxLevel). Each of the 4^depth sub-leaves
// is then diced at most at level - depth. A negative residentMaxLevel counts as 0. (The split is
// made per run of rays, not per leaf at set-up: under the per-ray rule a curved leaf's finest
// possible level is --max-lod, a footprint having no lower bound, so a set-up split would make
// 4^(maxLod - resident) top-level leaves of every leaf, while the few leaves seen closely
// enough need it: 0-41 % of the dicings of the six peer scenes, 0.006 % of forest-100's;
// bench/history/2026-11.md, "Sub-leaves".)
int subLeafDepth(int level, int residentMaxLevel);

}  // namespace rayes
