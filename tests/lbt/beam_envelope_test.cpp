// The gather's early out (lbt/beam_segment.h, BeamEnvelope): a segment's envelope may exclude a
// point only where the gather is dark (0 for a specular segment, a lobe mass P ≤ Q(kLobeReach)
// for a glossy one), and it must exclude what lies well outside the beam, or it saves nothing.
// Checked on random segments of every shape the tracer makes (diverging, converging, at and past
// a focus, sheared corner origins as on a curved reflector), at tiny and huge scales and far from
// the origin, with points in and around each segment's box, on its corner rays, at its cap and
// behind its scatterer.
#include <gtest/gtest.h>
#include <cmath>
#include <cstdint>
#include "lbt/beam_segment.h"
#include "lbt/gaussian_triangle.h"

namespace rayes {
namespace {

struct Random {
  uint64_t state;
  double uniform() {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return double(state >> 11) * 0x1.0p-53;
  }
  double in(double lo, double hi) { return lo + (hi - lo) * uniform(); }
};

// A segment from a scatterer triangle of size `size` at `at`, its corner rays aimed at points
// around `target` spread by `spread` (0: a focus there), of length `length`.
BeamSegment randomSegment(Random& r, Vec3 at, double size, double length, double spread, float sigma) {
  BeamSegment s;
  const Vec3 target = at + Vec3{float(r.in(-0.3, 0.3) * length), float(r.in(-0.3, 0.3) * length),
                                float(r.in(0.5, 1.0) * length)};
  for (int k = 0; k < 3; ++k) {
    s.o[k] = at + Vec3{float(r.in(-size, size)), float(r.in(-size, size)), float(r.in(-0.5, 0.5) * size)};
    const Vec3 aim = target + Vec3{float(r.in(-spread, spread)), float(r.in(-spread, spread)), 0};
    s.d[k] = normalize(aim - s.o[k]);
    s.t[k] = float(length * r.in(0.8, 1.6));
  }
  s.power = {1, 1, 1};
  s.sigma = sigma;
  return s;
}

// P at x recovered from the gather: E = power·|cos|·P/A⊥ with the normal along Ψ̄ (cos = 1),
// A⊥ the flux triangle's area on the plane through x perpendicular to Ψ̄, computed here on its own.
double lobeMass(const BeamSegment& s, Vec3 x) {
  const Vec3 c = normalize(s.d[0] + s.d[1] + s.d[2]);
  Vec3 p[3];
  for (int k = 0; k < 3; ++k) p[k] = s.o[k] + s.d[k] * (dot(x - s.o[k], c) / dot(s.d[k], c));
  const double area = 0.5 * double(length(cross(p[1] - p[0], p[2] - p[0])));
  Vec3 psi;
  return double(beamIrradiance(s, x, c, psi).x) * area;
}

TEST(BeamEnvelope, ExcludesOnlyPointsTheGatherLeavesDarkAndMostOfWhatLiesOutside) {
  Random r{7};
  const double tail = normalTail(kLobeReach);
  // The gather's own cut may add up to 3·Q(reach) to a mass of at most Q(reach).
  const double darkGlossy = 4 * tail;
  int excluded = 0, farOutside = 0, farExcluded = 0, behind = 0, behindExcluded = 0;
  for (const double scale : {1e-3, 1.0, 1e3})
    for (const Vec3 at : {Vec3{0, 0, 0}, Vec3{1e4f, -2e4f, 5e3f}})
      for (const float sigma : {0.0f, 0.001f, 0.05f, 0.15f})
        for (int n = 0; n < 60; ++n) {
          const double spread = n % 3 == 0 ? 0 : scale * r.in(0.01, 0.5);  // a third focus
          const BeamSegment s = randomSegment(r, at * float(scale), 0.05 * scale, 2 * scale, spread, sigma);
          const BeamEnvelope envelope = beamEnvelope(s);
          ASSERT_FALSE(envelope.never);
          const Box3 box = beamBounds(s);
          const Vec3 centre = (box.lo + box.hi) * 0.5f, half = (box.hi - box.lo) * 1.0f;
          for (int m = 0; m < 300; ++m) {
            Vec3 x;
            if (m < 12) {  // on a corner ray, before, at and past its end
              const int k = m % 3;
              x = s.o[k] + s.d[k] * (s.t[k] * float(0.25 + 0.35 * (m / 3)));
            } else {
              x = centre + Vec3{float(r.in(-1, 1)) * half.x, float(r.in(-1, 1)) * half.y, float(r.in(-1, 1)) * half.z};
            }
            if (!envelope.excludes(x)) continue;
            ++excluded;
            const double p = lobeMass(s, x);
            if (sigma == 0)
              EXPECT_EQ(p, 0.0) << "specular, scale " << scale << ", segment " << n << ", point " << m;
            else
              EXPECT_LE(p, darkGlossy) << "sigma " << sigma << ", scale " << scale << ", segment " << n;
          }
          // Points on the flux plane partway along the beam, far to one side: beyond twice the
          // beam's widest cross-section (at its start or its far end: between them the beam is
          // never wider) plus twice the lobe's reach from 2.5 times that distance.
          const Vec3 c = normalize(s.d[0] + s.d[1] + s.d[2]);
          const Vec3 o = (s.o[0] + s.o[1] + s.o[2]) * (1.0f / 3);
          float farEnd = 0;
          for (int k = 0; k < 3; ++k) farEnd = std::max(farEnd, dot(s.o[k] - o, c) + dot(s.d[k], c) * s.t[k]);
          double widest = 0;
          for (const float level : {0.0f, farEnd})
            for (int k = 0; k < 3; ++k) {
              const Vec3 centre = o + c * level;
              const Vec3 p = s.o[k] + s.d[k] * (dot(centre - s.o[k], c) / dot(s.d[k], c));
              widest = std::max(widest, double(length(p - centre)));
            }
          Vec3 side = normalize(cross(c, Vec3{0.3f, 0.5f, 0.8f}));
          const Vec3 mid = o + c * float(scale);
          for (int q = 0; q < 8; ++q) {
            side = normalize(cross(c, side + Vec3{0.1f * q, -0.2f, 0.05f}));
            const double away = 2 * widest + 2 * kLobeReach * sigma * 2.5 * scale;
            const Vec3 x = mid + side * float(away * r.in(1.0, 3.0));
            if (length(x - mid) > 1.8 * scale) continue;  // the plane must lie inside the cone of coaxial rays
            ++farOutside;
            farExcluded += envelope.excludes(x);
          }
          // Behind the scatterer (before every corner's origin along Ψ̄), anywhere to the side:
          // the gather's interpolated distance is negative there, so it is dark and excluded.
          float first = dot(s.o[0] - o, c);
          for (int k = 1; k < 3; ++k) first = std::min(first, dot(s.o[k] - o, c));
          for (int q = 0; q < 4; ++q) {
            const Vec3 x = o + c * (first - float(scale * r.in(0.01, 1.0))) + side * float(scale * r.in(-2, 2));
            ++behind;
            behindExcluded += envelope.excludes(x);
          }
        }
  EXPECT_GT(excluded, 10000);  // the checks above were not vacuous
  EXPECT_GT(farOutside, 1000);
  EXPECT_EQ(farExcluded, farOutside);
  EXPECT_EQ(behindExcluded, behind);
}

TEST(BeamEnvelope, ASegmentWhoseCornersAreNotCoaxialExcludesEverything) {
  BeamSegment s;
  for (int k = 0; k < 3; ++k) s.o[k] = {0.1f * k, 0, 0}, s.t[k] = 1;
  s.d[0] = {0, 0, 1};
  s.d[1] = {1, 0, 0};
  s.d[2] = {-1, 0, 0};
  s.power = {1, 1, 1};
  const BeamEnvelope envelope = beamEnvelope(s);
  EXPECT_TRUE(envelope.never);
  Vec3 psi;
  EXPECT_EQ(beamIrradiance(s, {0.1f, 0.1f, 0.5f}, {0, 0, 1}, psi).x, 0.0f);
  EXPECT_TRUE(envelope.excludes({0.1f, 0.1f, 0.5f}));
}

}  // namespace
}  // namespace rayes
