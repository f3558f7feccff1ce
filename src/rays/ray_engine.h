// What the renderer needs from whatever finds the hits of a generation of rays. Three engines:
//   SortedEngine  (rays/sorted_engine.h)  Rayes: sorted by patch, diced on demand, per-ray LOD;
//   CachingEngine (rays/caching_engine.h) the thesis's alternative to sorting: rays one at a
//                                        time, diced grids kept in an LRU cache of K entries
//                                        (the SortedEngine's hits; for counting dicings,
//                                        Table 6.2);
//   EmbreeEngine  (rays/embree_engine.h) the peer: every patch diced once up front into Embree
//                                        grids, traced with Embree's stream API.
//
// Contract of trace(): every ray of the batch whose kind is not Inactive gets its result
// filled as documented in core/ray_batch.h: a closest ray its nearest hit in (0, tmax)
// (batch.hitOf), a shadow ray any occluder (batch.occluded; a slot of shadow pairs keeps the
// leaf alone); a ray never hits batch.ray[i].ignoreLeaf; (u, v) are the
// patch's parameters, level the dicing level the hit was found at, ng the micro-triangle's unit
// normal, ns the unit normal blended from the diced vertex normals. Shading reads nothing else,
// so the same scene shades the same way whichever engine found the hits. When batch.queries is
// set, trace() also runs its leaf queries, once per leaf (core/leaf_queries.h): the SortedEngine in
// its per-leaf stage, the others in a loop by leaf. Images are a pure function of (scene,
// settings, seed) for every engine: none depends on thread count or batching.
//
// Memory (docs/design.md, invariant 3): bytesPerRay() is what the engine keeps per ray slot of the
// largest batch beyond the RayBatch itself (the renderer divides its ray budget by it);
// sortScratchBytesPerRay() what trace() takes of the batch's RayBatch::sortScratch per ray slot
// (the renderer counts it once with the integrator's shading sort, which uses the same memory
// while the batch is shaded: core/sort_scratch.h);
// fixedBytes() is what it holds regardless of the batch (dice buffers, or the whole Embree
// scene). Not thread-safe: one trace() at a time; trace() itself runs on all threads.
#pragma once
#include <cstddef>
#include <cstdint>
#include "core/ray_batch.h"
#include "rays/trace_settings.h"

namespace rayes {

// What an engine reports besides the per-generation stats (the stats file's "engine" section).
struct EngineStats {
  const char* name = "";
  size_t fixedBytes = 0;       // dice buffers (Rayes) or vertices + normals + Embree's own bytes
  size_t leafTableBytes = 0;   // the engine's own per-leaf tables (sizes, levels; the boxes are the top level's): grow with leaves
  // Up-front tessellation (the Embree engine; zero for Rayes).
  uint64_t micropolygons = 0;  // micro-quads held, summed over time steps
  uint64_t vertices = 0;       // grid vertices held, summed over time steps
  size_t vertexBytes = 0;      // our positions and normals
  size_t embreeBytes = 0;      // Embree's allocations held after the build
  size_t embreePeakBytes = 0;  // their peak during the build
  size_t estimatedBytes = 0;   // the estimate checked against the memory limit before allocating
  double tessellateSeconds = 0, buildSeconds = 0;
  int minLevel = 0, maxLevel = 0;  // range of the per-patch levels
  // The dice cache (CachingEngine; zero otherwise). Misses are dicings.
  uint64_t cacheEntries = 0, cacheHits = 0, cacheMisses = 0;
  size_t cachePeakBytes = 0;
  size_t cacheBytes = 0;        // the grids kept now (the grid cache or the dice cache)
  size_t borderBoundBytes = 0;  // Rayes: the shared table of border bounds (part of fixedBytes)
};

class RayEngine {
 public:
  virtual ~RayEngine() = default;
  virtual void trace(RayBatch& batch, GenerationStats& stats, TraceTimes& times) = 0;
  virtual size_t bytesPerRay() const = 0;
  virtual size_t sortScratchBytesPerRay() const { return 0; }
  virtual size_t fixedBytes() const = 0;
  virtual EngineStats engineStats() const = 0;
  // Bounds the diced grids the engine keeps between traces (the sorted engine's --grid-cache)
  // by `bytes` until called again, freeing what is above it at once (SIZE_MAX: the engine's own
  // bound), and returns the bytes they hold now. For a method that charges the grids its own
  // rays leave behind to its own memory account (lbt's corner rays, under --beam-memory). Only
  // between traces; never changes a hit. The other engines keep no grids between traces by
  // bytes: nothing to bound (0).
  virtual size_t limitKeptGrids(size_t /*bytes*/) { return 0; }
};

}  // namespace rayes
