// The glossy BRDF of light beam tracing (docs/design.md, "Light beam tracing"; Duvenhage ch. 8-11):
//   f(wo, wi) = ρs exp(-φ² / 2σ²) / (2π σ² cos θo),  φ = angle between wi and the mirror of wo
// (symmetric: also the angle between wo and the mirror of wi), wi toward the light, wo toward
// the viewer. Read from the light: light arriving along wi leaves with its reflected flux
// spread as ρs times a Gaussian in the angle from the mirror direction, normalised on the
// tangent plane (dΦo/dωo = ρs G(φ) Φi / 2πσ²), which is what a glossy beam carries (src/lbt).
// So the flux it reflects, ∫ f cos θo dωo = ρs ∫ exp(-φ²/2σ²) dωo / (2πσ²) ≤ ρs (sin φ ≤ φ, and
// the lobe below the horizon is lost), is never above ρs for any incidence: the physical bound.
// The other reading (cos θi in the denominator) reflects up to several times ρs at grazing
// incidence and disagrees with the beams by cos θo / cos θi (docs/design.md, "The glossy lobe's
// reading"). Not reciprocal: f(wo, wi) / f(wi, wo) = cos θi / cos θo (tested). Tends to the
// mirror as σ → 0: below kSmoothSigma it is a delta mirror of weight ρs.
// Sampling (sample: wi given wo; sampleAdjoint: the light's next direction given where it came
// from): φ from the Rayleigh distribution truncated to [0, π], azimuth uniform about the mirror
// direction: pdf = φ exp(-φ²/2σ²) / (2π σ² sin φ (1 - exp(-π²/2σ²))). The adjoint's weight,
// f(out, in) cos θout / pdf = ρs (sin φ / φ)(1 - exp(-π²/2σ²)), needs no cosine; the camera
// side's, f cos θi / pdf, is that times cos θi / cos θo. cos θo below kMinCos gives f = 0 (the
// 1/cos pole is integrable; its contribution there is below float resolution).
// Conventions: bsdf_common.h.
#pragma once
#include "shading/bsdf_common.h"

namespace rayes {

struct GaussianLobe {
  static constexpr float kSmoothSigma = 1e-3f;
  static constexpr float kMinCos = 1e-7f;
  Rgb rho{1, 1, 1};
  float sigma = 0.1f;  // radians

  bool smooth() const { return sigma < kSmoothSigma; }
  Rgb eval(Vec3 wo, Vec3 wi) const {
    if (smooth() || !(wo.z > kMinCos) || !(wi.z > 0)) return {};
    const float phi = angleBetween(wi, mirrorLocal(wo));
    const float f = std::exp(-phi * phi / (2 * sigma * sigma)) / (2 * kPi * sigma * sigma * wo.z);
    return std::isfinite(f) ? rho * f : Rgb{};
  }
  float pdf(Vec3 wo, Vec3 wi) const {
    if (smooth() || !(wo.z > 0) || !(wi.z > 0)) return 0;
    return pdfOfAngle(angleBetween(wi, mirrorLocal(wo)));
  }
  // The camera side: wi given wo, weight f cos θi / pdf.
  bool sample(Vec3 wo, float u1, float u2, float, BsdfSample& s) const {
    if (!(wo.z > 0) || !sampleAbout(wo, u1, u2, s)) return false;
    if (s.delta) return true;
    if (!(wo.z > kMinCos)) return false;   // f = 0 there (eval)
    s.weight = s.weight * (s.wi.z / wo.z);  // the flux weight times cos θi / cos θo: at most 1e7 ρs
    return true;
  }
  // The light side (the adjoint, for paths traced from the lights): light arriving along
  // `in` (toward where it came from) leaves along s.wi, weight f(s.wi, in) cos θ(s.wi) / pdf.
  bool sampleAdjoint(Vec3 in, float u1, float u2, float, BsdfSample& s) const {
    if (!(in.z > 0)) return false;
    return sampleAbout(in, u1, u2, s);
  }
  Rgb reflectance() const { return rho; }
  bool isDelta() const { return smooth(); }
  bool transmits() const { return false; }

 private:
  // A direction about the mirror of w with the lobe's flux weight ρs (sin φ / φ)(1 - tail):
  // the Gaussian normalised on the tangent plane over the sampling density.
  bool sampleAbout(Vec3 w, float u1, float u2, BsdfSample& s) const {
    s.etaRel = 1;
    if (smooth()) {
      s.wi = mirrorLocal(w);
      s.weight = rho;
      s.pdf = 1;
      s.delta = true;
      return true;
    }
    const float tail = truncation();
    // Inverse CDF of the truncated Rayleigh distribution; log1p keeps small u accurate.
    const float phi = std::min(kPi, sigma * std::sqrt(std::max(0.0f, -2.0f * std::log1p(-u1 * (1 - tail)))));
    const float sinPhi = std::sin(phi);
    s.wi = aroundAxis(mirrorLocal(w), std::cos(phi), sinPhi, 2 * kPi * u2);
    if (!(s.wi.z > kMinCos)) return false;
    s.pdf = pdfOfAngle(phi);
    if (!(s.pdf > 0) || !std::isfinite(s.pdf)) return false;
    s.weight = rho * (sincRatio(phi) * (1 - tail));
    s.delta = false;
    return true;
  }
  float truncation() const { return std::exp(-kPi * kPi / (2 * sigma * sigma)); }
  // sin φ / φ, 1 at φ = 0.
  static float sincRatio(float phi) { return phi < 1e-4f ? 1.0f - phi * phi / 6 : std::sin(phi) / phi; }
  float pdfOfAngle(float phi) const {
    const float s = sincRatio(phi);
    if (!(s > 0)) return 0;  // φ = π: the antipode of the mirror direction, measure zero
    const float p = std::exp(-phi * phi / (2 * sigma * sigma)) / (2 * kPi * sigma * sigma * s * (1 - truncation()));
    return std::isfinite(p) ? p : 0.0f;
  }
};

}  // namespace rayes
