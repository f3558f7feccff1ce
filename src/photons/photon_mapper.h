// Photon mapping (`--method pm`) and progressive photon mapping (`--method ppm`): the baselines
// light beam tracing is measured against (docs/design.md, "Caustic paths"). Both are the path
// tracer without caustic paths (CausticPaths::Without) plus a photon estimate of exactly those
// paths at every diffuse vertex of a camera path, so nothing is counted twice.
//   photons: light passes of the Renderer (integrator.h) trace paths from the lights through
//            the same engine, a generation at a time (shading/light_path.h: the light tracer's
//            emission and continuation); a photon is stored where a path first reaches a
//            diffuse surface after one or more caustic scatterers, and the path ends there.
//            Photon ids are global (photonsPerSample per sample), keyed like light paths.
//   pm:      one map of photonsPerSample x spp photons before the first pass; radiance
//            L = sum f(wo, wi_p) Phi_p / (pi r²) over the k nearest photons (r: the k-th's
//            distance, at most 4 r0). Consistent only as photons and k grow together.
//   ppm:     Knaus and Zwicker's probabilistic formulation: every pass of samples [s0, s1)
//            traces a fresh map of photonsPerSample x (s1 - s0) photons; camera sample s
//            gathers within radius r_s, r²_{s+1} = r²_s (s + α) / (s + 1) (α in (0, 1)), so
//            bias and variance both vanish as samples grow. Each sample is one iteration.
//   r0:      --photon-radius, or from the first map: the median distance of the k-th nearest
//            photon around 64 of its photons (deterministic).
// Photons that would land on a surface facing away (normals more than ~45 degrees apart) are
// not gathered. Memory: the photon map, counted in the stats (photon_map_bytes, peak).
#pragma once
#include <memory>
#include "shading/integrator.h"
#include "shading/shading_scene.h"

namespace rayes {

// Photon counts are per sample per pixel of the render, so doubling --spp doubles the effort
// (rayes converge relies on it).
struct PhotonOptions {
  bool progressive = false;            // ppm (else pm)
  CausticPaths causticPaths = CausticPaths::Without;  // Without: pt's other paths too; Only: the estimate alone
  uint64_t photonsPerSample = 20000;   // pm: one map of photonsPerSample * spp; ppm: per pass
  int neighbours = 32;                 // pm: k of the k-nearest estimate
  float radius = 0;                    // ppm: first radius; 0: from the first map's k-nearest
  float alpha = 2.0f / 3.0f;           // ppm: r²(i+1) = r²(i) (i + α) / (i + 1)
  // The probability a caustic estimate is taken at a diffuse vertex after the path's first
  // (--later-gathers; PathTracer::Options::laterGatherProbability).
  float laterGatherProbability = kLaterGatherProbability;
};

std::unique_ptr<Integrator> makePhotonMapper(const ShadingScene& scene, const PhotonOptions& options);

}  // namespace rayes
