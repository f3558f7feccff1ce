// Photon mapping (`--method pm`) and progressive photon mapping (`--method ppm`): the baselines
// light beam tracing is measured against (docs/design.md, "Caustic paths"). Both are the path
// tracer without caustic paths (CausticPaths::Without) plus a photon estimate of exactly those
// paths at every diffuse vertex of a camera path, so nothing is counted twice.
//   photons: light passes of the Renderer (integrator.h) trace paths from the lights through
//            the same engine, a generation at a time (shading/light_path.h: the light tracer's
//            emission and continuation); a photon is stored where a path first reaches a
//            diffuse surface after one or more caustic scatterers, and the path ends there.
//            Photon ids are global (photonsPerSample per sample), keyed like light paths.
//   pm:      one map of photonsPerSample x spp photons before the first pass; each photon
//            gets its own radius r_p, the distance to its k-th nearest other photon (within
//            [r0/64, 4 r0]); radiance L = sum f(wo, wi_p) Phi_p / (pi r_p²) over the photons
//            whose disk holds the point (the sample-point estimate: unbiased for a locally
//            uniform density, and flux-preserving; the bias left is the blur of the density's
//            variation over r_p, at a caustic's edges). Consistent as photons grow at fixed k.
//   ppm:     Knaus and Zwicker's probabilistic formulation: every pass of samples [s0, s1)
//            traces a fresh map of photonsPerSample x (s1 - s0) photons; camera sample s
//            gathers within radius r_s, r²_{s+1} = r²_s (s + α) / (s + 1) (α in (0, 1)), so
//            bias and variance both vanish as samples grow. Each sample is one iteration.
//   r0:      --photon-radius, or from the first map: the median distance of the k-th nearest
//            photon around 64 of its photons (deterministic).
// Photons that would land on a surface facing away (normals more than ~45 degrees apart) are
// not gathered. Memory: the photon map, counted in the stats (photon_map_bytes, peak). Before
// any photon is traced, the largest map's worst case (every light path stores its photon:
// kPhotonPeakBytes each, while the map is gathered and built) plus the light batch's state must
// fit half of the memory limit (core/memory.h; PhotonOptions::memoryBytes), and the map at most 2^32 - 1
// photons, or the render is refused with ResourceError("--photons").
#pragma once
#include <memory>
#include "photons/photon_map.h"
#include "shading/integrator.h"
#include "shading/shading_scene.h"

namespace rayes {

// ppm's default α: 1/3, not Knaus and Zwicker's 2/3. A caustic's error is mostly its edges':
// the blur moves flux across them in a band as wide as the radius, so the squared error there
// falls as r ~ s^-(1-α)/2 while the noise falls as s^-α, which balance at α = 1/3 (2/3 balances
// the r⁴ bias of a smooth density). Measured on scenes/caustic-closed-form.json (bench/history/
// 2026-11.md, "pm unbiased, ppm's defaults, on the closed-form caustic"): RMSE at 128 spp 23-24 %
// below α = 2/3 for two seeds, and the best or within 2 % of the best of six settings from 16 spp.
inline constexpr float kDefaultPhotonAlpha = 1.0f / 3.0f;

// Photon counts are per sample per pixel of the render, so doubling --spp doubles the effort
// (rayes converge relies on it).
struct PhotonOptions {
  bool progressive = false;            // ppm (else pm)
  CausticPaths causticPaths = CausticPaths::Without;  // Without: pt's other paths too; Only: the estimate alone
  uint64_t photonsPerSample = 20000;   // pm: one map of photonsPerSample * spp; ppm: per pass
  int neighbours = 32;                 // pm: each photon's radius reaches its k-th nearest other photon
  float radius = 0;                    // ppm: first radius; 0: from the first map's k-nearest
  float alpha = kDefaultPhotonAlpha;    // ppm: r²(i+1) = r²(i) (i + α) / (i + 1)
  // The probability a caustic estimate is taken at a diffuse vertex after the path's first
  // (--later-gathers; PathTracer::Options::laterGatherProbability).
  float laterGatherProbability = kLaterGatherProbability;
  // The photon maps' memory budget; 0: half of the memory limit, processMemoryLimit() (none if no limit can be read).
  uint64_t memoryBytes = 0;
};

// The most bytes one stored photon costs at the peak, while its map is gathered and built: the
// gathered vector at up to twice its size, growing (a reallocation holds the old and new
// buffers: under 3 photons each), then the build's sorted copy next to the gathered one, the
// build order (uint32_t) and split axes (uint8_t); the gather radii (2 floats) come after the
// gathered vector is freed.
inline constexpr uint64_t kPhotonPeakBytes = 3 * sizeof(Photon) + sizeof(uint32_t) + sizeof(uint8_t);
uint64_t photonMapPeakBytes(uint64_t photons);
// Photons of the largest map a render of samplesPerPixel traces: pm's one map, ppm's largest pass.
uint64_t largestPhotonMap(const PhotonOptions& options, int samplesPerPixel);
// Throws ResourceError("--photons") when that map might exceed 2^32 - 1 photons or, with every
// light path storing a photon, photonMapPeakBytes plus lightBatchBytes exceeds the budget.
void checkPhotonMemory(const PhotonOptions& options, int samplesPerPixel, uint64_t lightBatchBytes);

std::unique_ptr<Integrator> makePhotonMapper(const ShadingScene& scene, const PhotonOptions& options);

}  // namespace rayes
