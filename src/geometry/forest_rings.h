// The rings of a forest's branches (geometry/forest_patches.h): the spine's Bézier, its
// tangent, and the ring at a spine parameter. Shared by the growth (geometry/forest.cpp: where
// twigs carry their leaves) and the bark patches (geometry/forest_patches.cpp), so both compute
// a ring by one function from the same float t, and shared borders are bit-identical.
#pragma once
#include "core/vec.h"
#include "geometry/forest_patches.h"

namespace rayes::forest_rings {

// Bézier handle length of a quarter circle (4/3 tan(π/8)): radial error 0.027 %.
constexpr float kArcHandle = 0.5522847498f;
// cos and sin of the quarter angles 0, π/2, π, 3π/2, exactly: the four quarters of a ring meet
// in bit-identical points, and quarter 3 closes on quarter 0.
constexpr float kQuarterCos[5] = {1, 0, -1, 0, 1};
constexpr float kQuarterSin[5] = {0, 1, 0, -1, 0};

inline Vec3 bezier(const Vec3 (&p)[4], float t) {
  const float s = 1 - t;
  return p[0] * (s * s * s) + p[1] * (3 * s * s * t) + p[2] * (3 * s * t * t) + p[3] * (t * t * t);
}
inline Vec3 bezierTangent(const Vec3 (&p)[4], float t) {
  const float s = 1 - t;
  return (p[1] - p[0]) * (3 * s * s) + (p[2] - p[1]) * (6 * s * t) + (p[3] - p[2]) * (3 * t * t);
}

// The ring of a branch at spine parameter t: centre, radius, and the frame (n, b) the quarter
// angles are measured in.
struct Ring {
  Vec3 c, n, b;
  float r;
  Vec3 at(int q) const { return c + (n * kQuarterCos[q] + b * kQuarterSin[q]) * r; }
  Vec3 tangentAt(int q) const { return (b * kQuarterCos[q] - n * kQuarterSin[q]) * (kArcHandle * r); }
};
inline Ring ringAt(const ForestBranch& br, float t) {
  const Vec3 T = normalize(bezierTangent(br.spine, t));
  const Vec3 n = normalize(br.up - T * dot(br.up, T));
  return {bezier(br.spine, t), n, cross(T, n), br.r0 + (br.r1 - br.r0) * t};
}

}  // namespace rayes::forest_rings
