#include "lbt/beam_seeds.h"
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace rayes {
namespace {

constexpr uint32_t kNoVertex = 0xffffffffu;

// A grid vertex's (u or v) coordinate: i of m cells, inset from the borders.
float gridCoord(int i, int m) { return kSeedInset + (1 - 2 * kSeedInset) * float(i) / float(m); }

// A leaf's surface at the 5×5 points (0, ¼, ½, ¾, 1)², each with a neighbour a small step
// along u and one along v (towards the inside), for the spans below. Evaluated per leaf and
// light, never held for every leaf (O(1) memory whatever the number of scatterers).
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

// Where the grids' corner rays and triangles go: the chunk being filled, handed to the sink when
// it holds chunkTriangles triangles of [first, last) at the end of a row; triangles outside that
// range are counted and skipped (a chunk holding none of them yet keeps only its last row).
struct Emitter {
  const size_t& chunkTriangles;
  size_t first, last;
  BeamBudget* budget;
  const std::function<void(SeedChunk&&)>& sink;
  SeedChunk chunk;
  size_t next = 0;  // the global index of the next triangle
  size_t capCorners = 0, capTriangles = 0;

  bool done() const { return next >= last; }
  // Room for `corners` more corner rays and `triangles` more triangles, taken before it is made
  // (the old arrays are held while they are copied).
  void reserve(size_t corners, size_t triangles) {
    BeamSeeds& s = chunk.seeds;
    const size_t nc = s.org.size() + corners, nt = s.triangles.size() + triangles;
    if (nc <= capCorners && nt <= capTriangles) return;
    const size_t cc = std::max(nc, 2 * capCorners), ct = std::max(nt, 2 * capTriangles);
    const size_t old = BeamSeeds::bytesFor(capCorners, capTriangles);
    if (!chunk.charge.bytes() && budget) chunk.charge = BeamCharge(budget, 0, "");
    chunk.charge.add(BeamSeeds::bytesFor(cc, ct), "a chunk of beam seeds");
    s.org.reserve(cc), s.dir.reserve(cc), s.coneWidth.reserve(cc), s.coneSpread.reserve(cc), s.aim.reserve(cc);
    s.fromAfar.reserve(cc);
    s.triangles.reserve(ct), s.flux.reserve(ct);
    chunk.charge.sub(old);
    capCorners = cc, capTriangles = ct;
  }
  uint32_t addCorner(Vec3 o, Vec3 d, float width, float spread, const SeedAim& aim, bool fromAfar) {
    BeamSeeds& s = chunk.seeds;
    s.org.push_back(o), s.dir.push_back(d), s.coneWidth.push_back(width), s.coneSpread.push_back(spread);
    s.aim.push_back(aim), s.fromAfar.push_back(fromAfar);
    return uint32_t(s.org.size() - 1);
  }
  void addTriangle(const std::array<uint32_t, 3>& t, Rgb flux) {
    if (next >= first && next < last) chunk.seeds.triangles.push_back(t), chunk.seeds.flux.push_back(flux);
    ++next;
  }
  // At the end of a row: the chunk out when full (or, with none of the range in it, emptied).
  // True when the chunk was restarted: the row's corner rays must be added again.
  bool endRow(bool lastRow) {
    const size_t n = chunk.seeds.triangles.size();
    if (n == 0 && chunk.seeds.org.empty()) return false;
    if (n > 0 && n < chunkTriangles) return false;
    flush();
    return !lastRow;
  }
  void flush() {
    if (!chunk.seeds.triangles.empty()) {
      chunk.first = next - chunk.seeds.triangles.size();
      sink(std::move(chunk));
    }
    chunk = SeedChunk{};
    capCorners = capTriangles = 0;
  }
};

// Adds one leaf's mu × mv grid, row by row: corner(p, o, d) gives the ray toward surface point p
// (false: none); flux(a, b, c) a triangle's flux from its corner ray ids.
template <class Corner, class Flux>
void addLeafGrid(const ScattererSurface& leaf, int mu, int mv, float width, float spread, bool fromAfar, Corner corner,
                 Flux flux, Emitter& out) {
  if (out.done()) return;
  BeamCharge rows(out.budget, 2 * size_t(mu + 1) * sizeof(uint32_t), "a row of beam seeds");
  std::vector<uint32_t> below(size_t(mu) + 1, kNoVertex), above(size_t(mu) + 1, kNoVertex);
  const auto addRow = [&](int j, std::vector<uint32_t>& id) {
    out.reserve(size_t(mu) + 1, 0);
    for (int i = 0; i <= mu; ++i) {
      const float u = gridCoord(i, mu), v = gridCoord(j, mv);
      Vec3 o, d;
      id[i] = corner(leaf.position(u, v), o, d)
                  ? out.addCorner(o, d, width, spread, {leaf.leaf, u, v, 0.25f / float(mu), 0.25f / float(mv)}, fromAfar)
                  : kNoVertex;
    }
  };
  addRow(0, below);
  for (int j = 0; j < mv && !out.done(); ++j) {
    addRow(j + 1, above);
    out.reserve(0, 2 * size_t(mu));
    for (int i = 0; i < mu; ++i) {
      const uint32_t a = below[i], b = below[i + 1], c = above[i + 1], d = above[i];
      for (const std::array<uint32_t, 3> t : {std::array<uint32_t, 3>{a, b, c}, std::array<uint32_t, 3>{a, c, d}}) {
        if (t[0] == kNoVertex || t[1] == kNoVertex || t[2] == kNoVertex) continue;
        const Rgb f = flux(t[0], t[1], t[2]);
        if (!(maxComponent(f) > 0)) continue;
        out.addTriangle(t, f);
      }
    }
    std::swap(below, above);
    if (out.endRow(j + 1 == mv)) addRow(j + 1, below);
  }
}

// Point and spot lights, and the sample points of area lights: intensity(unit direction) in W/sr.
template <class Intensity>
void seedFromPoint(Vec3 c, Intensity intensity, std::span<const ScattererSurface> leaves, int n, Emitter& out) {
  const double cell = 2.0 / n;
  const auto angle = [&](Vec3 a, Vec3 b) {
    const Vec3 da = a - c, db = b - c;
    return double(std::atan2(length(cross(da, db)), dot(da, db)));
  };
  for (size_t k = 0; k < leaves.size() && !out.done(); ++k) {
    const Samples samples = samplesOf(leaves[k]);
    if (!samples.finite) continue;
    const auto [su, sv] = spansOf(samples, angle);
    const int mu = cellsFor(su, cell, 4 * n), mv = cellsFor(sv, cell, 4 * n);
    const float spread = float(std::max(su / mu, sv / mv));
    auto corner = [&](Vec3 p, Vec3& o, Vec3& d) {
      o = c;
      d = normalize(p - c);
      return isFinite(d) && d != Vec3{};
    };
    auto flux = [&](uint32_t a, uint32_t b, uint32_t t) {
      const BeamSeeds& seeds = out.chunk.seeds;
      const double omega = sphericalTriangleArea(seeds.dir[a], seeds.dir[b], seeds.dir[t]);
      return intensity(normalize(seeds.dir[a] + seeds.dir[b] + seeds.dir[t])) * float(omega);
    };
    addLeafGrid(leaves[k], mu, mv, 0.0f, std::isfinite(spread) ? spread : float(cell), false, corner, flux, out);
  }
}

void seedFromDistant(const DistantLight& light, std::span<const ScattererSurface> leaves, int n, Emitter& out) {
  const Vec3 l = normalize(light.direction);
  Vec3 eu, ev;
  orthonormalBasis(l, eu, ev);
  // Lengths across the light: what a parallel beam's cross-section sees.
  const auto across = [&](Vec3 a, Vec3 b) {
    const Vec3 d = b - a;
    return double(length(d - l * dot(d, l)));
  };
  double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
  Box3 scatterers;
  for (const ScattererSurface& surface : leaves) {
    const Samples leaf = samplesOf(surface);
    if (!leaf.finite) continue;
    for (const auto& row : leaf.p)
      for (const Vec3& p : row) {
        scatterers.extend(p);
        u0 = std::min(u0, double(dot(p, eu))), u1 = std::max(u1, double(dot(p, eu)));
        v0 = std::min(v0, double(dot(p, ev))), v1 = std::max(v1, double(dot(p, ev)));
      }
  }
  const double side = std::max(u1 - u0, v1 - v0);
  if (!(side > 0) || !std::isfinite(side)) return;
  const double cell = side / n;
  // Aimed at the scatterers, not at the scene: the plane twice their bounding radius before
  // their centre (the samples' box; a leaf bulging past its samples stays well inside), so the
  // corner rays and where they land keep the scatterers' float precision in a scene of any
  // size. What lies between the light and that plane is found by the way back (fromAfar).
  const Vec3 center = scatterers.center();
  const float start = length(scatterers.extent());
  for (size_t k = 0; k < leaves.size() && !out.done(); ++k) {
    const Samples samples = samplesOf(leaves[k]);
    if (!samples.finite) continue;
    const auto [su, sv] = spansOf(samples, across);
    const int mu = cellsFor(su, cell, 4 * n), mv = cellsFor(sv, cell, 4 * n);
    // Upstream of its surface point, on the plane `start` before the scatterers' centre.
    auto corner = [&](Vec3 p, Vec3& o, Vec3& d) {
      o = p + l * (dot(center - p, l) + start);
      d = -l;
      return isFinite(o);
    };
    auto flux = [&](uint32_t a, uint32_t b, uint32_t t) {
      const BeamSeeds& seeds = out.chunk.seeds;
      const Vec3 &pa = seeds.org[a], &pb = seeds.org[b], &pc = seeds.org[t];
      const double area = std::fabs(double(dot(cross(pb - pa, pc - pa), l))) / 2;
      return light.irradiance * float(area);
    };
    addLeafGrid(leaves[k], mu, mv, float(std::max(su / mu, sv / mv)), 0.0f, true, corner, flux, out);
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
    out.fromAfar.push_back(v < fromAfar.size() ? fromAfar[v] : 0);
  }
  for (size_t t = first; t < last; ++t) {
    out.triangles.push_back({id[triangles[t][0]], id[triangles[t][1]], id[triangles[t][2]]});
    out.flux.push_back(flux[t]);
  }
  return out;
}

void seedBeams(const BeamLights& lights, std::span<const ScattererSurface> leaves, const Box3& sceneBounds,
               int resolution, const size_t& chunkTriangles, size_t first, size_t last, BeamBudget* budget,
               const std::function<void(SeedChunk&&)>& sink) {
  if (leaves.empty() || resolution < 1 || first >= last) return;
  BeamCharge held(budget, 0, "");
  Emitter out{chunkTriangles, first, last, budget, sink, {}};
  for (const PointLight& p : lights.points)
    seedFromPoint(p.position, [&](Vec3) { return p.intensity; }, leaves, resolution, out);
  for (const SpotLight& s : lights.spots)
    seedFromPoint(s.position, [&](Vec3 d) { return s.intensity * s.falloff(dot(d, s.direction)); }, leaves,
                  resolution, out);
  if (lights.areaSamples > 0 && !lights.patches.empty()) {
    const size_t k = size_t(lights.areaSamples);
    held.add(2 * lights.patches.size() * k * k * sizeof(AreaLightPoint), "the area lights' sample points");
    for (const AreaLightPoint& a : areaLightPoints(lights.patches, lights.areaSamples, sceneBounds))
      seedFromPoint(a.position, [&](Vec3 d) { return a.intensity * std::max(0.0f, dot(d, a.normal)); }, leaves,
                    resolution, out);
  }
  for (const DistantLight& d : lights.distants) seedFromDistant(d, leaves, resolution, out);
  out.flush();
}

BeamSeeds seedBeams(const BeamLights& lights, std::span<const ScattererSurface> leaves, const Box3& sceneBounds,
                    int resolution) {
  BeamSeeds seeds;
  const size_t all = std::numeric_limits<size_t>::max();
  seedBeams(lights, leaves, sceneBounds, resolution, all, 0,
            std::numeric_limits<size_t>::max(), nullptr, [&](SeedChunk&& chunk) { seeds = std::move(chunk.seeds); });
  return seeds;
}

}  // namespace rayes
