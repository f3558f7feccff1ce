// Coated plastic: a smooth dielectric coating (index eta over air) on a Lambertian base of
// albedo ρ, with the internal reflections at the coating summed in closed form (the
// "smooth plastic" of Weidlich-Wilkie / Mitsuba):
//   specular (delta) lobe: F(θo) in the mirror direction;
//   diffuse lobe: f = ρ (1 - F(θo)) (1 - F(θi)) / (π eta² (1 - ρ Fdr_in)),
// Fdr_in the coating's internal diffuse reflectance, 1 - (1 - Fdr_out) / eta² (by etendue,
// Fdr_out = the cosine-weighted average of F from outside). Hence ∫ f cos + F(θo) =
// F + (1 - F) ρ (1 - Fdr_in) / (1 - ρ Fdr_in) ≤ 1, exactly 1 at ρ = 1 (lossless).
// Reciprocal (the diffuse lobe is symmetric). Sampling: the specular lobe with probability
// F / (F + (1 - F) avg(ρ)), else cosine. Build with Plastic::make (computes Fdr_in once per
// material). Conventions: bsdf_common.h.
#pragma once
#include "shading/bsdf_common.h"
#include "shading/fresnel.h"
#include "shading/sampling.h"

namespace rayes {

struct Plastic {
  Rgb albedo;
  float eta = 1.5f;
  float fdrIn = 0;  // internal diffuse Fresnel reflectance of the coating

  static float internalDiffuseReflectance(float eta) {
    return 1.0f - (1.0f - diffuseFresnelOutside(eta)) / (eta * eta);
  }
  static Plastic make(Rgb albedo, float eta) { return {albedo, eta, internalDiffuseReflectance(eta)}; }

  Rgb eval(Vec3 wo, Vec3 wi) const {
    if (!(wo.z > 0) || !(wi.z > 0)) return {};
    const float s = (1.0f - fresnelDielectric(wo.z, eta)) * (1.0f - fresnelDielectric(wi.z, eta)) /
                    (kPi * eta * eta);
    return {diffuse(albedo.x, s), diffuse(albedo.y, s), diffuse(albedo.z, s)};
  }
  float pdf(Vec3 wo, Vec3 wi) const {
    if (!(wo.z > 0) || !(wi.z > 0)) return 0;
    return (1.0f - specularProbability(wo)) * wi.z * kInvPi;
  }
  bool sample(Vec3 wo, float u1, float u2, float uc, BsdfSample& s) const {
    if (!(wo.z > 0)) return false;
    const float ps = specularProbability(wo);
    s.etaRel = 1;
    if (uc < ps) {
      s.wi = mirrorLocal(wo);
      s.pdf = ps;
      const float w = fresnelDielectric(wo.z, eta) / ps;
      s.weight = {w, w, w};
      s.delta = true;
      return true;
    }
    s.wi = sampleCosineHemisphere(u1, u2);
    if (!(s.wi.z > 0)) return false;
    s.pdf = (1.0f - ps) * s.wi.z * kInvPi;
    if (!(s.pdf > 0)) return false;
    s.weight = eval(wo, s.wi) * (s.wi.z / s.pdf);
    s.delta = false;
    return isFinite(s.weight);
  }
  Rgb reflectance() const { return albedo; }
  bool isDelta() const { return false; }
  bool transmits() const { return false; }

 private:
  float diffuse(float rho, float s) const {
    const float d = 1.0f - rho * fdrIn;
    return d > 0 ? rho * s / d : 0.0f;
  }
  float specularProbability(Vec3 wo) const {
    const float f = fresnelDielectric(wo.z, eta);
    const float total = f + (1.0f - f) * average(albedo);
    return total > 0 ? f / total : 0.0f;
  }
};

}  // namespace rayes
