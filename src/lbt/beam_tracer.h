// The light phase of light beam tracing (docs/design.md, "Light beam tracing"): the corner
// rays of the generator triangles (lbt/beam_seeds.h) are traced as generations of a RayBatch
// through the same ray engine as camera rays (the app passes its engine as `trace`); at each
// specular or glossy scatterer every corner ray is reflected (conductors, glossy lobes, total
// internal reflection) or refracted (dielectrics) about its interpolated vertex normal, so
// neighbouring beams keep sharing corner rays. Each straight piece after the first scattering
// is a BeamSegment. A beam stops (and is counted by reason) when its corners reach different
// materials or a non-scatterer, straddle a silhouette or total internal reflection, stop being
// coaxial, or after maxDepth scatterings. Flux: Φ = I·Ω (or E·A), times each bounce's
// reflectance averaged over the three corners; σ² adds up over glossy bounces.
// Not done (documented limits): a stopped beam is not split into smaller ones, so energy is
// lost along scatterer edges and seams in a band one cell wide; dielectrics carry only the
// refracted part (the Fresnel-reflected part of glass is dropped).
//
// Deterministic: segments come out in (generation, triangle) order whatever the thread count
// or how many rays each trace() call holds.
#pragma once
#include <cstdint>
#include <functional>
#include <vector>
#include "core/ray_batch.h"
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
  uint64_t stoppedMixed = 0;        // corners on different materials, or some on a non-scatterer
  uint64_t stoppedSilhouette = 0;   // corners on both sides of a surface, or leaking through it
  uint64_t stoppedTir = 0;          // some corners refracted, others totally reflected
  uint64_t stoppedDivergent = 0;    // corner rays no longer roughly coaxial
};

using TraceRays = std::function<void(RayBatch&)>;

// maxDepth ≥ 1 scatterings; far: the length given to a corner ray that escapes the scene;
// raysPerTrace ≥ 1: the most rays handed to one trace() call.
std::vector<BeamSegment> traceBeams(const ShadingScene& scene, const BeamSeeds& seeds, int maxDepth, float far,
                                    size_t raysPerTrace, const TraceRays& trace, BeamTraceStats& stats);

}  // namespace rayes
