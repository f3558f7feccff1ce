// The live progress of this process's render: a few atomics the render thread and the set-up
// code write cheaply (relaxed stores; never a lock, never a wait), and the progress reporter's
// timer thread reads (app/progress.h). One per process (liveProgress()): the program renders
// one scene at a time; `rayes converge` renders several in turn, each starting it afresh.
//
// Paths finished inside a batch: after each generation the render thread may count the batch's
// paths that wrote no ray (their slots are all Inactive: the path ended). It does so only when
// the reporter asked since the last count (countWanted), so a render without progress, or
// between two redraws, pays one atomic load per generation.
#pragma once
#include <atomic>
#include <cstdint>
#include "core/ray_batch.h"

namespace rayes {

enum class Phase : int {
  Starting,
  LoadingScene,      // reading and parsing the scene, growing generated shapes (forests)
  BuildingTopLevel,  // leaf boxes, the top-level BVH, shading's view of the scene
  Tessellating,      // --engine embree: every patch diced up front
  TracingBeams,      // lbt: the beams, before the first pass
  Preparing,         // other methods' work before the first pass
  TracingPhotons,    // pm, ppm: a pass's photon map
  Rendering,         // camera paths
  Writing,           // the outputs
  Done,
};
const char* phaseName(Phase p);  // "loading the scene", ...

struct ProgressState {
  std::atomic<int> phase{int(Phase::Starting)};
  std::atomic<uint64_t> pathsTotal{0}, pathsDone{0};  // camera paths of the render; done: whole batches
  std::atomic<uint64_t> batchPaths{0}, batchPathsDone{0};  // the running camera batch
  std::atomic<int> samplesTotal{0}, samplesDone{0};  // samples per pixel finished (whole passes)
  std::atomic<int> generation{-1};                   // the running batch's last generation traced (-1: none)
  std::atomic<bool> countWanted{false};

  void reset();
  void setPhase(Phase p) { phase.store(int(p), std::memory_order_relaxed); }
  Phase currentPhase() const { return Phase(phase.load(std::memory_order_relaxed)); }
  // The Renderer's hooks: a camera batch of `paths` paths begins; a generation of the running
  // batch was traced and shaded (`rays` holds the next one; path k owns slots
  // [k * raysPerPath, (k + 1) * raysPerPath)); a batch (or pass) ended with `done` of `total`
  // paths and `samples` spp finished.
  void startBatch(uint64_t paths);
  void afterGeneration(uint32_t depth, const RayBatch& rays, size_t raysPerPath);
  void batchDone(uint64_t done, uint64_t total, int samples);
  // Paths done: whole batches and, as last counted, the running one's.
  uint64_t paths() const;
};

ProgressState& liveProgress();

// Paths of a batch whose ray slots are all Inactive (finished), among the first `paths` paths.
uint64_t finishedPaths(const RayBatch& rays, size_t raysPerPath, uint64_t paths);

}  // namespace rayes
