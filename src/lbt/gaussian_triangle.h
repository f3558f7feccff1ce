// The glossy gather's footprint integral (docs/design.md, "Light beam tracing"): the mass of
// an isotropic 2D Gaussian lobe of width σ, centred at the origin of the flux plane, over a
// triangle Ω_ABC:
//
//   P = ∬_ABC exp(-|φ|² / 2σ²) / (2πσ²) dφ.
//
// By the divergence theorem with the radial field F = CDF(r)/(2πr)·r̂, CDF(r) = 1 - e^(-r²/2)
// (the exact Gaussian radial CDF; the thesis's raised cosine loses about 7 % of the flux), P
// is a sum over the three edges. With s = |d|·tan θ along an edge at signed distance d from
// the origin, an edge from s0 to s1 contributes
//
//   sign(d)·[G(|d|, s1/|d|) - G(|d|, s0/|d|)],   G(h, a) = atan(a)/2π - T(h, a),
//
// where T is Owen's T function. G is bounded by 1/4, so nothing diverges: an origin on an
// edge or a corner (d = 0) contributes 0 from that edge, collinear corners give P = 0, an
// inverted triangle (past a focus) gives the same P as its mirror image, and σ → 0 tends to
// the specular indicator (1 inside, 1/2 on an edge, 0 outside).
//
// G is evaluated directly, never as a difference with atan: for |a| <= 1 by Owen's series
// (T1 in Patefield & Tandy 2000), whose coefficients depend on h alone and so serve both ends
// of an edge, and for |a| > 1 by Owen's reflection onto (|a|h, 1/|a|). No exp per quadrature
// node, no atan for an edge within 9 of the centre whose ends are both within 45° of its foot.
//
// Accuracy: G to an absolute 1e-14, so P to ~1e-13, far below what a float image can hold
// (one ulp of 1.0f is 1.2e-7). The gather's cheap mode (a lobe cut at reach < 9) trades that
// for 3·Q(reach) and takes a 7-point cubature for triangles small against σ (error at most
// Q(reach)·A/2π: the bound is derived in the .cpp). Pure functions of their arguments,
// thread-safe, O(1).
#pragma once

namespace rayes {

struct FlatPoint {
  double x, y;
};

// G(h, a) = atan(a)/2π - T(h, a) = (1/2π) ∫_0^atan(a) (1 - e^(-h²/2cos²θ)) dθ, T being Owen's
// T function: the part of the angle an edge at distance h subtends from its foot to a·h along
// it that the unit lobe's mass covers. Any real h and a (±inf too); odd in a, even in h,
// 0 at h = 0, exactly atan(a)/2π for |h| >= 9 (T < Q(9)/2 < 6e-20 there). Absolute error
// below 1e-14.
double owenTComplement(double h, double a);

// G(h, a1) - G(h, a0): one edge's term, with the work that depends on h alone done once.
// `cut` (at most 9, the default) drops what lies that far from the centre: for |h| >= cut the
// term is the angle (atan(a1) - atan(a0))/2π, and an end with |a·h| >= cut loses the parts
// of Owen's reflection at |a|h. Either changes the term by at most Q(cut) (T is odd and
// monotone in a and below Q/2; each end's dropped parts lie within ½Q(|a|h)).
double owenTComplementDifference(double h, double a0, double a1, double cut = 9);

// The standard normal upper tail Q(x) = ½·erfc(x/√2): the mass of the half-plane at signed
// distance x from the lobe's centre.
double normalTail(double x);

// P for σ = 1. Either orientation; any finite corners (huge ones give 0 or 1).
double gaussianTriangleMass(FlatPoint a, FlatPoint b, FlatPoint c);

// The same with the lobe cut at `reach` (σ = 1): a centre at least `reach` from every edge's
// line gets 1 (inside) or 0 (outside) without the edge integrals, and otherwise each edge's
// term is cut at `reach` (owenTComplementDifference); the error is at most 3·Q(reach)
// (Q(4) = 3.2e-5, Q(5) = 2.9e-7). For reach < 9, a triangle whose corners lie within R of its
// centroid with R⁶ <= 24·Q(reach) (R <= 0.302 at reach 4, 0.138 at 5) is integrated by a
// 7-point cubature instead, within Q(reach)·A/2π (A its area): seven exps for three edges'
// series. reach ≥ 9 is gaussianTriangleMass, which never takes the cubature.
double gaussianTriangleMassWithin(FlatPoint a, FlatPoint b, FlatPoint c, double reach);

// P for a lobe of width sigma > 0: P(φ, σ) = P(φ/σ, 1), cut at reach·σ as above (the default:
// exact to 1e-13). sigma = 0 is the specular limit.
double gaussianTriangleMass(FlatPoint a, FlatPoint b, FlatPoint c, double sigma, double reach = 9);

}  // namespace rayes
