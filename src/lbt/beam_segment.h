// A beam segment (docs/design.md, "Light beam tracing"): the straight piece of a light beam
// between two interactions, three corner rays o_i + s d_i (d_i unit) from the scatterer (or the
// light) to where each corner ray was stopped (s ≤ t_i), carrying the flux of its generator
// triangle times the reflectances of its chain (power = ρ·Φ) and the combined glossy width
// σ = sqrt(Σ σ_k²) (0: specular).
//
// beamIrradiance() is the caustic gather of one segment at a receiver point x with normal n:
//   E = power / A⊥ · |cos(n, Ψ)| · P,
// A⊥ the area of the triangle where the corner rays cross the flux plane through x (the plane
// perpendicular to the central direction Ψ̄), Ψ the corner directions blended at x's
// barycentrics in that triangle, P = 1 inside / 0 outside for a specular segment and the
// Gaussian lobe's mass over the triangle of angular offsets (lbt/gaussian_triangle.h) for a
// glossy one. Finite for every input: a specular focus (A⊥ → 0) gives 0 and is counted by the
// caller; a glossy focus takes the limit P/A⊥ → g(φ)/r², so E → power·|cos|/(2πσ²r²).
#pragma once
#include "core/box.h"
#include "core/vec.h"

namespace rayes {

struct BeamSegment {
  Vec3 o[3], d[3];  // corner rays: origins and unit directions
  float t[3];       // where each corner ray ends (its hit, or the scene's far bound)
  Rgb power;        // ρ·Φ in W
  float sigma = 0;  // combined lobe width in radians, 0 for specular
  uint8_t scatterings = 1;  // specular/glossy bounces before it: it lands at light-path vertex scatterings + 1
};

// Corner rays closer to each other's direction than this are "roughly coaxial" (cos of 60°);
// a segment whose corners diverge more is not a beam (the tracer does not emit it).
inline constexpr float kCoaxialCos = 0.5f;

// A gather point may lie this far (relative to the segment's length) beyond the plane of the
// corner rays' ends: the ends lie on the receiver, and so does x, but a curved receiver bulges
// out of that plane.
inline constexpr float kCapSlack = 0.02f;

// How far a glossy lobe reaches, in σ: the mass beyond one edge's line is Q(5) = 2.9e-7. The
// bins hold a segment only this far out (beamBounds), and the gather takes P = 0 or 1 without
// the edge integrals for a point this far from every edge of the angular triangle, and drops
// what lies beyond it from each edge's integral otherwise (P within 3·Q(5) in all).
inline constexpr double kLobeReach = 5;

// The box a segment's gathers can lie in: its corner rays up to t_i, grown by its lobe
// (kLobeReach·σ of angle at the far end).
Box3 beamBounds(const BeamSegment& s);

// The gather; psi receives the light's direction at x (Ψ̄ when nothing arrives).
Rgb beamIrradiance(const BeamSegment& s, Vec3 x, Vec3 n, Vec3& psi);

}  // namespace rayes
