// A rough conductor: GGX microfacets (microfacet.h) with the complex Fresnel term of a metal
// (fresnel.h), visible-normal sampling; perfectly smooth (a delta mirror) when
// alpha < Ggx::kSmoothAlpha. f = D G F / (4 cos θo cos θi).
// Reciprocal. ∫ f cos ≤ F ≤ 1; single scattering loses energy as alpha grows (no
// multiple-scattering compensation). Sampled weight F G / G1(wo). Conventions: bsdf_common.h.
#pragma once
#include "shading/bsdf_common.h"
#include "shading/fresnel.h"
#include "shading/microfacet.h"

namespace rayes {

struct Conductor {
  Rgb eta{0.2f, 0.92f, 1.1f}, k{3.9f, 2.45f, 2.14f};  // copper by default
  float alpha = 0;

  bool smooth() const { return alpha < Ggx::kSmoothAlpha; }
  Rgb eval(Vec3 wo, Vec3 wi) const {
    if (smooth() || !(wo.z > 0) || !(wi.z > 0)) return {};
    const Vec3 m = normalize(wo + wi);
    if (m == Vec3{}) return {};
    const Ggx g(alpha);
    const float s = g.D(m) * g.G(wo, wi) / (4.0f * wo.z * wi.z);
    if (!std::isfinite(s)) return {};
    return fresnelConductor(dot(wo, m), eta, k) * s;
  }
  float pdf(Vec3 wo, Vec3 wi) const {
    if (smooth() || !(wo.z > 0) || !(wi.z > 0)) return 0;
    const Vec3 m = normalize(wo + wi);
    const float c = dot(wo, m);
    if (m == Vec3{} || !(c > 0)) return 0;
    const float p = Ggx(alpha).pdfVisible(wo, m) / (4.0f * c);
    return std::isfinite(p) ? p : 0.0f;
  }
  bool sample(Vec3 wo, float u1, float u2, float, BsdfSample& s) const {
    if (!(wo.z > 0)) return false;
    s.etaRel = 1;
    if (smooth()) {
      s.wi = mirrorLocal(wo);
      s.weight = fresnelConductor(wo.z, eta, k);
      s.pdf = 1;
      s.delta = true;
      return true;
    }
    const Ggx g(alpha);
    const Vec3 m = g.sampleVisible(wo, u1, u2);
    const float c = dot(wo, m);
    if (!(c > 0)) return false;
    s.wi = reflect(wo, m);
    if (!(s.wi.z > 0)) return false;
    s.pdf = g.pdfVisible(wo, m) / (4.0f * c);
    if (!(s.pdf > 0) || !std::isfinite(s.pdf)) return false;
    s.weight = fresnelConductor(c, eta, k) * (g.G(wo, s.wi) / g.G1(wo));
    s.delta = false;
    return true;
  }
  Rgb reflectance() const { return fresnelConductor(1.0f, eta, k); }
  bool isDelta() const { return smooth(); }
  bool transmits() const { return false; }
};

}  // namespace rayes
