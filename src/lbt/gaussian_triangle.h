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
// Pure functions of their arguments, thread-safe, O(1): two Owen's T evaluations per edge,
// each a fixed 20-point Gauss-Legendre rule (written by hand: no library here has Owen's T).
#pragma once

namespace rayes {

struct FlatPoint {
  double x, y;
};

// Owen's T function T(h, a) = (1/2π) ∫_0^a exp(-h²(1+x²)/2) / (1+x²) dx, for any real h and a.
// Absolute error below 1e-14.
double owenT(double h, double a);

// The standard normal upper tail Q(x) = ½·erfc(x/√2): the mass of the half-plane at signed
// distance x from the lobe's centre.
double normalTail(double x);

// P for σ = 1. Either orientation; any finite corners (huge ones give 0 or 1).
double gaussianTriangleMass(FlatPoint a, FlatPoint b, FlatPoint c);

// The same with the lobe cut at `reach` (σ = 1): a centre at least `reach` from every edge's
// line gets 1 (inside) or 0 (outside) without the edge integrals; the error is at most
// 3·Q(reach) (Q(5) = 2.9e-7). reach ≥ 9 is gaussianTriangleMass.
double gaussianTriangleMassWithin(FlatPoint a, FlatPoint b, FlatPoint c, double reach);

// P for a lobe of width sigma > 0: P(φ, σ) = P(φ/σ, 1), cut at reach·σ as above (the default:
// exact to 1e-14). sigma = 0 is the specular limit.
double gaussianTriangleMass(FlatPoint a, FlatPoint b, FlatPoint c, double sigma, double reach = 9);

}  // namespace rayes
