// The per-pixel cost layers of a render (`--cost-layers`; docs/stats.md, "Cost layers"): the
// dicings charged to each pixel's camera paths and the render time apportioned to it, written
// as the EXR layers dicings.Y and time.Y beside lod.Y (the level at the first hit, always
// written).
//
// Dicings: the engine splits each dicing among the rays that caused it (RayBatch::dicingShare,
// fixed point); after every trace of a camera batch the shares of a path's ray slots are added
// to the path, and at the batch's end each path's sum to its pixel. The sums are integers, so
// the layer is bit-identical at any thread count, and its total is exactly the dicings of the
// camera batches (light paths, lt's camera batches and lbt's corner rays are charged to no
// pixel: `cost_layers.dicings_not_charged`).
// Time: each camera batch's wall time (its rounds, generations and film) is measured and
// shared among its paths in proportion to the rays each traced. A measurement: it differs from
// run to run and with the thread count.
//
// Memory: 16 bytes per pixel of the film's window, and per path of the largest batch
// bytesPerPath() (the renderer adds it to the path's cost in the ray budget). Not thread-safe:
// the renderer calls it between traces; afterTrace runs its own parallel loop.
#pragma once
#include <cstdint>
#include <functional>
#include <vector>
#include "core/ray_batch.h"
#include "shading/film.h"

namespace rayes {

class PixelCost {
 public:
  PixelCost(const PixelWindow& window, int fullWidth);
  // What a path of the batch costs while it is traced: its dicing sum and ray count, and the
  // shares of its ray slots in the RayBatch.
  static constexpr size_t bytesPerPath(size_t raysPerPath) {
    return sizeof(uint64_t) + sizeof(uint32_t) + raysPerPath * sizeof(uint64_t);
  }
  // A camera batch of `paths` paths of `raysPerPath` ray slots (slots k·raysPerPath … belong to
  // path k) starts.
  void startBatch(uint32_t paths, uint32_t raysPerPath);
  // After a trace of the batch's rays: each path's traced rays are counted and its slots' dicing
  // shares taken (and cleared).
  void afterTrace(RayBatch& rays);
  // The batch took `seconds`: path k's dicings and its share of the time go to pixel
  // pixelOf(k) (-1 or outside the window: charged to no pixel).
  void finishBatch(double seconds, const std::function<int64_t(uint32_t)>& pixelOf);

  // The layers over the window, row order: dicings (fractional: shares of dicings) and seconds.
  std::vector<float> dicings() const;
  std::vector<float> seconds() const;
  // Dicings charged to pixels (exact) and those of camera batches charged to none.
  double dicingsCharged() const;
  double dicingsNotCharged() const;
  double secondsCharged() const { return secondsCharged_; }
  // The fixed-point sum of every pixel's dicings (RayBatch::kDicingShareOne per dicing).
  uint64_t dicingsChargedFixed() const { return chargedFixed_; }
  size_t bytes() const;

 private:
  PixelWindow window_;
  int fullWidth_;
  uint32_t raysPerPath_ = 0;
  std::vector<uint64_t> pixelDicings_;  // fixed point, per pixel of the window
  std::vector<double> pixelSeconds_;
  std::vector<uint64_t> pathDicings_;   // the batch's paths
  std::vector<uint32_t> pathRays_;
  uint64_t chargedFixed_ = 0, unchargedFixed_ = 0;
  double secondsCharged_ = 0;
};

}  // namespace rayes
