// The isotropic GGX (Trowbridge-Reitz) microfacet distribution in the local shading frame
// (normal = +z), with Heitz's visible-normal sampling (2018), after pbrt-v4's
// TrowbridgeReitzDistribution. Shared by the rough conductor and the rough dielectric.
//
// alpha is the GGX width (the "roughness" of the scene format), clamped below to kMinAlpha so
// that D stays finite in float; callers treat alpha < kSmoothAlpha as a perfectly smooth
// (delta) surface instead. Every function returns a finite, non-negative value for any unit
// input, including directions in the tangent plane.
#pragma once
#include <algorithm>
#include <cmath>
#include <numbers>
#include "core/vec.h"

namespace rayes {

class Ggx {
 public:
  static constexpr float kSmoothAlpha = 1e-3f;
  static constexpr float kMinAlpha = 1e-4f;
  explicit Ggx(float alpha) : a_(std::max(alpha, kMinAlpha)) {}
  float alpha() const { return a_; }

  // Microfacet normal density (projected-area normalised: ∫ D(m) cos θm dω = 1).
  float D(Vec3 m) const {
    const float c2 = m.z * m.z;
    if (!(c2 > 0)) return 0;
    const float s2 = std::max(0.0f, 1.0f - c2);
    const float a2 = a_ * a_;
    // D = a² / (π (c² a² + s²)²), written without tan θ so grazing m stays finite.
    const float d = c2 * a2 + s2;
    const float r = a2 / (std::numbers::pi_v<float> * d * d);
    return std::isfinite(r) ? r : 0.0f;
  }
  // Smith Λ(w) = (sqrt(1 + a² tan²θ) - 1) / 2.
  float lambda(Vec3 w) const {
    const float c2 = w.z * w.z;
    if (!(c2 > 0)) return std::numeric_limits<float>::infinity();
    const float t2 = std::max(0.0f, 1.0f - c2) / c2;
    return 0.5f * (std::sqrt(1.0f + a_ * a_ * t2) - 1.0f);
  }
  float G1(Vec3 w) const { return 1.0f / (1.0f + lambda(w)); }
  float G(Vec3 wo, Vec3 wi) const { return 1.0f / (1.0f + lambda(wo) + lambda(wi)); }

  // Density of visible normals from w, over solid angle of m: G1(w) max(0, w·m) D(m) / |cos θw|.
  float pdfVisible(Vec3 w, Vec3 m) const {
    const float c = std::fabs(w.z);
    if (!(c > 0)) return 0;
    const float r = G1(w) / c * D(m) * std::fabs(dot(w, m));
    return std::isfinite(r) ? r : 0.0f;
  }

  // A visible normal from w (either side; the result is in the upper hemisphere).
  Vec3 sampleVisible(Vec3 w, float u1, float u2) const {
    Vec3 wh = normalize(Vec3{a_ * w.x, a_ * w.y, w.z});
    if (wh.z < 0) wh = -wh;
    if (wh == Vec3{0, 0, 0}) wh = {0, 0, 1};
    const Vec3 t1 = wh.z < 0.99999f ? normalize(cross(Vec3{0, 0, 1}, wh)) : Vec3{1, 0, 0};
    const Vec3 t2 = cross(wh, t1);
    // Uniform disk (polar), then warp to the visible half of the hemisphere.
    const float r = std::sqrt(u1), phi = 2.0f * std::numbers::pi_v<float> * u2;
    float px = r * std::cos(phi), py = r * std::sin(phi);
    const float h = std::sqrt(std::max(0.0f, 1.0f - px * px));
    const float s = 0.5f * (1.0f + wh.z);
    py = (1.0f - s) * h + s * py;
    const float pz = std::sqrt(std::max(0.0f, 1.0f - px * px - py * py));
    const Vec3 nh = t1 * px + t2 * py + wh * pz;
    const Vec3 m = normalize(Vec3{a_ * nh.x, a_ * nh.y, std::max(1e-6f, nh.z)});
    return m == Vec3{0, 0, 0} ? Vec3{0, 0, 1} : m;
  }

 private:
  float a_;
};

}  // namespace rayes
