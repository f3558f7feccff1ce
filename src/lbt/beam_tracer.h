// The light phase of light beam tracing (docs/design.md, "Light beam tracing"): the corner
// rays of the generator triangles (lbt/beam_seeds.h) are traced as generations of a RayBatch
// through the same ray engine as camera rays (the app passes its engine as `trace`); at each
// specular or glossy scatterer every corner ray is reflected (conductors, glossy lobes, total
// internal reflection) or refracted (dielectrics) about its interpolated vertex normal, so
// neighbouring beams keep sharing corner rays. Each straight piece after the first scattering
// is a BeamSegment. A beam stops (and is counted by reason) when its corners reach different
// materials or a non-scatterer, straddle a silhouette or total internal reflection, stop being
// coaxial, or after maxDepth scatterings; a first beam whose corners miss their aims (another
// surface in front of their leaf) ends there (none on target) or splits (some). Flux: Φ = I·Ω (or E·A), times each bounce's
// reflectance averaged over the three corners; σ² adds up over glossy bounces.
// Splitting: a beam that stops for one of those reasons is split into four (its first corner
// rays subdivided at edge midpoints, flux in proportion) and the children are traced again
// from the light, as generations through the engine, in a later pass; they emit segments only
// from the generation where their parent stopped. After splitDepth splits the beam is dropped
// and the flux its scattering corners carried is counted (droppedFlux). Dielectrics: a beam
// whose corners refract also spawns its Fresnel-reflected branch (weight F per corner, TIR
// corners F = 1), traced the same way, so glass carries both parts; a beam straddling total
// internal reflection splits, its reflected branch is whole.
//
// Deterministic: segments come out ordered by seed triangle (then pass, generation, triangle)
// whatever the thread count or how many rays each trace() call holds, and the segments of
// seeds.range(a, b) traced alone are the same run of that order (batches, BeamBatches).
#pragma once
#include <algorithm>
#include <cstdint>
#include <functional>
#include <vector>
#include "core/ray_batch.h"
#include "lbt/beam_budget.h"
#include "lbt/beam_seeds.h"
#include "lbt/beam_segment.h"
#include "shading/shading_scene.h"

namespace rayes {

struct BeamTraceStats {
  uint64_t cornerRays = 0;          // rays traced, all generations
  uint64_t generatorTriangles = 0;
  uint64_t segments = 0;
  int generations = 0;
  // Beams stopped before maxDepth at a scatterer, by reason.
  uint64_t stoppedMixed = 0;        // corners on different materials, some on a non-scatterer, or some first corners off their aim
  uint64_t stoppedSilhouette = 0;   // corners on both sides of a surface, or leaking through it
  uint64_t stoppedTir = 0;          // some corners refracted, others totally reflected
  uint64_t stoppedDivergent = 0;    // corner rays no longer roughly coaxial
  uint64_t splits = 0;              // beams split into four instead of stopping
  uint64_t reflectedBranches = 0;   // Fresnel-reflected beams spawned at dielectrics
  double droppedFlux = 0;           // W (mean over RGB) of beams stopped after splitDepth splits

  // Another run's counts added in (generations: the deepest of the two), as for beam batches.
  void add(const BeamTraceStats& o) {
    cornerRays += o.cornerRays;
    generatorTriangles += o.generatorTriangles;
    segments += o.segments;
    generations = std::max(generations, o.generations);
    stoppedMixed += o.stoppedMixed;
    stoppedSilhouette += o.stoppedSilhouette;
    stoppedTir += o.stoppedTir;
    stoppedDivergent += o.stoppedDivergent;
    splits += o.splits;
    reflectedBranches += o.reflectedBranches;
    droppedFlux += o.droppedFlux;
  }
};

struct BeamTraceOptions {
  int maxDepth = 4;          // ≥ 1 scatterings
  int splitDepth = 4;        // ≥ 0 splits of a beam before it is dropped
  float far = 1e30f;         // the length given to a corner ray that escapes the scene
  size_t raysPerTrace = 1;   // ≥ 1: the most rays handed to one trace() call
};

using TraceRays = std::function<void(RayBatch&)>;

// Adds to stats (so batches accumulate) when it returns. Memory: every array it makes (the
// passes' corner rays and triangles, split children, a generation's rays and scatterings, the
// segments) is taken from `budget` (may be null) before it is made and given back when freed;
// BeamBudgetExceeded when one does not fit (nothing is added to stats then). The returned
// segments' bytes stay taken, held by `keep` (given back at once when it is null).
std::vector<BeamSegment> traceBeams(const ShadingScene& scene, const BeamSeeds& seeds, const BeamTraceOptions& options,
                                    const TraceRays& trace, BeamTraceStats& stats, BeamBudget* budget = nullptr,
                                    BeamCharge* keep = nullptr);

}  // namespace rayes
