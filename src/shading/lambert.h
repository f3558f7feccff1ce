// Lambertian reflection: f = albedo / π, cosine-weighted sampling (weight = albedo exactly).
// Reciprocal; ∫ f cos = albedo, so lossless at albedo 1. Conventions: bsdf_common.h.
#pragma once
#include "shading/bsdf_common.h"
#include "shading/sampling.h"

namespace rayes {

struct Lambert {
  Rgb albedo;

  Rgb eval(Vec3 wo, Vec3 wi) const { return wo.z > 0 && wi.z > 0 ? albedo * kInvPi : Rgb{}; }
  float pdf(Vec3 wo, Vec3 wi) const { return wo.z > 0 && wi.z > 0 ? wi.z * kInvPi : 0.0f; }
  bool sample(Vec3 wo, float u1, float u2, float, BsdfSample& s) const {
    if (!(wo.z > 0)) return false;
    s.wi = sampleCosineHemisphere(u1, u2);
    if (!(s.wi.z > 0)) return false;
    s.pdf = s.wi.z * kInvPi;
    s.weight = albedo;
    s.delta = false;
    s.etaRel = 1;
    return true;
  }
  Rgb reflectance() const { return albedo; }
  bool isDelta() const { return false; }
  bool transmits() const { return false; }
};

}  // namespace rayes
