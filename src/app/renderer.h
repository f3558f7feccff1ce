// START HERE for the whole program. The Renderer turns a Scene into a Film:
//
//   setup:  leaves = the scene's patches; their conservative boxes go into the TopLevelBvh;
//           the ray memory budget fixes how many paths a batch holds and the candidate
//           capacity.
//   passes: samples are rendered in passes of 1, 1, 2, 4, ... samples per pixel (progress and
//           the error-against-time curve are reported per pass); a pass is split into batches
//           of whole paths that fit the budget.
//   batch:  PathTracer::start -> repeat { Tracer::trace (one generation) ->
//           PathTracer::shade (next generation) } until no ray is left -> PathTracer::finish.
//
// Determinism: the film is a pure function of (scene, settings, seed) under the default
// per-ray LOD: batches cover whole sample indices, the film adds samples in order.
// Not thread-safe; render() uses all threads allowed by the caller's ThreadLimit.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>
#include "rays/tracer.h"
#include "scene/scene.h"
#include "shading/film.h"
#include "shading/path_tracer.h"
#include "toplevel/toplevel_bvh.h"

namespace rayes {

struct RenderOptions {
  int maxLod = 10;
  LodRule lod = LodRule::PerRay;
  size_t rayMemoryBytes = size_t(1) << 30;
  bool sortByLeaf = true;
  std::vector<float> reference;  // RGB per pixel; empty: no error curve
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

// What the scene uses, counted once at setup: the stats say what was done and what was left
// out because nothing needed it (docs/design.md, invariant 4).
struct SceneFeatures {
  uint64_t movingLeaves = 0;         // leaves with more than one time sample
  bool shutterOpen = false;          // the camera's shutter has an interval
  uint64_t displacedLeaves = 0;
  uint64_t subdivisionLeaves = 0;
  uint64_t borderClosureLeaves = 0;  // leaves whose borders need crack-closing regions
  bool environment = false;
  uint64_t distantLights = 0;
  // Precision (docs/design.md): the coarsest float spacing over a leaf's size (the loader
  // refuses beyond 2^-8), and the leaves coarser than 2^-16, whose images may differ from the
  // same scene near the origin by more than rounding noise.
  double coarsestRelativeSpacing = 0;
  uint64_t lowPrecisionLeaves = 0;
};

struct RenderStats {
  SceneFeatures features;
  std::vector<GenerationRecord> generations;
  double timeSetup = 0, timeTotal = 0, timeFilm = 0;
  TraceTimes trace;
  ShadeStats shade;
  uint64_t micropolygonsPotential = 0;
  uint64_t pathsPerBatch = 0, candidateCapacity = 0, batches = 0;
  size_t bytesPerPath = 0, topLevelBytes = 0, diceBufferBytes = 0;
  std::vector<ErrorSample> errorCurve;
  std::vector<std::pair<std::string, uint64_t>> leafKinds;
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
  static size_t bytesPerPath();

 private:
  const Scene& scene_;
  RenderOptions options_;
  ShadingScene shading_;
  std::vector<Box3> leafBoxes_;
  TopLevelBvh top_;
  std::unique_ptr<Tracer> tracer_;
  RenderStats stats_;
};

// Root-mean-square difference of the film's mean RGB against a reference (RGB per pixel).
double rmseAgainst(const Film& film, const std::vector<float>& referenceRgb);

}  // namespace rayes
