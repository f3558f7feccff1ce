// Top-level leaves that are bricks of participating media (docs/design.md, "Volumes"): a scene
// with media appends one leaf per brick (or per block of bricks: shading's BrickNumbering) after
// its patch leaves, so the ray engine sorts rays by brick as it sorts them by patch, and runs the null-collision tracking of a brick for the whole
// run of its rays while that brick's voxels are held. Like LeafQueries, the type lives in core so
// shading implements the tracking and src/rays drives it without knowing each other.
//
// Contract: leaves [firstLeaf, firstLeaf + bricks) of the top level are brick leaves. During trace()
// an engine that sorts by leaf calls track() once per brick run (or per chunk of a long run; the
// calls may be concurrent, within a brick too) with each ray's search limit, takes each closest
// ray's collision as a hit on that leaf (competing with surface hits under the usual total order),
// and sets `tracked`. The tracker keeps shadow rays' transmittance factors itself, accumulated
// order-independently (TransmittanceProduct), so the result is the same bits for any sort order,
// chunking or thread count. An engine that does not run brick leaves leaves `tracked` false and
// the tracker's owner walks each ray itself through the same per-brick function.
#pragma once
#include <atomic>
#include <cmath>
#include <cstdint>
#include <span>
#include "core/ray_batch.h"

namespace rayes {

class MediumLeafTracker {
 public:
  virtual ~MediumLeafTracker() = default;
  // For each ray slot rays[k] of `b` crossing brick leaf `leaf`, within t in (0, limits[k]]: a
  // closest ray's first real collision in the brick into collisions[k] (+inf: none before the
  // limit); a shadow ray's transmittance factor through the brick, kept by the tracker
  // (collisions[k] untouched).
  virtual void track(uint32_t leaf, const RayBatch& b, std::span<const uint32_t> rays, std::span<const float> limits,
                     std::span<float> collisions) = 0;

  uint32_t firstLeaf = kNoLeaf, bricks = 0;
  bool isBrick(uint32_t leaf) const { return leaf >= firstLeaf && leaf - firstLeaf < bricks; }
  // Set by the engine when it ran the brick leaves of this trace (the owner clears it first).
  bool tracked = false;
};

// A product of factors in [0, 1] accumulated in any order to the same bits: the sum of their
// −log in fixed point (2^-24 per unit: a ratio-tracking factor is 0 or at least 1/16, so 2^39
// factors fit), and a flag for an exact zero. Thread-safe: add() is atomic.
class TransmittanceProduct {
 public:
  static constexpr double kScale = double(1 << 24);
  static constexpr uint64_t kZero = uint64_t(1) << 63;
  // The quantised term of one factor (what add() adds, and what a product of one walk sums).
  static uint64_t term(float factor) {
    if (!(factor > 0)) return kZero;
    if (factor >= 1) return 0;
    return uint64_t(std::llround(-std::log(double(factor)) * kScale));
  }
  static float valueOf(uint64_t sum) { return sum & kZero ? 0.0f : float(std::exp(-double(sum) / kScale)); }
  // Adds a term to a sum held elsewhere (a slot of an array), atomically.
  static void add(uint64_t& sum, uint64_t t) {
    std::atomic_ref<uint64_t> s(sum);
    if (t & kZero) s.fetch_or(kZero, std::memory_order_relaxed);
    else if (t) s.fetch_add(t, std::memory_order_relaxed);
  }
  // The same, for a sum one thread owns.
  static void addLocal(uint64_t& sum, uint64_t t) { sum = t & kZero ? sum | kZero : sum + t; }
};

}  // namespace rayes
