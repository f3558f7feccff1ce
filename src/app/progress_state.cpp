#include "app/progress_state.h"
#include <algorithm>
#include <functional>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

namespace rayes {

const char* phaseName(Phase p) {
  switch (p) {
    case Phase::Starting: return "starting";
    case Phase::LoadingScene: return "loading the scene";
    case Phase::BuildingTopLevel: return "building the top level";
    case Phase::Tessellating: return "tessellating for Embree";
    case Phase::TracingBeams: return "tracing beams";
    case Phase::Preparing: return "preparing the method";
    case Phase::TracingPhotons: return "tracing photons";
    case Phase::Rendering: return "rendering";
    case Phase::Writing: return "writing the outputs";
    case Phase::Done: return "done";
  }
  return "?";
}

void ProgressState::reset() {
  setPhase(Phase::Starting);
  for (auto* a : {&pathsTotal, &pathsDone, &batchPaths, &batchPathsDone}) a->store(0, std::memory_order_relaxed);
  samplesTotal.store(0, std::memory_order_relaxed);
  samplesDone.store(0, std::memory_order_relaxed);
  generation.store(-1, std::memory_order_relaxed);
  countWanted.store(false, std::memory_order_relaxed);
}

void ProgressState::startBatch(uint64_t paths) {
  batchPaths.store(paths, std::memory_order_relaxed);
  batchPathsDone.store(0, std::memory_order_relaxed);
  generation.store(-1, std::memory_order_relaxed);
}

uint64_t finishedPaths(const RayBatch& rays, size_t raysPerPath, uint64_t paths) {
  if (raysPerPath == 0) return 0;
  paths = std::min<uint64_t>(paths, rays.size() / raysPerPath);
  // One read of each slot's kind, in parallel: at most once per redraw, beside a generation's tracing.
  return tbb::parallel_reduce(
      tbb::blocked_range<uint64_t>(0, paths, 1 << 14), uint64_t(0),
      [&](const tbb::blocked_range<uint64_t>& r, uint64_t finished) {
        for (uint64_t k = r.begin(); k != r.end(); ++k) {
          bool live = false;
          for (size_t s = 0; s < raysPerPath && !live; ++s) live = rays.ray[k * raysPerPath + s].kind != RayKind::Inactive;
          finished += !live;
        }
        return finished;
      },
      std::plus<uint64_t>());
}

void ProgressState::afterGeneration(uint32_t depth, const RayBatch& rays, size_t raysPerPath) {
  generation.store(int(depth), std::memory_order_relaxed);
  if (!countWanted.exchange(false, std::memory_order_relaxed)) return;
  const uint64_t done = finishedPaths(rays, raysPerPath, batchPaths.load(std::memory_order_relaxed));
  // Rounds of one batch (lbt's beam ranges) trace the same paths again: never count backwards.
  if (done > batchPathsDone.load(std::memory_order_relaxed)) batchPathsDone.store(done, std::memory_order_relaxed);
}

void ProgressState::batchDone(uint64_t done, uint64_t total, int samples) {
  pathsTotal.store(total, std::memory_order_relaxed);
  pathsDone.store(done, std::memory_order_relaxed);
  batchPaths.store(0, std::memory_order_relaxed);
  batchPathsDone.store(0, std::memory_order_relaxed);
  samplesDone.store(samples, std::memory_order_relaxed);
}

uint64_t ProgressState::paths() const {
  const uint64_t whole = pathsDone.load(std::memory_order_relaxed);
  const uint64_t total = pathsTotal.load(std::memory_order_relaxed);
  const uint64_t p = whole + batchPathsDone.load(std::memory_order_relaxed);
  return total ? std::min(p, total) : p;
}

ProgressState& liveProgress() {
  static ProgressState state;
  return state;
}

}  // namespace rayes
