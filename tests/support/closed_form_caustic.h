// scenes/caustic-closed-form.json: a caustic with a closed form, for checking caustic methods
// against it (not against each other). A point light of intensity I = 10 W/sr at P, a tilted
// rectangular mirror of reflectance ρ = 0.9 (glossy, σ = 0: a perfect mirror) below it, a
// diffuse ceiling of albedo 0.5 at z = 2 facing down. The camera looks straight up from between
// mirror and ceiling (the mirror is behind it, never seen; the ceiling's plane is parallel to the
// film, so pixels cover equal areas of it). max_depth 2: only light -> mirror -> ceiling ->
// camera counts (the ceiling's light reflected back by the mirror is a longer path). Used by
// tests/photons/photon_closed_form_render_test.cpp and bench/app_closed_form_caustic.cpp (no
// test framework here).
//
// The reflection off a planar mirror is the light seen from its mirror image P': on the ceiling,
// where the segment P' -> x crosses the mirror, E(x) = ρ·I·cos θ / D² with D = |x - P'| and
// θ the angle at the ceiling (cos θ = (2 - P'z) / D); elsewhere 0. The flux reflected onto the
// ceiling (all of it lands in view) is ρ·I·Ω, Ω the mirror's solid angle from P. Radiance seen
// by the camera: L = albedo / π · E.
#pragma once
#include <cmath>
#include <numbers>
#include "core/vec.h"
#include "shading/camera.h"

namespace rayes::testing {

struct ClosedFormCaustic {
  // Must match scenes/caustic-closed-form.json.
  static constexpr double kIntensity = 10, kReflectance = 0.9, kAlbedo = 0.5, kCeilingZ = 2;
  const Vec3 light{0.25f, -0.05f, 0.8f};
  const Vec3 corner{-0.6f, -0.6f, -0.05f}, edgeU{1.2f, 0, 0.06f}, edgeV{-0.0025f, 1.2f, 0.05f};  // the mirror

  Vec3 normal() const { return normalize(cross(edgeU, edgeV)); }
  Vec3 image() const { return light - normal() * (2 * dot(light - corner, normal())); }

  // (u, v) of the point where the segment from the light's image to x meets the mirror's plane;
  // false if it does not.
  bool mirrorCoordinates(Vec3 x, double& u, double& v) const {
    const Vec3 a = image(), n = normal();
    const double da = dot(a - corner, n), dx = dot(x - corner, n);
    if (!(da < 0 && dx > 0)) return false;
    const Vec3 m = a + (x - a) * float(da / (da - dx));
    // Solve m - corner = u edgeU + v edgeV (edgeU is orthogonal to edgeV).
    u = dot(m - corner, edgeU) / dot(edgeU, edgeU);
    v = dot(m - corner, edgeV) / dot(edgeV, edgeV);
    return true;
  }
  // Irradiance on the ceiling at x (x.z = 2).
  double irradiance(Vec3 x) const {
    double u, v;
    if (!mirrorCoordinates(x, u, v) || u < 0 || u > 1 || v < 0 || v > 1) return 0;
    const Vec3 d = x - image();
    const double d2 = dot(d, d);
    return kReflectance * kIntensity * (kCeilingZ - image().z) / (d2 * std::sqrt(d2));
  }
  // Whether x lies inside the footprint at least `margin` (in the mirror's (u, v)) from its edges.
  bool inside(Vec3 x, double margin) const {
    double u, v;
    return mirrorCoordinates(x, u, v) && u > margin && u < 1 - margin && v > margin && v < 1 - margin;
  }
  // The flux reflected onto the ceiling: ρ·I·Ω (Ω: two spherical triangles, Van Oosterom and
  // Strackee).
  double reflectedFlux() const {
    const Vec3 c[4] = {corner, corner + edgeU, corner + edgeU + edgeV, corner + edgeV};
    auto tri = [&](Vec3 a, Vec3 b, Vec3 e) {
      a = normalize(a - light), b = normalize(b - light), e = normalize(e - light);
      return 2 * std::atan2(std::fabs(double(dot(a, cross(b, e)))), 1.0 + dot(a, b) + dot(b, e) + dot(e, a));
    };
    return kReflectance * kIntensity * (tri(c[0], c[1], c[2]) + tri(c[0], c[2], c[3]));
  }
};

// Where the camera ray through film position (px, py) meets the ceiling.
inline Vec3 ceilingPoint(const PerspectiveCamera& camera, float px, float py) {
  const CameraRay r = camera.generate(px, py, 0.5f, 0.5f, 0);
  return r.org + r.dir * float((ClosedFormCaustic::kCeilingZ - r.org.z) / r.dir.z);
}

}  // namespace rayes::testing
