// START HERE for the whole program. The Renderer is the scheduler: it turns a Scene into a
// Film by driving one Integrator (made by app/methods.h from --method; the Renderer knows no
// method by name) and one RayEngine through memory-bounded batches. It owns the budget, the
// passes, the batches and the generations, and nothing else:
//
//   setup:  RenderData (leaf boxes, TopLevelBvh, shading's view of the scene, feature counts);
//           the integrator, and the ray engine (--engine: the sorted engine, the caching engine,
//           or the Embree engine that tessellates everything here); the ray memory budget
//           divided by the bytes one path costs (the integrator's state, its ray slots and the
//           engine's bytes per ray slot) fixes how many paths a batch holds and the candidate
//           capacity; then Integrator::prepare, with a way to trace through the engine.
//   passes: one pass of all samples per pixel, split into batches of whole paths that fit the
//           budget, so every leaf is diced as few times as the budget allows: by blocks of
//           pixels, each batch every sample of a stripe of the image (Integrator::
//           setPixelBlock), where the integrator allows it. Progressive (--progressive, a
//           --reference to measure against, or an integrator whose traits ask for it): passes
//           of 1, 1, 2, 4, ... samples per pixel, a complete image after each (the
//           error-against-time curve is recorded per pass), for about 1 + log2(spp) times the
//           dicings. All give the same bits: a path's pixel and sample do not depend on the
//           order of ids, and the film adds a pixel's samples in sample order. Before a pass's
//           camera paths, the integrator's light paths (Integrator::lightPaths), if any.
//   batch:  for each of Integrator::roundsPerBatch rounds: startRound, start -> repeat
//           { RayEngine::trace (one generation) -> Integrator::shade (next generation) } until
//           no ray is left; then Integrator::finish.
//
// Determinism: the film is a pure function of (scene, settings, seed) under the default
// per-ray LOD: batches cover whole sample indices or whole pixels, the film adds samples in order.
// Not thread-safe; render() uses all threads allowed by the caller's ThreadLimit.
#pragma once
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>
#include "app/render_data.h"
#include "app/methods.h"
#include "rays/caching_engine.h"
#include "rays/embree_engine.h"
#include "rays/sorted_engine.h"
#include "scene/scene.h"
#include "shading/film.h"
#include "shading/integrator.h"

namespace rayes {

enum class EngineKind { Rayes, Embree };

// The default ray memory budget under a memory limit of `limitBytes` (core/memory.h: the
// cgroup's, RLIMIT_AS or physical memory, the smallest): an eighth of it, at least 256 MiB and
// at most 2 GiB, so that a render's peak (the budget, one dice buffer per thread, the film, the
// scene) stays under 4 GiB; 1 GiB where no limit can be read (0).
// A larger batch means fewer dicings per ray, never a different image.
size_t defaultRayMemoryBytes(uint64_t limitBytes);
size_t defaultRayMemoryBytes();  // under this process's limit

struct RenderOptions {
  EngineKind engine = EngineKind::Rayes;
  bool embreeAutoLod = false;    // Embree engine: per-patch level from the camera (else maxLod)
  size_t memoryLimitBytes = 0;   // Embree engine: refuse a tessellation larger than this (0: none)
  size_t diceCacheEntries = 0;   // > 0: the CachingEngine with this many entries (--dice-cache)
  int maxLod = 10;
  LodRule lod = LodRule::PerRay;
  int lodBias = 0;               // TraceSettings::lodBias (--lod-bias)
  int candidatesPerRay = TraceSettings::kDefaultCandidatesPerRay;  // TraceSettings::maxCandidatesPerRay (--candidates-per-ray)
  size_t rayMemoryBytes = defaultRayMemoryBytes();
  size_t gridCacheBytes = size_t(512) << 20;  // TraceSettings::gridCacheBytes (--grid-cache); 0: off
  bool sortByLeaf = true;
  bool progressive = false;      // passes of 1, 1, 2, 4, ... spp (implied by a reference)
  MethodOptions method;          // --method and the options of each method
  std::vector<float> reference;  // RGB per pixel; empty: no error curve; else one point per pass
};

struct GenerationRecord {
  int pass = 0, batch = 0, depth = 0;
  GenerationStats stats;
};

struct ErrorSample {
  int spp;
  double seconds;
  double rmse;
};

// Memory by owner (docs/stats.md): what each part of a render holds at its largest. Only the
// scene description grows with the leaf count; nothing grows with the micropolygons a scene
// could produce.
struct MemoryByOwner {
  size_t rayBuffers = 0;         // the RayBatch and the integrator's path state, at the batch size
  size_t candidatesAndSort = 0;  // the engine's per-ray-slot state: candidates, sort scratch, trace state
  size_t topLevel = 0;           // the top-level BVH's nodes
  size_t diceBuffers = 0;        // Rayes: the per-thread dice buffers; Embree: the whole tessellation
  size_t diceCache = 0;          // diced grids kept between uses (--grid-cache, --dice-cache), at their peak
  size_t borderBounds = 0;       // Rayes: border boxes and radii kept between dicings (fixed capacity)
  size_t film = 0;
  size_t sceneDescription = 0;   // the leaves (records, boxes, stored patches) and every per-leaf table
  uint64_t leaves = 0;
};

struct RenderStats {
  SceneFeatures features;
  std::vector<GenerationRecord> generations;
  double timeSetup = 0, timeTotal = 0, timeFilm = 0;
  TraceTimes trace;
  ShadeStats shade;
  EngineStats engine;
  uint64_t micropolygonsPotential = 0;
  uint64_t pathsPerBatch = 0, candidateCapacity = 0, batches = 0;
  uint64_t pixelsPerBlock = 0;   // batches by blocks of this many pixels, all their samples (0: sample-major)
  bool progressive = false;      // rendered in passes (asked for, or the integrator's traits)
  size_t raysPerPath = 0;        // ray slots per path (bytes_per_ray = bytesPerPath / raysPerPath)
  size_t bytesPerPath = 0, topLevelBytes = 0, diceBufferBytes = 0;
  MemoryByOwner memory;
  std::vector<ErrorSample> errorCurve;
  std::vector<std::pair<std::string, uint64_t>> leafKinds;
  MethodStats method;            // the method's own section (Integrator::methodStats)
};

class Renderer {
 public:
  // Throws InputError when the budget cannot hold a single path.
  Renderer(const Scene& scene, const RenderOptions& options);
  ~Renderer();

  // progress(done paths, total paths, samples finished so far)
  using Progress = std::function<void(uint64_t, uint64_t, int)>;
  Film render(const Progress& progress = {});
  const RenderStats& stats() const { return stats_; }
  // What one path costs in the ray memory budget (the unit of --ray-memory).
  size_t bytesPerPath() const { return stats_.bytesPerPath; }
  // The method being rendered with (its own statistics: Integrator::methodStats).
  const Integrator& integrator() const { return *integrator_; }

 private:
  MemoryByOwner memoryAtSetup(uint64_t raysPerPath) const;
  // Whether the ray batches keep a shutter time per ray: only when something moves.
  bool raysTimed() const { return stats_.features.movingLeaves > 0; }
  void traceLightPass(int s0, int s1, int pass, int& batch);

  const Scene& scene_;
  RenderOptions options_;
  RenderData data_;
  std::unique_ptr<Integrator> integrator_;
  std::unique_ptr<RayEngine> engine_;
  RenderStats stats_;
  // One camera batch: every round of the integrator, then its film.
  void runCameraBatch(uint64_t first, uint32_t count, int pass, int batch, RayBatch& rays, Film& film);
  // Generations of the batch in `rays` until no path goes on (camera paths, or the
  // integrator's light paths).
  void runGenerations(int pass, int batch, RayBatch& rays, bool lightPaths);
};

// Root-mean-square difference of the film's mean RGB against a reference (RGB per pixel).
double rmseAgainst(const Film& film, const std::vector<float>& referenceRgb);

}  // namespace rayes
