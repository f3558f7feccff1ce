// A dielectric interface (glass, water): reflection and refraction, smooth (delta lobes when
// alpha < Ggx::kSmoothAlpha) or rough (GGX microfacets, Walter et al. 2007, visible-normal
// sampling), after pbrt-v4's DielectricBxDF. eta = n_inside / n_outside; the local +z points
// outside, so wo.z < 0 means the viewer is inside. Total internal reflection reflects all.
// Radiance transport: refracted radiance is scaled by 1/etaRel² (it is compressed into a
// smaller solid angle), so the power-conserving identity is ∫ f cos · etaRel² = 1 for the
// smooth interface (BsdfSample::etaRel tells the caller). Generalised reciprocity:
// f(wo, wi) / n(wo)² = f(wi, wo) / n(wi)². eta = 1 is an invisible interface (passes
// straight through). Conventions: bsdf_common.h.
#pragma once
#include "shading/bsdf_common.h"
#include "shading/fresnel.h"
#include "shading/microfacet.h"

namespace rayes {

struct Dielectric {
  float eta = 1.5f;
  float alpha = 0;

  bool smooth() const { return alpha < Ggx::kSmoothAlpha || eta == 1.0f; }

  Rgb eval(Vec3 wo, Vec3 wi) const {
    float d = 0, p = 0;
    evalPdf(wo, wi, d, p);
    return {d, d, d};
  }
  float pdf(Vec3 wo, Vec3 wi) const {
    float d = 0, p = 0;
    evalPdf(wo, wi, d, p);
    return p;
  }

  bool sample(Vec3 wo, float u1, float u2, float uc, BsdfSample& s) const {
    if (wo.z == 0 || !std::isfinite(wo.z)) return false;
    if (smooth()) {
      const float r = fresnelDielectric(wo.z, eta), t = 1.0f - r;
      s.delta = true;
      if (uc < r) {
        s.wi = mirrorLocal(wo);
        s.pdf = r;
        s.weight = {1, 1, 1};  // (R / |cos|) |cos| / R
        s.etaRel = 1;
        return true;
      }
      float etaRel = 1;
      if (!refract(wo, eta, s.wi, etaRel) || !(t > 0)) return false;
      s.pdf = t;
      const float w = 1.0f / (etaRel * etaRel);  // (T / |cos| / etaRel²) |cos| / T
      s.weight = {w, w, w};
      s.etaRel = etaRel;
      return true;
    }
    const Ggx g(alpha);
    const Vec3 m = g.sampleVisible(wo, u1, u2);
    const float r = fresnelDielectric(dot(wo, m), eta), t = 1.0f - r;
    const float g1 = g.G1(wo);
    s.delta = false;
    if (uc < r) {
      s.wi = reflect(wo, m);
      if (!(s.wi.z * wo.z > 0)) return false;
      s.pdf = g.pdfVisible(wo, m) / (4.0f * std::fabs(dot(wo, m))) * r;
      const float w = g.G(wo, s.wi) / g1;
      s.weight = {w, w, w};
      s.etaRel = 1;
    } else {
      float etaRel = 1;
      if (!refract(wo, m, eta, s.wi, etaRel)) return false;
      if (!(s.wi.z * wo.z < 0)) return false;
      const float denom = sq(dot(s.wi, m) + dot(wo, m) / etaRel);
      if (!(denom > 0)) return false;
      s.pdf = g.pdfVisible(wo, m) * std::fabs(dot(s.wi, m)) / denom * t;
      const float w = g.G(wo, s.wi) / (g1 * etaRel * etaRel);
      s.weight = {w, w, w};
      s.etaRel = etaRel;
    }
    if (!(s.pdf > 0) || !std::isfinite(s.pdf) || !isFinite(s.weight)) return false;
    return true;
  }

  Rgb reflectance() const { return {1, 1, 1}; }
  bool isDelta() const { return smooth(); }
  bool transmits() const { return true; }

 private:
  static float sq(float x) { return x * x; }

  // f and pdf of the rough interface together (they share the half vector).
  void evalPdf(Vec3 wo, Vec3 wi, float& f, float& pdf) const {
    f = pdf = 0;
    if (smooth()) return;
    const float co = wo.z, ci = wi.z;
    if (co == 0 || ci == 0) return;
    const bool reflectPair = co * ci > 0;
    const float etaRel = reflectPair ? 1.0f : (co > 0 ? eta : 1.0f / eta);
    Vec3 m = wi * etaRel + wo;
    if (!(dot(m, m) > 0)) return;
    m = normalize(m);
    if (m == Vec3{}) return;
    if (m.z < 0) m = -m;
    // Microfacets seen from behind by either direction contribute nothing.
    if (dot(m, wi) * ci < 0 || dot(m, wo) * co < 0) return;
    const Ggx g(alpha);
    const float r = fresnelDielectric(dot(wo, m), eta), t = 1.0f - r;
    if (reflectPair) {
      f = g.D(m) * g.G(wo, wi) * r / std::fabs(4.0f * ci * co);
      pdf = g.pdfVisible(wo, m) / (4.0f * std::fabs(dot(wo, m))) * r;
    } else {
      const float denom = sq(dot(wi, m) + dot(wo, m) / etaRel);
      if (!(denom > 0)) return;
      f = g.D(m) * t * g.G(wo, wi) * std::fabs(dot(wi, m) * dot(wo, m) / (ci * co * denom)) / (etaRel * etaRel);
      pdf = g.pdfVisible(wo, m) * std::fabs(dot(wi, m)) / denom * t;
    }
    if (!std::isfinite(f) || !std::isfinite(pdf)) f = pdf = 0;
  }
};

}  // namespace rayes
