// How every method spawns rays from the scene: the two ray slots of a path, the offset of a
// ray leaving a hit, and the cone a bounce gives it. The path tracer, the light paths of the
// light tracer and of photon mapping, and the beams' corner rays all use these, so a ray
// leaves a surface the same way whichever method made it. Pure functions; thread-safe.
#pragma once
#include <cstdint>
#include "core/vec.h"

namespace rayes {

// Ray slots per path of every method: slot 2k is path k's closest-hit ray (camera,
// continuation or light path), 2k+1 its shadow ray (next-event estimation, or the light
// tracer's connection to the camera).
inline constexpr uint32_t kRaysPerPath = 2;

// Cone spread given to rays leaving a diffuse surface (radians per unit distance). A
// Lambertian lobe spreads rays over the hemisphere, so its rays want coarse geometry; the
// constant is the footprint of one of ~64 directions covering the cosine lobe (pi / 64 sr).
inline constexpr float kDiffuseSpread = 0.22f;

// The spread of a ray leaving a bounce: a narrower lobe gives a narrower cone, sqrt(1 / pdf)
// of the sampled direction (the angle of the solid angle it stands for), never wider than
// kDiffuseSpread nor narrower than the incoming one; a delta bounce keeps the incoming spread.
// Finite for any pdf (0 or infinite included).
float spreadAfterBounce(float incoming, float pdf, bool delta);

// How far a secondary ray's origin is pushed off a hit p at `level` on a leaf of longest side
// `side` (along the geometric normal, to the side the ray leaves), found by a ray from `from`
// (p itself for a point evaluated on the surface): the patch's dicing-error bound at that
// level, C / 4^level (zero for planar patches), plus the rounding error of the hit point,
// gamma(32) (|p| + |from| + side). The derivation is at the definition and in docs/design.md,
// "Secondary-ray offsets". Finite and positive for any input.
float originOffset(float side, float errorCoefficient, int level, Vec3 p, Vec3 from);

}  // namespace rayes
