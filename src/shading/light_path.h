// The steps of a path that starts on the lights, shared by the light tracer (which connects
// its vertices to the camera) and photon mapping (which stores them): the ray leaving a light,
// what a segment's hit looks like from the light's side, and the continuation (the BSDF sampled
// from the light's side with the adjoint's weight, Russian roulette on the throughput).
// Random numbers are keyed by the path's RngKey with dimensions of their own (light_path.cpp).
#pragma once
#include <cstdint>
#include "core/ray_batch.h"
#include "core/rng.h"
#include "shading/bsdf.h"
#include "shading/integrator.h"
#include "shading/surface_hit.h"

namespace rayes {

// Where a light path stands with respect to caustic paths (integrator.h, CausticPaths): at the
// light, in a chain of caustic scatterers from it, past the diffuse vertex that ended such a
// chain (a caustic path from here on), or past a diffuse vertex reached without one.
enum class LightRun : uint8_t { AtLight, CausticChain, CausticPath, NotCaustic };
inline LightRun nextRun(LightRun run, bool causticScatterer) {
  if (run == LightRun::AtLight || run == LightRun::CausticChain)
    return causticScatterer ? LightRun::CausticChain : run == LightRun::AtLight ? LightRun::NotCaustic : LightRun::CausticPath;
  return run;
}

struct LightPathStart {
  EmissionSample e;
  float time = 0;
  float back = 0;  // an emissive patch's offset at level 0 (rays leave from its point moved off it)
  // Where a ray toward w leaves: off the emitter to w's side, so geometry flush with it does not stop it.
  Vec3 leaving(Vec3 w) const { return e.org + e.normal * (dot(e.normal, w) >= 0 ? back : -back); }
};

// Picks a light by power and samples a ray leaving it (vertex 0 of the key); false if none.
bool sampleLightPathStart(const ShadingScene& scene, const RngKey& key, LightPathStart& out);
// Writes that ray as path `path`'s closest-hit ray into slot cs.
void writeLightPathStart(const LightPathStart& s, uint32_t path, size_t cs, RayBatch& rays);

// The hit of a light path's segment (slot cs).
struct LightPathHit {
  RayHit h;
  Vec3 wi;          // unit, toward the light
  Vec3 ns;          // h's shading normal, decoded once (at.ng is its geometric normal)
  SurfaceHit at;
  float arrival;    // Veach's shading-normal correction on the light's side, |ns·wi| / |ng·wi|
  const Material* mat;
};
// False when the ray found nothing, or a broken hit (counted in stats.nonFinite), or wi lies in
// the micro-triangle's plane.
bool lightPathHit(const ShadingScene& scene, const RayBatch& rays, size_t cs, ShadeStats& stats, LightPathHit& out);

// The next segment from a hit: the BSDF sampled from the light's side, weighted by the adjoint
// (eta² undone for refraction, the shading-normal correction), Russian roulette on the
// throughput T. Writes the ray into slot cs and returns true if the path goes on.
bool continueLightPath(const ShadingScene& scene, const LightPathHit& hit, const Bsdf& bsdf, uint32_t vertex,
                       const RngKey& key, uint32_t path, size_t cs, Rgb& T, RayBatch& rays, ShadeStats& stats);

}  // namespace rayes
