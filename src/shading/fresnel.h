// Fresnel reflectance for unpolarised light: a dielectric interface (real relative index of
// refraction) and a conductor (complex index eta + i k), after pbrt-v4 (FrDielectric,
// FrComplex). Both clamp their cosine to [-1, 1] and return a value in [0, 1] for every finite
// input: no division by zero at grazing angles or eta = 1, total internal reflection returns 1.
#pragma once
#include <algorithm>
#include <cmath>
#include <complex>
#include "core/vec.h"

namespace rayes {

// cosThetaI: cosine between the incident direction and the normal on the side of the outside
// medium; negative means the direction is inside. eta = n_inside / n_outside (> 0).
inline float fresnelDielectric(float cosThetaI, float eta) {
  cosThetaI = std::clamp(cosThetaI, -1.0f, 1.0f);
  if (cosThetaI < 0) { eta = 1.0f / eta; cosThetaI = -cosThetaI; }
  const float sin2I = std::max(0.0f, 1.0f - cosThetaI * cosThetaI);
  const float sin2T = sin2I / (eta * eta);
  if (sin2T >= 1.0f) return 1.0f;  // total internal reflection
  const float cosT = std::sqrt(std::max(0.0f, 1.0f - sin2T));
  const float parl = (eta * cosThetaI - cosT) / (eta * cosThetaI + cosT);
  const float perp = (cosThetaI - eta * cosT) / (cosThetaI + eta * cosT);
  const float r = 0.5f * (parl * parl + perp * perp);
  // Both denominators are > 0 unless cosThetaI = cosT = 0 (grazing at eta = 1): total reflection.
  return std::isfinite(r) ? std::min(r, 1.0f) : 1.0f;
}

// The same for s and p polarisation separately (the glass-slab test sums the series per
// polarisation). Returns {R_s, R_p}.
inline void fresnelDielectricPolarised(float cosThetaI, float eta, float& rs, float& rp) {
  cosThetaI = std::clamp(cosThetaI, -1.0f, 1.0f);
  if (cosThetaI < 0) { eta = 1.0f / eta; cosThetaI = -cosThetaI; }
  const float sin2T = std::max(0.0f, 1.0f - cosThetaI * cosThetaI) / (eta * eta);
  if (sin2T >= 1.0f) { rs = rp = 1.0f; return; }
  const float cosT = std::sqrt(std::max(0.0f, 1.0f - sin2T));
  const float parl = (eta * cosThetaI - cosT) / (eta * cosThetaI + cosT);
  const float perp = (cosThetaI - eta * cosT) / (cosThetaI + eta * cosT);
  rp = std::isfinite(parl) ? parl * parl : 1.0f;
  rs = std::isfinite(perp) ? perp * perp : 1.0f;
}

// Conductor: cosThetaI >= 0 (clamped), index eta + i k (eta > 0, k >= 0), one channel.
inline float fresnelConductor(float cosThetaI, float eta, float k) {
  using C = std::complex<float>;
  cosThetaI = std::clamp(cosThetaI, 0.0f, 1.0f);
  const C n(eta, k);
  const float sin2I = 1.0f - cosThetaI * cosThetaI;
  const C sin2T = C(sin2I) / (n * n);
  const C cosT = std::sqrt(C(1.0f) - sin2T);
  const C parl = (n * cosThetaI - cosT) / (n * cosThetaI + cosT);
  const C perp = (C(cosThetaI) - n * cosT) / (C(cosThetaI) + n * cosT);
  const float r = 0.5f * (std::norm(parl) + std::norm(perp));
  return std::isfinite(r) ? std::clamp(r, 0.0f, 1.0f) : 1.0f;
}

inline Rgb fresnelConductor(float cosThetaI, Rgb eta, Rgb k) {
  return {fresnelConductor(cosThetaI, eta.x, k.x), fresnelConductor(cosThetaI, eta.y, k.y),
          fresnelConductor(cosThetaI, eta.z, k.z)};
}

// Refraction of w (pointing away from the surface, on either side) about the normal n = +z
// flipped to w's side; eta = n_inside / n_outside. Returns false on total internal reflection.
// etaRel receives n_transmitted / n_incident.
inline bool refract(Vec3 w, float eta, Vec3& wt, float& etaRel) {
  float cosI = w.z;
  Vec3 n{0, 0, 1};
  if (cosI < 0) { eta = 1.0f / eta; cosI = -cosI; n = {0, 0, -1}; }
  const float sin2I = std::max(0.0f, 1.0f - cosI * cosI);
  const float sin2T = sin2I / (eta * eta);
  if (sin2T >= 1.0f) return false;
  const float cosT = std::sqrt(std::max(0.0f, 1.0f - sin2T));
  wt = -w / eta + n * (cosI / eta - cosT);
  etaRel = eta;
  return true;
}

// The same about an arbitrary unit normal m (a microfacet normal); w and m on the same side
// decides the outside.
inline bool refract(Vec3 w, Vec3 m, float eta, Vec3& wt, float& etaRel) {
  float cosI = dot(w, m);
  if (cosI < 0) { eta = 1.0f / eta; cosI = -cosI; m = -m; }
  const float sin2I = std::max(0.0f, 1.0f - cosI * cosI);
  const float sin2T = sin2I / (eta * eta);
  if (sin2T >= 1.0f) return false;
  const float cosT = std::sqrt(std::max(0.0f, 1.0f - sin2T));
  wt = -w / eta + m * (cosI / eta - cosT);
  etaRel = eta;
  return true;
}

inline Vec3 reflect(Vec3 w, Vec3 m) { return -w + m * (2.0f * dot(w, m)); }

// Hemispherical average of the dielectric Fresnel reflectance seen from the outside,
// 2 ∫ F(μ) μ dμ over μ in [0, 1] (composite Simpson, 2048 intervals; F is smooth from the
// outside). Used by the coated plastic, once per material.
inline float diffuseFresnelOutside(float eta) {
  const int n = 2048;
  double s = 0;
  for (int i = 0; i <= n; ++i) {
    const double mu = double(i) / n;
    const double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
    s += w * fresnelDielectric(float(mu), eta) * mu;
  }
  return float(2.0 * s / (3.0 * n));
}

}  // namespace rayes
