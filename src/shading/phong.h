// The modified Phong BRDF of Lafortune and Willems (1994), energy-normalised:
//   f = kd / π + ks (n + 2) / (2π) max(0, cos α)^n,  α = angle between wi and the mirror of wo.
// Reciprocal; ∫ f cos ≤ kd + ks (equality at normal incidence), so the scene reader requires
// kd + ks ≤ 1 per channel. Sampling mixes the cosine lobe (probability avg(kd) / (avg(kd) +
// avg(ks))) and the cos^n lobe about the mirror direction; a lobe sample below the horizon is
// no sample (sample() returns false, pdf() integrates to less than 1 by exactly that mass).
// The weight is f cos / pdf of the mixture. Conventions: bsdf_common.h.
#pragma once
#include "shading/bsdf_common.h"
#include "shading/sampling.h"

namespace rayes {

struct Phong {
  Rgb kd, ks;
  float exponent = 20;

  Rgb eval(Vec3 wo, Vec3 wi) const {
    if (!(wo.z > 0) || !(wi.z > 0)) return {};
    return kd * kInvPi + ks * ((exponent + 2) * 0.5f * kInvPi * lobe(wo, wi));
  }
  float pdf(Vec3 wo, Vec3 wi) const {
    if (!(wo.z > 0) || !(wi.z > 0)) return 0;
    const float pd = diffuseProbability();
    return pd * wi.z * kInvPi + (1 - pd) * (exponent + 1) * 0.5f * kInvPi * lobe(wo, wi);
  }
  bool sample(Vec3 wo, float u1, float u2, float uc, BsdfSample& s) const {
    if (!(wo.z > 0) || (isBlack(kd) && isBlack(ks))) return false;
    if (uc < diffuseProbability()) {
      s.wi = sampleCosineHemisphere(u1, u2);
    } else {
      const float cosA = std::pow(u1, 1.0f / (exponent + 1));
      const float sinA = std::sqrt(std::max(0.0f, 1.0f - cosA * cosA));
      s.wi = aroundAxis(mirrorLocal(wo), cosA, sinA, 2 * kPi * u2);
    }
    if (!(s.wi.z > 0)) return false;
    s.pdf = pdf(wo, s.wi);
    if (!(s.pdf > 0) || !std::isfinite(s.pdf)) return false;
    s.weight = eval(wo, s.wi) * (s.wi.z / s.pdf);
    s.delta = false;
    s.etaRel = 1;
    return isFinite(s.weight);
  }
  Rgb reflectance() const { return kd + ks; }
  bool isDelta() const { return false; }
  bool transmits() const { return false; }

 private:
  float diffuseProbability() const {
    const float d = average(kd), s = average(ks);
    return d + s > 0 ? d / (d + s) : 0.0f;
  }
  float lobe(Vec3 wo, Vec3 wi) const {
    const float c = dot(mirrorLocal(wo), wi);
    return c > 0 ? std::pow(std::min(c, 1.0f), exponent) : 0.0f;
  }
};

}  // namespace rayes
