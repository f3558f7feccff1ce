// START HERE for integrators. Every method (path tracing, light tracing, photon mapping,
// progressive photon mapping, light beams) is an Integrator: it turns the hits of one
// generation of rays into the next generation and, at the end of a batch, into film
// contributions. The Renderer drives every integrator the same way (thesis §6.2.2, "group rays
// by generation") and knows none of them by name; app/methods.h makes them from the options.
//
//   prepare(setup)             once, after the ray engine exists and before the first pass:
//                              work the method does up front through the engine (lbt traces
//                              its beams); most do nothing;
//   start(first, count, rays)  paths [first, first + count) of the render begin; their first
//                              rays are written into `rays`;
//   shade(bounce, rays, stats) after the rays were traced: consume their hits, write the next
//                              generation in place; returns how many rays were written (0: the
//                              batch is done, unless leaf queries are still pending in
//                              rays.queries: then one more trace runs them, and one more shade
//                              adds them);
//   addFirstHits(rays, film, from)  right after round 0's shade(0) (the camera generation), before
//                              the next trace: add the first-hit AOVs of the batch's paths with
//                              ids >= from to the film, in finish()'s order (the film keeps AOV
//                              sums apart from the radiance's, so their bits do not depend on
//                              when); a method that keeps them in `rays` finds them there;
//   finish(film, stats)        add the batch's results to the film in a fixed order.
//
// Rounds: an integrator whose estimate does not fit memory at once (lbt's beams in batches
// under --beam-memory) asks for each camera batch to be traced roundsPerBatch() times;
// startRound(r) comes before round r's start(), addFirstHits in round 0 only (the paths are
// the same in every round), and finish() once after the last round.
//
// Slots: path k of a batch owns ray slots [k * raysPerPath(), (k + 1) * raysPerPath()) and
// touches no others, so paths are shaded in parallel without locks. Path ids are sample-major
// (sample * pixels + pixel) unless the integrator accepts setPixelBlock (then block by block of
// pixels, each block's samples together); batches are contiguous id ranges started in
// increasing order, and finish() must add to each pixel in an order fixed by the path ids alone,
// so the image is bit-identical for any thread count, batch size, pixel block and trace order
// (docs/design.md, invariant 2).
// Windows (--crop, a part of a farm split): an integrator whose camera ids are pixels takes
// setPixelWindow(w), and its ids then cover w's pixels only, each path keyed (RNG) by its
// full-image pixel and sample as in the whole image; one whose traits().lightPathIds (lt)
// traces light paths over the whole image and keeps only the splats the film's window holds.
// Anything else a method derives from the image (photon counts, radii, beams) depends on the
// full image, never on the window.
// Resume (from a checkpoint, in the middle of pass p): the Renderer traces the light paths of
// the first pass and then of pass p again, so a pass's light paths may leave state for later
// passes only from the first pass (pm's one map, ppm's first radius).
// bytesPerPath() is the integrator's own state per path (besides its ray slots), so the ray
// memory budget can be divided into whole paths; it must not change after prepare().
// sortScratchBytesPerPath() is what shade() takes of the batch's RayBatch::sortScratch per path
// (the shading sort), memory the engine's trace() uses too: the budget counts the larger of the
// two once (core/sort_scratch.h).
//
// Light passes (photon mapping): before the camera paths of the pass over samples [s0, s1),
// the Renderer traces the integrator's own paths with ids lightPaths(s0, s1) = [first, end)
// the same way, in batches: startLight / { trace, shadeLight } / finishLightBatch, then
// lightPassDone once. The default is none.
//
// An integrator is driven by one thread (the Renderer's); its kernels parallelise inside.
// This header sees only core and shading: the rays side (src/rays) traces the RayBatch and
// never sees an integrator; the app holds both and hands prepare() a way to trace.
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>
#include "core/ray_batch.h"
#include "core/timer.h"
#include "shading/film.h"
#include "shading/method_stats.h"
#include "shading/shading_scene.h"

namespace rayes {

struct ShadeStats {
  std::atomic<uint64_t> shadedHits{0}, shadowRays{0}, continuationRays{0}, nonFinite{0},
      rouletteKills{0};
  std::atomic<uint64_t> splats{0};  // light tracing: connections to the camera that reached the film
  std::atomic<uint64_t> photonsTraced{0}, photonsStored{0}, photonMapBytes{0};  // photon mapping (bytes: peak)
  // lbt, pm, ppm: caustic estimates taken at diffuse vertices, and those a later vertex's
  // roulette left out (PathTracer::Options::laterGatherProbability).
  std::atomic<uint64_t> gathers{0}, gathersSkipped{0};
  // Media (pt): real collisions (scattering vertices), transmittance estimates (shadow rays
  // through media), density lookups and brick cells walked by both trackings; time summed over
  // threads inside shade.
  std::atomic<uint64_t> mediumCollisions{0}, transmittanceEstimates{0}, densityLookups{0}, brickCellsWalked{0};
  std::atomic<uint64_t> emissionLookups{0};  // density lookups of emissionAlong (0: no medium emits)
  TimeAccumulator volume;
  TimeAccumulator shade, sort;  // wall clock; sort is the (material, leaf) sort, inside shade
};

// What an integrator may do once before the first pass (Integrator::prepare).
struct IntegratorSetup {
  std::function<void(RayBatch&)> trace;  // one generation of rays through the render's engine
  // Bounds the diced grids the engine keeps between traces until called again (SIZE_MAX: the
  // engine's own --grid-cache) and returns the bytes they hold now (RayEngine::limitKeptGrids):
  // a method whose own rays dice finer than the camera's charges those grids to its own account.
  std::function<size_t(size_t)> limitKeptGrids;
  uint64_t pathsPerBatch = 0;            // the most paths one camera batch holds
};

// What the Renderer must know of a method to schedule it.
struct IntegratorTraits {
  bool progressive = false;  // renders in passes of 1, 1, 2, 4, ... spp (ppm: a map and radius per pass)
  bool lightPasses = false;  // traces paths of its own before each pass's camera paths (lightPaths)
  // Camera batches are light paths spread over the whole image (lt): ids are not pixels, a
  // window only filters the splats, and a farm split divides the ids, not the pixels.
  bool lightPathIds = false;
  bool beamsUpFront = false;  // prepare() traces light beams (the progress line names the phase)
  // Path k's slots are 2k (any ray) and 2k+1 (shadow rays only, or none), in every batch it
  // starts: the Renderer makes its batches of shadow pairs (RayBatch::shadowPairs), whose odd
  // slots keep an occluding leaf instead of a full hit.
  bool shadowPairs = false;
};

class Integrator {
 public:
  virtual ~Integrator() = default;
  virtual IntegratorTraits traits() const { return {}; }
  virtual uint32_t raysPerPath() const = 0;
  virtual size_t bytesPerPath() const = 0;
  virtual size_t sortScratchBytesPerPath() const { return 0; }
  // Bytes the integrator keeps per leaf of the scene, made once (counted in the stats' scene
  // description).
  virtual size_t leafTableBytes() const { return 0; }
  virtual void prepare(const IntegratorSetup& /*setup*/) {}
  virtual uint32_t roundsPerBatch() const { return 1; }
  virtual void startRound(uint32_t /*round*/) {}
  virtual void start(uint64_t first, uint32_t count, RayBatch& rays) = 0;
  virtual size_t shade(uint32_t bounce, RayBatch& rays, ShadeStats& stats) = 0;
  virtual void finish(Film& film, ShadeStats& stats) = 0;
  virtual void addFirstHits(RayBatch& /*rays*/, Film& /*film*/, uint64_t /*from*/) {}  // none: no camera hits
  // Orders camera path ids by blocks of n pixels, every sample of a block before the next block
  // (PathTracer::setPixelBlock), if the integrator can; false: ids stay sample-major.
  virtual bool setPixelBlock(uint32_t /*n*/) { return false; }
  // Camera path ids cover `window`'s pixels only (PathTracer::setPixelWindow); false: the
  // integrator cannot (then only the whole image may be rendered, unless traits().lightPathIds).
  virtual bool setPixelWindow(const PixelWindow& /*window*/) { return false; }
  // The full-image pixel camera path `id` (of the current layout: block, window) lands on, or -1
  // when camera ids are not pixels (traits().lightPathIds). For charging a path's cost to its
  // pixel (app/pixel_cost.h).
  virtual int64_t cameraPixelOf(uint64_t /*id*/) const { return -1; }

  struct IdRange { uint64_t first = 0, end = 0; };
  virtual IdRange lightPaths(int /*s0*/, int /*s1*/) const { return {}; }
  virtual void startLight(uint64_t /*first*/, uint32_t /*count*/, RayBatch& /*rays*/) {}
  virtual size_t shadeLight(uint32_t /*bounce*/, RayBatch& /*rays*/, ShadeStats& /*stats*/) { return 0; }
  virtual void finishLightBatch(ShadeStats& /*stats*/) {}
  virtual void lightPassDone(ShadeStats& /*stats*/) {}

  // The method's own section of the stats file (beams), and what it left out and why.
  virtual MethodStats methodStats() const { return {}; }
};

// Which paths an estimate counts, split at caustic paths (light -> (caustic scatterer)+ ->
// diffuse vertex -> ..., isCausticScatterer in shading/material.h): all, all but those, or
// those alone. `pt --caustic-paths without` plus a caustic method is the whole image.
enum class CausticPaths : uint8_t { All, Without, Only };
inline bool counts(CausticPaths which, bool causticPath) {
  return which == CausticPaths::All || (which == CausticPaths::Only) == causticPath;
}
// "all", "without", "only"; throws InputError naming `where` for another name.
CausticPaths causticPathsFromName(const std::string& name, const std::string& where);
const char* causticPathsName(CausticPaths which);

// The default roulette on caustic estimates at diffuse vertices after a path's first: none.
// Measured (bench/history/2026-11.md, "Fewer gathers after the first diffuse vertex"): q = 0.25
// made lbt on lbt-discoball-glossy 27 % more efficient (its glossy gathers are dear), but cost lbt
// and pm on lbt-discoball (σ = 0.001) a third of theirs: cheap gathers save no time and the room's
// indirect caustic light gets noisier.
inline constexpr float kLaterGatherProbability = 1.0f;

}  // namespace rayes
