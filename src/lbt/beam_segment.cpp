#include "lbt/beam_segment.h"
#include <algorithm>
#include <cmath>
#include <numbers>
#include "lbt/gaussian_triangle.h"

namespace rayes {
namespace {
// Below this flux-triangle area (relative to r²) the segment is at a focus.
constexpr double kFocusArea = 1e-12;
// Below this angular area (relative to σ²) P is the lobe's density times the area (the exact
// integral would cancel catastrophically).
constexpr double kSmallLobeArea = 1e-6;

struct D3 {
  double x, y, z;
};
D3 d3(Vec3 v) { return {v.x, v.y, v.z}; }
D3 sub(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 add(D3 a, D3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
D3 mul(D3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dotD(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 crossD(D3 a, D3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double lengthD(D3 a) { return std::sqrt(dotD(a, a)); }
double cross2(FlatPoint a, FlatPoint b) { return a.x * b.y - a.y * b.x; }
void store(double (&out)[3], D3 v) { out[0] = v.x, out[1] = v.y, out[2] = v.z; }
D3 load(const double (&in)[3]) { return {in[0], in[1], in[2]}; }

// Whether x (the flux plane's origin), outside the flux triangle a, lies so far beyond one
// edge's line that the lobe's mass over the angular triangle is below Q(kLobeReach): the test
// the footprint integral would make on the angular corners, made before their three atan2.
// The bound: let n be that edge's unit normal towards the triangle, h = min_k a_k·n > 0 the
// line's distance from x. A corner maps to φ_k = atan(ρ_k/r)/ρ_k · a_k (ρ_k = |a_k|), and
// atan(z)/z falls with z while atan(z) ≥ z/(1+z), so φ_k·n ≥ h·atan(ρmax/r)/ρmax ≥ h/(r+ρmax):
// the angular triangle lies beyond a line h/(r+ρmax) from the lobe's centre, whose far side
// holds mass Q(h/((r+ρmax)σ)). At σ = 0.001 about 99 % of the gathers that reach the
// footprint integral end here (lbt-discoball, lbt-ring; bench/history/2026-11.md).
bool farOutsideLobe(const FlatPoint (&a)[3], double area2, double r, double sigma) {
  if (!(area2 != 0)) return false;
  double rhoMax2 = 0;
  for (const FlatPoint& p : a) rhoMax2 = std::max(rhoMax2, p.x * p.x + p.y * p.y);
  const double reach = kLobeReach * sigma * (r + std::sqrt(rhoMax2));
  for (int i = 0; i < 3; ++i) {
    const FlatPoint p = a[i], q = a[(i + 1) % 3];
    const FlatPoint t{q.x - p.x, q.y - p.y};
    // cross(p, t) is x's signed distance inside the edge's line times |t| (for area2 > 0).
    const double outside = area2 > 0 ? -cross2(p, t) : cross2(p, t);
    if (outside > 0 && outside * outside >= reach * reach * (t.x * t.x + t.y * t.y)) return true;
  }
  return false;
}
}  // namespace

Box3 beamBounds(const BeamSegment& s) {
  Box3 box;
  float far = 0;
  for (int i = 0; i < 3; ++i) {
    box.extend(s.o[i]);
    box.extend(s.o[i] + s.d[i] * s.t[i]);
    far = std::max(far, s.t[i]);
  }
  if (s.sigma > 0) {
    const float pad = far * std::tan(std::min(float(kLobeReach) * s.sigma, 1.3f));
    box.lo -= Vec3{pad, pad, pad};
    box.hi += Vec3{pad, pad, pad};
  }
  return box;
}

BeamEnvelope beamEnvelope(const BeamSegment& s) {
  BeamEnvelope v;
  D3 d[3], o[3];
  for (int i = 0; i < 3; ++i) d[i] = d3(s.d[i]), o[i] = d3(s.o[i]);
  const D3 sum = add(add(d[0], d[1]), d[2]);
  const double len = lengthD(sum);
  if (!(len > 0) || !std::isfinite(len)) return v.never = true, v;
  const D3 c = mul(sum, 1 / len);  // as beamIrradiance's Ψ̄, to the bit
  const D3 origin = mul(add(add(o[0], o[1]), o[2]), 1.0 / 3);
  double cosMin = 1;
  D3 start[3], slope[3];  // corner i's offset from the axis at axial distance t: start + slope·t
  for (int i = 0; i < 3; ++i) {
    const double ci = dotD(d[i], c);
    if (!(ci >= kCoaxialCos)) return v.never = true, v;
    cosMin = std::min(cosMin, ci);
    const D3 rel = sub(o[i], origin);
    const double l = dotD(rel, c);
    slope[i] = mul(sub(d[i], mul(c, ci)), 1 / ci);
    start[i] = sub(sub(rel, mul(c, l)), mul(slope[i], l));
    v.spreadSlope = std::max(v.spreadSlope, lengthD(slope[i]));
    v.axialOffset = std::max(v.axialOffset, std::fabs(l));
    v.axialStart = i == 0 ? l : std::min(v.axialStart, l);
    v.axialEnd = std::max(v.axialEnd, l + ci * double(s.t[i]));
  }
  if (!std::isfinite(v.axialEnd)) v.axialEnd = 0;
  for (int i = 0; i < 3; ++i) {
    v.spreadStart = std::max(v.spreadStart, lengthD(start[i]));
    v.spreadEnd = std::max(v.spreadEnd, lengthD(add(start[i], mul(slope[i], v.axialEnd))));
  }
  v.invCosMin = 1 / cosMin;
  v.lobeReach = s.sigma > 0 ? kLobeReach * double(s.sigma) : 0;
  store(v.origin, origin);
  store(v.axis, c);
  // The cap: beamIrradiance's end plane, taken whenever it would be for the largest cap.
  const double tMax = std::max({double(s.t[0]), double(s.t[1]), double(s.t[2])});
  D3 end[3];
  for (int i = 0; i < 3; ++i) end[i] = add(o[i], mul(d[i], double(s.t[i])));
  D3 endNormal = crossD(sub(end[1], end[0]), sub(end[2], end[0]));
  const double endLen = lengthD(endNormal);
  // (cap ≤ max t_i up to rounding, which the factor 1 + 1e-9 covers here and in excludes.)
  if (endLen > kFocusArea * tMax * tMax * (1 + 1e-9) && std::isfinite(endLen) && std::isfinite(tMax)) {
    endNormal = mul(endNormal, dotD(endNormal, c) < 0 ? -1 / endLen : 1 / endLen);
    store(v.capNormal, endNormal);
    store(v.capPoint, end[0]);
    v.capLimit = kCapSlack * tMax;
  }
  return v;
}

bool BeamEnvelope::excludes(Vec3 xf) const {
  if (never) return true;
  constexpr double kMargin = 1e-6;
  const D3 x = d3(xf);
  // The same arithmetic as the gather's cap test, so only cap ≤ max t_i needs a margin.
  if (capLimit >= 0) {
    if (dotD(sub(x, load(capPoint)), load(capNormal)) > capLimit * (1 + 1e-9)) return true;
  }
  const D3 c = load(axis);
  const D3 rel = sub(x, load(origin));
  const double t = dotD(rel, c);
  // Behind every corner's origin along Ψ̄, every corner's distance (x - o_i)·Ψ̄ / d_i·Ψ̄ is
  // negative, and so is the gather's interpolated r: it returns 0 there.
  if (t < axialStart - kMargin * (std::fabs(t) + axialOffset)) return true;
  const double w = lengthD(sub(rel, mul(c, t)));
  // Each corner's distance from the axis is convex in t: below its chord between the axial
  // levels 0 and axialEnd, and growing at most by spreadSlope per unit beyond them.
  const double spread = t <= 0               ? spreadStart - spreadSlope * t
                        : t >= axialEnd      ? spreadEnd + spreadSlope * (t - axialEnd)
                                             : spreadStart + (spreadEnd - spreadStart) * (t / axialEnd);
  const double outside = w - spread;
  const double need = lobeReach * ((std::fabs(t) + axialOffset) * invCosMin + w + spread);
  // NaN compares false: not excluded.
  return outside > need + kMargin * (w + spread + std::fabs(t) + axialOffset);
}

namespace {

// A glossy lobe that crosses its scatterer's horizon (grazing light) sends nothing below it: no
// direction below a surface is a reflection off it, and the path tracer's lobe (GaussianLobe)
// is 0 there too. The horizon is the plane of the corner rays' origins, which lie on the last
// scatterer (exact on a flat facet, the chord plane of a curved one), on the side the beam
// leaves by. Degenerate origins (collinear) give no plane and cut nothing.
bool belowScattererHorizon(const D3 (&o)[3], D3 c, D3 x) {
  const D3 e1 = sub(o[1], o[0]), e2 = sub(o[2], o[0]);
  const D3 n = crossD(e1, e2);
  const double len = lengthD(n);
  if (!(len > 1e-9 * lengthD(e1) * lengthD(e2)) || !std::isfinite(len)) return false;
  const double side = dotD(n, c);
  if (side == 0) return false;  // the beam runs along its origins' plane: no side to cut
  return dotD(sub(x, o[0]), n) * side < 0;
}

}  // namespace

Rgb beamIrradiance(const BeamSegment& s, Vec3 xf, Vec3 nf, Vec3& psi) {
  const D3 x = d3(xf);
  D3 d[3], o[3];
  for (int i = 0; i < 3; ++i) d[i] = d3(s.d[i]), o[i] = d3(s.o[i]);
  const D3 sum = add(add(d[0], d[1]), d[2]);
  const double len = lengthD(sum);
  if (!(len > 0) || !std::isfinite(len)) return {};
  const D3 c = mul(sum, 1 / len);
  psi = Vec3{float(c.x), float(c.y), float(c.z)};
  Vec3 e1f, e2f;
  orthonormalBasis(psi, e1f, e2f);
  const D3 e1 = d3(e1f), e2 = d3(e2f);

  // Where the corner rays cross the flux plane through x, relative to x, in the plane's basis.
  FlatPoint a[3];
  double along[3];
  for (int i = 0; i < 3; ++i) {
    const double ci = dotD(d[i], c);
    if (!(ci >= kCoaxialCos)) return {};
    along[i] = dotD(sub(x, o[i]), c) / ci;
    const D3 rel = sub(add(o[i], mul(d[i], along[i])), x);
    a[i] = {dotD(rel, e1), dotD(rel, e2)};
  }
  const double area2 = cross2({a[1].x - a[0].x, a[1].y - a[0].y}, {a[2].x - a[0].x, a[2].y - a[0].y});
  // x's barycentrics in the flux triangle (x is the plane's origin), and the same clamped
  // into the triangle for what must be interpolated from the corners (cap, direction).
  double lambda[3] = {cross2(a[1], a[2]) / area2, cross2(a[2], a[0]) / area2, cross2(a[0], a[1]) / area2};
  double clamped[3] = {1.0 / 3, 1.0 / 3, 1.0 / 3};
  bool inside = area2 != 0;
  if (area2 != 0 && std::isfinite(lambda[0] + lambda[1] + lambda[2])) {
    double total = 0;
    for (int i = 0; i < 3; ++i) {
      inside = inside && lambda[i] >= 0;
      total += std::max(0.0, lambda[i]);
    }
    if (total > 0)
      for (int i = 0; i < 3; ++i) clamped[i] = std::max(0.0, lambda[i]) / total;
  } else {
    inside = false;
  }
  if (s.sigma == 0 && !inside) return {};

  // The segment's extent: x must lie past the generator, and not beyond the plane of the
  // corner rays' ends (on a flat receiver the ends and x lie in one plane, wherever the lobe
  // spreads); when the ends are degenerate, not beyond their interpolated distance.
  double r = 0, cap = 0;
  D3 dir{0, 0, 0};
  for (int i = 0; i < 3; ++i) {
    r += clamped[i] * along[i];
    cap += clamped[i] * double(s.t[i]);
    dir = add(dir, mul(d[i], clamped[i]));
  }
  if (!(r > 0)) return {};
  if (s.sigma > 0 && !inside && farOutsideLobe(a, area2, r, s.sigma)) return {};
  if (s.sigma > 0 && belowScattererHorizon(o, c, x)) return {};
  D3 end[3];
  for (int i = 0; i < 3; ++i) end[i] = add(o[i], mul(d[i], double(s.t[i])));
  D3 endNormal = crossD(sub(end[1], end[0]), sub(end[2], end[0]));
  const double endLen = lengthD(endNormal);
  if (endLen > kFocusArea * cap * cap && std::isfinite(endLen)) {
    endNormal = mul(endNormal, dotD(endNormal, c) < 0 ? -1 / endLen : 1 / endLen);
    if (dotD(sub(x, end[0]), endNormal) > kCapSlack * cap) return {};
  } else if (r > cap * (1 + kCapSlack)) {
    return {};
  }
  const double dirLen = lengthD(dir);
  if (!(dirLen > 0)) return {};
  const double cosN = std::fabs(dotD(dir, d3(nf))) / dirLen;
  psi = Vec3{float(dir.x / dirLen), float(dir.y / dirLen), float(dir.z / dirLen)};
  const double areaPerp = std::fabs(area2) / 2;
  const bool focus = !(areaPerp > kFocusArea * r * r);

  double perArea;  // P / A⊥
  if (s.sigma == 0) {
    if (focus) return {};  // a specular focus: unbounded irradiance, no value to give
    perArea = 1 / areaPerp;
  } else {
    const double sigma = s.sigma;
    // The flux triangle seen from the scatterer at x's distance r along the beam: a corner at
    // distance ρ from x in the flux plane lies at the angle atan(ρ / r). One r for all three
    // corners keeps the angular triangle similar to the flux triangle near a focus (angular
    // area → A⊥/r²), so P/A⊥ stays below the lobe's peak density over r². (Each corner's own
    // distance would shear it: where corner origins lie at different distances, as on a curved
    // reflector, the angular area shrinks only linearly as A⊥ → 0 and P/A⊥ spikes.)
    FlatPoint phi[3];
    for (int i = 0; i < 3; ++i) {
      const double dist = std::sqrt(a[i].x * a[i].x + a[i].y * a[i].y);
      const double angle = std::atan2(dist, r);
      phi[i] = dist > 0 ? FlatPoint{angle * a[i].x / dist, angle * a[i].y / dist} : FlatPoint{0, 0};
    }
    const double areaAngle =
        std::fabs(cross2({phi[1].x - phi[0].x, phi[1].y - phi[0].y}, {phi[2].x - phi[0].x, phi[2].y - phi[0].y})) / 2;
    if (focus || areaAngle < kSmallLobeArea * sigma * sigma) {
      // P = density at the blended offset times the angular area; the angular area over A⊥
      // tends to 1/r² at a focus, where both vanish.
      const FlatPoint mid{clamped[0] * phi[0].x + clamped[1] * phi[1].x + clamped[2] * phi[2].x,
                          clamped[0] * phi[0].y + clamped[1] * phi[1].y + clamped[2] * phi[2].y};
      const double q = (mid.x * mid.x + mid.y * mid.y) / (sigma * sigma);
      const double density = std::exp(-q / 2) / (2 * std::numbers::pi * sigma * sigma);
      perArea = density * (focus ? 1 / (r * r) : areaAngle / areaPerp);
    } else {
      perArea = gaussianTriangleMass(phi[0], phi[1], phi[2], sigma, kLobeReach) / areaPerp;
    }
  }
  const double scale = perArea * cosN;
  if (!std::isfinite(scale)) return {};
  const Rgb e = s.power * float(scale);
  return isFinite(e) ? e : Rgb{};
}

}  // namespace rayes
