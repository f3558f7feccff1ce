// START HERE for integrators. An Integrator turns the hits of one generation of rays into the
// next generation and, at the end of a batch, into film contributions. The Renderer drives
// every integrator the same way (thesis §6.2.2, "group rays by generation"):
//
//   start(first, count, rays)  paths [first, first + count) of the render begin; their first
//                              rays are written into `rays`;
//   shade(bounce, rays, stats) after the rays were traced: consume their hits, write the next
//                              generation in place; returns how many rays were written (0: the
//                              batch is done, unless leaf queries are still pending in
//                              rays.queries: then one more trace runs them, and one more shade
//                              adds them);
//   finish(film, stats)        add the batch's results to the film in a fixed order.
//
// Slots: path k of a batch owns ray slots [k * raysPerPath(), (k + 1) * raysPerPath()) and
// touches no others, so paths are shaded in parallel without locks. Path ids are sample-major
// (sample * pixels + pixel) unless the integrator accepts setPixelBlock (then block by block of
// pixels, each block's samples together); batches are contiguous id ranges started in
// increasing order, and finish() must add to each pixel in an order fixed by the path ids alone,
// so the image is bit-identical for any thread count, batch size, pixel block and trace order
// (docs/design.md, invariant 2).
// bytesPerPath() is the integrator's own state per path (besides its ray slots), so the ray
// memory budget can be divided into whole paths.
//
// Light passes (photon mapping): before the camera paths of the pass over samples [s0, s1),
// the Renderer traces the integrator's own paths with ids lightPaths(s0, s1) = [first, end)
// the same way, in batches: startLight / { trace, shadeLight } / finishLightBatch, then
// lightPassDone once. The default is none.
//
// This header sees only core and shading: the rays side (src/rays) traces the RayBatch and
// never sees an integrator; the app holds both.
#pragma once
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>
#include "core/ray_batch.h"
#include "core/timer.h"
#include "shading/film.h"
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
  TimeAccumulator shade, sort;  // wall clock; sort is the (material, leaf) sort, inside shade
};

class Integrator {
 public:
  virtual ~Integrator() = default;
  virtual uint32_t raysPerPath() const = 0;
  virtual size_t bytesPerPath() const = 0;
  // Bytes the integrator keeps per leaf of the scene, made once (counted in the stats' scene
  // description).
  virtual size_t leafTableBytes() const { return 0; }
  virtual void start(uint64_t first, uint32_t count, RayBatch& rays) = 0;
  virtual size_t shade(uint32_t bounce, RayBatch& rays, ShadeStats& stats) = 0;
  virtual void finish(Film& film, ShadeStats& stats) = 0;
  // Orders camera path ids by blocks of n pixels, every sample of a block before the next block
  // (PathTracer::setPixelBlock), if the integrator can; false: ids stay sample-major.
  virtual bool setPixelBlock(uint32_t /*n*/) { return false; }

  struct IdRange { uint64_t first = 0, end = 0; };
  virtual IdRange lightPaths(int /*s0*/, int /*s1*/) const { return {}; }
  virtual void startLight(uint64_t /*first*/, uint32_t /*count*/, RayBatch& /*rays*/) {}
  virtual size_t shadeLight(uint32_t /*bounce*/, RayBatch& /*rays*/, ShadeStats& /*stats*/) { return 0; }
  virtual void finishLightBatch(ShadeStats& /*stats*/) {}
  virtual void lightPassDone(ShadeStats& /*stats*/) {}
};

// LightBeams: the path tracer without caustic paths plus the caustic gather of light beams
// (src/lbt; the app builds the beams and hands them to the path tracer).
enum class IntegratorMethod { PathTracing, LightTracing, PhotonMapping, ProgressivePhotonMapping, LightBeams };

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
// Measured (bench/RESULTS.md, "Fewer gathers after the first diffuse vertex"): q = 0.25 made
// lbt on lbt-discoball-glossy 27 % more efficient (its glossy gathers are dear), but cost
// lbt and pm on lbt-discoball (σ = 0.001) a third of theirs: cheap gathers save no time and
// the room's indirect caustic light gets noisier.
inline constexpr float kLaterGatherProbability = 1.0f;

// What the methods take besides the scene. Photon counts are per sample per pixel of the
// render, so doubling --spp doubles every method's effort (rayes converge relies on it).
struct IntegratorOptions {
  CausticPaths causticPaths = CausticPaths::All;  // pt and lt
  uint64_t photonsPerSample = 20000;   // pm: one map of photonsPerSample * spp; ppm: per pass
  int photonNeighbours = 32;           // pm: k of the k-nearest estimate
  float photonRadius = 0;              // ppm: first radius; 0: from the first map's k-nearest
  float photonAlpha = 2.0f / 3.0f;     // ppm: r²(i+1) = r²(i) (i + α) / (i + 1)
  // lbt, pm, ppm: the probability a caustic estimate is taken at a diffuse vertex after the
  // path's first (--later-gathers; PathTracer::Options::laterGatherProbability).
  float laterGatherProbability = kLaterGatherProbability;
};

// "pt", "lt", "pm", "ppm", "lbt": the names of the command line and the stats.
const std::vector<std::string>& integratorMethodNames();
// Throws InputError naming `where` for an unknown name.
IntegratorMethod integratorMethodFromName(const std::string& name, const std::string& where);
const char* integratorMethodName(IntegratorMethod method);
// The path and light tracers (the photon mappers live in src/lbt: lbt/photon_mapper.h).
std::unique_ptr<Integrator> makeIntegrator(IntegratorMethod method, const ShadingScene& scene,
                                           const IntegratorOptions& options = {});

}  // namespace rayes
