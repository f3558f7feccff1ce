#include "lbt/beam_seeds.h"
#include <algorithm>
#include <cmath>
#include <utility>

namespace rayes {
namespace {

constexpr uint32_t kNoVertex = 0xffffffffu;

// A grid vertex's (u or v) coordinate: i of m cells, inset from the borders.
float gridCoord(int i, int m) { return kSeedInset + (1 - 2 * kSeedInset) * float(i) / float(m); }

// A leaf's surface at the 5×5 points (0, ¼, ½, ¾, 1)², each with a neighbour a small step
// along u and one along v (towards the inside), for the spans below. Evaluated once per leaf
// for every light (seedBeams).
constexpr int kSampleSteps = 4;
constexpr float kRateStep = 1.0f / 1024;
struct Samples {
  Vec3 p[kSampleSteps + 1][kSampleSteps + 1];  // [v][u]
  Vec3 du[kSampleSteps + 1][kSampleSteps + 1], dv[kSampleSteps + 1][kSampleSteps + 1];
  bool finite = true;
};
Samples samplesOf(const ScattererSurface& leaf) {
  Samples s;
  for (int j = 0; j <= kSampleSteps; ++j)
    for (int i = 0; i <= kSampleSteps; ++i) {
      const float u = float(i) / kSampleSteps, v = float(j) / kSampleSteps;
      s.p[j][i] = leaf.position(u, v);
      s.du[j][i] = leaf.position(u + (i < kSampleSteps ? kRateStep : -kRateStep), v);
      s.dv[j][i] = leaf.position(u, v + (j < kSampleSteps ? kRateStep : -kRateStep));
      s.finite = s.finite && isFinite(s.p[j][i]) && isFinite(s.du[j][i]) && isFinite(s.dv[j][i]);
    }
  return s;
}

// What the leaf spans along u and along v if it were everywhere as dense as where it is densest
// (`span(a, b)` per unit of u or v: the largest of the local rates at the samples and of the
// chords between neighbouring samples): a uniform grid in (u, v) then keeps every cell near the
// target, where the light sees the leaf at a slant as well as head-on (a wide plane under a
// point light is densest at its foot).
template <class Span>
std::pair<double, double> spansOf(const Samples& s, Span span) {
  double su = 0, sv = 0;
  for (int k = 0; k <= kSampleSteps; ++k)
    for (int m = 0; m <= kSampleSteps; ++m) {
      su = std::max(su, span(s.p[k][m], s.du[k][m]) / kRateStep);
      sv = std::max(sv, span(s.p[m][k], s.dv[m][k]) / kRateStep);
      if (m == kSampleSteps) continue;
      su = std::max(su, span(s.p[k][m], s.p[k][m + 1]) * kSampleSteps);
      sv = std::max(sv, span(s.p[m][k], s.p[m + 1][k]) * kSampleSteps);
    }
  return {su, sv};
}

int cellsFor(double span, double cell, int most) {
  const double m = std::ceil(span / cell);
  return m >= 1 ? int(std::min(m, double(most))) : 1;  // NaN: 1
}

// Adds one leaf's mu × mv grid: corner(p, o, d) gives the ray toward surface point p (false:
// none); flux(a, b, c) a triangle's flux from its corner ray ids.
template <class Corner, class Flux>
void addLeafGrid(const ScattererSurface& leaf, int mu, int mv, float width, float spread, Corner corner, Flux flux,
                 BeamSeeds& seeds) {
  std::vector<uint32_t> id(size_t(mu + 1) * (mv + 1), kNoVertex);
  for (int j = 0; j <= mv; ++j)
    for (int i = 0; i <= mu; ++i) {
      const float u = gridCoord(i, mu), v = gridCoord(j, mv);
      Vec3 o, d;
      if (!corner(leaf.position(u, v), o, d)) continue;
      id[size_t(j) * (mu + 1) + i] = uint32_t(seeds.org.size());
      seeds.org.push_back(o);
      seeds.dir.push_back(d);
      seeds.coneWidth.push_back(width);
      seeds.coneSpread.push_back(spread);
      seeds.aim.push_back({leaf.leaf, u, v, 0.25f / float(mu), 0.25f / float(mv)});
    }
  for (int j = 0; j < mv; ++j)
    for (int i = 0; i < mu; ++i) {
      const auto at = [&](int di, int dj) { return id[size_t(j + dj) * (mu + 1) + i + di]; };
      const uint32_t a = at(0, 0), b = at(1, 0), c = at(1, 1), d = at(0, 1);
      for (const std::array<uint32_t, 3> t : {std::array<uint32_t, 3>{a, b, c}, std::array<uint32_t, 3>{a, c, d}}) {
        if (t[0] == kNoVertex || t[1] == kNoVertex || t[2] == kNoVertex) continue;
        const Rgb f = flux(t[0], t[1], t[2]);
        if (!(maxComponent(f) > 0)) continue;
        seeds.triangles.push_back(t);
        seeds.flux.push_back(f);
      }
    }
}

// Point and spot lights, and the sample points of area lights: intensity(unit direction) in W/sr.
template <class Intensity>
void seedFromPoint(Vec3 c, Intensity intensity, std::span<const ScattererSurface> leaves,
                   std::span<const Samples> samples, int n, BeamSeeds& seeds) {
  const double cell = 2.0 / n;
  const auto angle = [&](Vec3 a, Vec3 b) {
    const Vec3 da = a - c, db = b - c;
    return double(std::atan2(length(cross(da, db)), dot(da, db)));
  };
  for (size_t k = 0; k < leaves.size(); ++k) {
    if (!samples[k].finite) continue;
    const auto [su, sv] = spansOf(samples[k], angle);
    const int mu = cellsFor(su, cell, 4 * n), mv = cellsFor(sv, cell, 4 * n);
    const float spread = float(std::max(su / mu, sv / mv));
    auto corner = [&](Vec3 p, Vec3& o, Vec3& d) {
      o = c;
      d = normalize(p - c);
      return isFinite(d) && d != Vec3{};
    };
    auto flux = [&](uint32_t a, uint32_t b, uint32_t t) {
      const double omega = sphericalTriangleArea(seeds.dir[a], seeds.dir[b], seeds.dir[t]);
      return intensity(normalize(seeds.dir[a] + seeds.dir[b] + seeds.dir[t])) * float(omega);
    };
    addLeafGrid(leaves[k], mu, mv, 0.0f, std::isfinite(spread) ? spread : float(cell), corner, flux, seeds);
  }
}

void seedFromDistant(const DistantLight& light, std::span<const ScattererSurface> leaves,
                     std::span<const Samples> samples, const Box3& scene, int n, BeamSeeds& seeds) {
  const Vec3 l = normalize(light.direction);
  Vec3 eu, ev;
  orthonormalBasis(l, eu, ev);
  // Lengths across the light: what a parallel beam's cross-section sees.
  const auto across = [&](Vec3 a, Vec3 b) {
    const Vec3 d = b - a;
    return double(length(d - l * dot(d, l)));
  };
  double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
  for (const Samples& leaf : samples) {
    if (!leaf.finite) continue;
    for (const auto& row : leaf.p)
      for (const Vec3& p : row) {
        u0 = std::min(u0, double(dot(p, eu))), u1 = std::max(u1, double(dot(p, eu)));
        v0 = std::min(v0, double(dot(p, ev))), v1 = std::max(v1, double(dot(p, ev)));
      }
  }
  const double side = std::max(u1 - u0, v1 - v0);
  if (!(side > 0) || !std::isfinite(side)) return;
  const double cell = side / n;
  const Vec3 center = scene.center();
  const float start = length(scene.extent()) + 1.0f;  // outside the scene's bounding sphere
  for (size_t k = 0; k < leaves.size(); ++k) {
    if (!samples[k].finite) continue;
    const auto [su, sv] = spansOf(samples[k], across);
    const int mu = cellsFor(su, cell, 4 * n), mv = cellsFor(sv, cell, 4 * n);
    // Upstream of its surface point, on the plane `start` before the scene's centre.
    auto corner = [&](Vec3 p, Vec3& o, Vec3& d) {
      o = p + l * (dot(center - p, l) + start);
      d = -l;
      return isFinite(o);
    };
    auto flux = [&](uint32_t a, uint32_t b, uint32_t t) {
      const Vec3 &pa = seeds.org[a], &pb = seeds.org[b], &pc = seeds.org[t];
      const double area = std::fabs(double(dot(cross(pb - pa, pc - pa), l))) / 2;
      return light.irradiance * float(area);
    };
    addLeafGrid(leaves[k], mu, mv, float(std::max(su / mu, sv / mv)), 0.0f, corner, flux, seeds);
  }
}

}  // namespace

std::vector<AreaLightPoint> areaLightPoints(std::span<const PatchLight> patches, int k, const Box3& sceneBounds) {
  std::vector<AreaLightPoint> points;
  if (k < 1) return points;
  // Off the surface by a hair, so the corner rays do not find the light's own patch.
  const float lift = 1e-5f * (length(sceneBounds.extent()) + sceneBounds.magnitude());
  for (const PatchLight& light : patches)
    for (int j = 0; j < k; ++j)
      for (int i = 0; i < k; ++i) {
        Vec3 p, n;
        light.evaluate((i + 0.5f) / float(k), (j + 0.5f) / float(k), p, n);
        const float area = length(n) / float(k * k);  // |dP/du × dP/dv| over the stratum
        if (!(area > 0) || !isFinite(p)) continue;
        n = normalize(n);
        for (float side : {1.0f, -1.0f}) {
          if (side < 0 && !light.twoSided) break;
          points.push_back({p + n * (side * lift), n * side, light.radiance * area});
        }
      }
  return points;
}

double sphericalTriangleArea(Vec3 a, Vec3 b, Vec3 c) {
  const double triple = std::fabs(double(dot(a, cross(b, c))));
  const double denom = 1.0 + double(dot(a, b)) + double(dot(b, c)) + double(dot(c, a));
  const double omega = 2.0 * std::atan2(triple, denom);
  return std::isfinite(omega) && omega > 0 ? omega : 0.0;
}

BeamSeeds BeamSeeds::range(size_t first, size_t last) const {
  BeamSeeds out;
  last = std::min(last, triangles.size());
  std::vector<uint32_t> id(org.size(), 0xffffffffu);
  for (size_t t = first; t < last; ++t)
    for (uint32_t v : triangles[t]) id[v] = 0;
  for (size_t v = 0; v < org.size(); ++v) {
    if (id[v]) continue;
    id[v] = uint32_t(out.org.size());
    out.org.push_back(org[v]);
    out.dir.push_back(dir[v]);
    out.coneWidth.push_back(coneWidth[v]);
    out.coneSpread.push_back(coneSpread[v]);
    out.aim.push_back(aim[v]);
  }
  for (size_t t = first; t < last; ++t) {
    out.triangles.push_back({id[triangles[t][0]], id[triangles[t][1]], id[triangles[t][2]]});
    out.flux.push_back(flux[t]);
  }
  return out;
}

BeamSeeds seedBeams(const BeamLights& lights, std::span<const ScattererSurface> leaves, const Box3& sceneBounds,
                    int resolution) {
  BeamSeeds seeds;
  if (leaves.empty() || resolution < 1) return seeds;
  std::vector<Samples> samples;
  samples.reserve(leaves.size());
  for (const ScattererSurface& leaf : leaves) samples.push_back(samplesOf(leaf));
  for (const PointLight& p : lights.points)
    seedFromPoint(p.position, [&](Vec3) { return p.intensity; }, leaves, samples, resolution, seeds);
  for (const SpotLight& s : lights.spots)
    seedFromPoint(s.position, [&](Vec3 d) { return s.intensity * s.falloff(dot(d, s.direction)); }, leaves, samples,
                  resolution, seeds);
  for (const AreaLightPoint& a : areaLightPoints(lights.patches, lights.areaSamples, sceneBounds))
    seedFromPoint(a.position, [&](Vec3 d) { return a.intensity * std::max(0.0f, dot(d, a.normal)); }, leaves,
                  samples, resolution, seeds);
  for (const DistantLight& d : lights.distants) seedFromDistant(d, leaves, samples, sceneBounds, resolution, seeds);
  return seeds;
}

}  // namespace rayes
