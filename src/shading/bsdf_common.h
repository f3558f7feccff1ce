// What every BSDF shares: the local shading frame (normal = +z) and the result of sampling.
//
// Conventions for every model in src/shading (lambert.h, conductor.h, dielectric.h, plastic.h,
// phong.h, gaussian_lobe.h): directions are unit vectors in the local frame pointing away from
// the surface; wo is toward the viewer (where radiance goes), wi toward the light. eval(wo, wi)
// is the BSDF value f for light arriving along wi and leaving along wo (radiance transport);
// pdf(wo, wi) is the solid-angle density with which sample(wo, ...) returns wi, counting only
// the non-delta lobes; sample() returns false when it produces no direction (the sample then
// carries zero weight). Reflection-only models require wo.z > 0 (the caller turns the frame
// to the viewer's side) and return zero otherwise; the dielectric uses the frame as given
// (+z = outside).
#pragma once
#include <cmath>
#include <numbers>
#include "core/vec.h"
#include "shading/sampling.h"

namespace rayes {

struct BsdfSample {
  Vec3 wi;
  Rgb weight;          // f |cos θi| / pdf, or the lobe's weight for a delta lobe
  float pdf = 0;       // solid-angle density of wi (the delta lobe's choice probability if delta)
  bool delta = false;  // wi came from a delta lobe: eval() and pdf() do not contain it
  float etaRel = 1;    // n_transmitted / n_incident when wi was refracted, 1 for reflection
};

inline constexpr float kInvPi = std::numbers::inv_pi_v<float>;
inline constexpr float kPi = std::numbers::pi_v<float>;

inline Vec3 mirrorLocal(Vec3 w) { return {-w.x, -w.y, w.z}; }
inline float average(Rgb c) { return (c.x + c.y + c.z) * (1.0f / 3.0f); }

// Angle between two unit vectors, accurate near 0 and π (atan2 of |cross| and dot, never acos).
inline float angleBetween(Vec3 a, Vec3 b) { return std::atan2(length(cross(a, b)), dot(a, b)); }

}  // namespace rayes
