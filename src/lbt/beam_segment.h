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
// glossy one; a glossy lobe that crosses its scatterer's horizon (grazing light) gives nothing
// below it, the horizon being the plane of the corner rays' origins. Finite for every input: a
// specular focus (A⊥ → 0) gives 0 and is counted by the caller; a glossy focus takes the limit
// P/A⊥ → g(φ)/r², so E → power·|cos|/(2πσ²r²).
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

// How far a glossy lobe reaches, in σ: the mass beyond one edge's line is Q(4) = 3.2e-5. The
// bins hold a segment only this far out (beamBounds), and the gather takes P = 0 or 1 without
// the edge integrals for a point this far from every edge of the angular triangle, and drops
// what lies beyond it from each edge's integral otherwise (P within 3·Q(4) = 9.5e-5 in all).
// A segment's flux that lands beyond the reach is at most the lobe's mass outside a disc of
// radius 4: e^(-8) = 3.4e-4 (5σ: e^(-12.5) = 3.7e-6); measured, 5σ → 4σ darkened
// lbt-ring-glossy's image by 0.010 % and cut lbt-discoball-glossy's CPU by 25 %
// (bench/history/2026-11.md, "Glossy gathers"). BeamStore's pieces bin wider (kPieceReach): their
// boxes lose more than this, an open bias of theirs.
inline constexpr double kLobeReach = 4;

// The box a segment's gathers can lie in: its corner rays up to t_i, grown by its lobe
// (kLobeReach·σ of angle at the far end).
Box3 beamBounds(const BeamSegment& s);

// The gather; psi receives the light's direction at x (Ψ̄ when nothing arrives).
Rgb beamIrradiance(const BeamSegment& s, Vec3 x, Vec3 n, Vec3& psi);

// Where a segment's gather can be nonzero, as two tests made before the gather's own set-up
// (about 97 % of the gathers a bin offers are 0 on the caustic scenes: bench/history/2026-11.md):
//  - the spread: the flux triangle at axial distance t from the corners' centroid O (along Ψ̄)
//    lies within S(t) of the axis (S: each corner's offset is linear in t, so its length is
//    convex: below the chord between the levels 0 and the farthest end, growing at most V per
//    unit beyond), so a point w from the axis is at least D = w − S(t) outside it; for a glossy
//    segment D must also exceed kLobeReach·σ times the bound on r + ρmax of beamIrradiance's
//    lobe test ((|t| + L)/cos_min + w + S(t));
//  - the cap: beyond the plane of the corner rays' ends by more than kCapSlack·max t_i (the
//    gather's own cap test, with its interpolated t replaced by the largest).
// excludes(x) ⇒ beamIrradiance(s, x, ·) is 0 for a specular segment and carries P ≤ Q(kLobeReach)
// (a lobe mass the gather itself may drop) for a glossy one; a relative margin of 1e-6 covers the
// gather's float flux-plane basis. Computed in double, as the gather is (168 bytes).
struct BeamEnvelope {
  double origin[3] = {0, 0, 0}, axis[3] = {0, 0, 1};
  double spreadStart = 0, spreadEnd = 0, spreadSlope = 0;  // S(0), S(axialEnd), V
  double axialEnd = 0;                    // the farthest corner end's axial distance
  double axialOffset = 0, invCosMin = 1;  // L = max |(o_i − O)·Ψ̄|, 1 / min d_i·Ψ̄
  double axialStart = 0;                  // min (o_i − O)·Ψ̄: before it, x is behind every corner
  double lobeReach = 0;                   // kLobeReach·σ (0: specular)
  double capNormal[3] = {0, 0, 0}, capPoint[3] = {0, 0, 0}, capLimit = -1;  // < 0: no cap plane
  bool never = false;                     // the gather is 0 everywhere (corners not coaxial)
  bool excludes(Vec3 x) const;
};
BeamEnvelope beamEnvelope(const BeamSegment& s);

}  // namespace rayes
