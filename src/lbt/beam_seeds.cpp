#include "lbt/beam_seeds.h"
#include <algorithm>
#include <cmath>
#include <limits>

namespace rayes {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Rect {
  double u0 = kInf, u1 = -kInf, v0 = kInf, v1 = -kInf;
  bool empty() const { return !(u0 <= u1 && v0 <= v1); }
  void extend(double u, double v) { u0 = std::min(u0, u), u1 = std::max(u1, u), v0 = std::min(v0, v), v1 = std::max(v1, v); }
  void extend(const Rect& r) { extend(r.u0, r.v0), extend(r.u1, r.v1); }
};

// Marks the cells of an N×N grid over [lo, lo + N·cell]² that a rectangle covers.
void markCells(const Rect& r, double lo, double cell, int n, std::vector<uint8_t>& used) {
  if (r.empty()) return;
  const int i0 = std::clamp(int(std::floor((r.u0 - lo) / cell)), 0, n - 1);
  const int i1 = std::clamp(int(std::floor((r.u1 - lo) / cell)), 0, n - 1);
  const int j0 = std::clamp(int(std::floor((r.v0 - lo) / cell)), 0, n - 1);
  const int j1 = std::clamp(int(std::floor((r.v1 - lo) / cell)), 0, n - 1);
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i) used[size_t(j) * n + i] = 1;
}

Vec3 boxCorner(const Box3& b, int k) {
  return {(k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y, (k & 4) ? b.hi.z : b.lo.z};
}

// Adds the corner rays and triangles of the used cells of one N×N grid. corner(i, j) gives a
// grid vertex's ray; flux(a, b, c) a triangle's flux from its corner ray ids.
template <class Corner, class Flux>
void addGrid(int n, const std::vector<uint8_t>& used, float width, float spread, Corner corner, Flux flux,
             BeamSeeds& seeds) {
  std::vector<uint32_t> id(size_t(n + 1) * (n + 1), 0xffffffffu);
  auto vertex = [&](int i, int j) {
    uint32_t& v = id[size_t(j) * (n + 1) + i];
    if (v == 0xffffffffu) {
      Vec3 o, d;
      corner(i, j, o, d);
      v = uint32_t(seeds.org.size());
      seeds.org.push_back(o);
      seeds.dir.push_back(d);
      seeds.coneWidth.push_back(width);
      seeds.coneSpread.push_back(spread);
    }
    return v;
  };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if (!used[size_t(j) * n + i]) continue;
      const uint32_t a = vertex(i, j), b = vertex(i + 1, j), c = vertex(i + 1, j + 1), d = vertex(i, j + 1);
      for (const std::array<uint32_t, 3> t : {std::array<uint32_t, 3>{a, b, c}, std::array<uint32_t, 3>{a, c, d}}) {
        const Rgb f = flux(t[0], t[1], t[2]);
        if (!(maxComponent(f) > 0)) continue;
        seeds.triangles.push_back(t);
        seeds.flux.push_back(f);
      }
    }
}

// The rectangle of a cube face (axis w, coordinates u, v in [-1, 1]) that a box covers as seen
// from c: the projections of the box clipped to the half-space in front of the face (its
// corners there and where its edges cross the plane just in front of c), clipped to the face.
Rect projectOntoFace(const Box3& b, Vec3 c, Vec3 w, Vec3 u, Vec3 v) {
  Rect r;
  const double eps = 1e-6 * (double(b.longestSide()) + double(length(b.center() - c)));
  auto add = [&](Vec3 p, double z) { r.extend(double(dot(p, u)) / z, double(dot(p, v)) / z); };
  for (int k = 0; k < 8; ++k) {
    const Vec3 p = boxCorner(b, k) - c;
    const double z = dot(p, w);
    if (z > eps) add(p, z);
    for (int bit : {1, 2, 4}) {
      if (k & bit) continue;
      const Vec3 q = boxCorner(b, k | bit) - c;
      const double zq = dot(q, w);
      if ((z > eps) == (zq > eps)) continue;
      const float a = float((eps - z) / (zq - z));  // the edge crosses z = eps here
      add(p + (q - p) * a, eps);
    }
  }
  if (r.empty()) return r;
  return {std::max(r.u0, -1.0), std::min(r.u1, 1.0), std::max(r.v0, -1.0), std::min(r.v1, 1.0)};
}

// Point and spot lights, and the sample points of area lights: a cube map about the point;
// intensity(unit direction) in W/sr.
template <class Intensity>
void seedFromPoint(Vec3 c, Intensity intensity, std::span<const Box3> boxes, int n, BeamSeeds& seeds) {
  const double cell = 2.0 / n;
  for (int face = 0; face < 6; ++face) {
    const int axis = face / 2;
    const float sign = (face & 1) ? -1.0f : 1.0f;
    Vec3 w{}, u{}, v{};
    w[axis] = sign;
    u[(axis + 1) % 3] = 1;
    v[(axis + 2) % 3] = 1;
    std::vector<uint8_t> used(size_t(n) * n, 0);
    bool any = false;
    for (const Box3& b : boxes) {
      const Rect r = projectOntoFace(b, c, w, u, v);
      if (!r.empty()) any = true;
      markCells(r, -1, cell, n, used);
    }
    if (!any) continue;
    auto corner = [&](int i, int j, Vec3& o, Vec3& d) {
      o = c;
      d = normalize(w + u * float(-1 + i * cell) + v * float(-1 + j * cell));
    };
    auto flux = [&](uint32_t a, uint32_t b, uint32_t t) {
      const double omega = sphericalTriangleArea(seeds.dir[a], seeds.dir[b], seeds.dir[t]);
      return intensity(normalize(seeds.dir[a] + seeds.dir[b] + seeds.dir[t])) * float(omega);
    };
    addGrid(n, used, 0.0f, float(cell), corner, flux, seeds);
  }
}

void seedFromDistant(const DistantLight& light, std::span<const Box3> boxes, const Box3& scene, int n,
                     BeamSeeds& seeds) {
  const Vec3 l = normalize(light.direction);
  Vec3 u, v;
  orthonormalBasis(l, u, v);
  std::vector<Rect> rects;
  Rect all;
  for (const Box3& b : boxes) {
    Rect r;
    for (int k = 0; k < 8; ++k) r.extend(dot(boxCorner(b, k), u), dot(boxCorner(b, k), v));
    rects.push_back(r);
    all.extend(r);
  }
  if (rects.empty()) return;
  const double side = std::max(all.u1 - all.u0, all.v1 - all.v0);
  if (!(side > 0)) return;
  const double cell = side / n;
  std::vector<uint8_t> used(size_t(n) * n, 0);
  for (const Rect& r : rects) {
    Rect shifted{r.u0 - all.u0, r.u1 - all.u0, r.v0 - all.v0, r.v1 - all.v0};
    markCells(shifted, 0, cell, n, used);
  }
  const Vec3 center = scene.center();
  const float start = length(scene.extent()) + 1.0f;  // outside the scene's bounding sphere
  const Vec3 base = center - u * dot(center, u) - v * dot(center, v) + l * start;
  auto corner = [&](int i, int j, Vec3& o, Vec3& d) {
    o = base + u * float(all.u0 + i * cell) + v * float(all.v0 + j * cell);
    d = -l;
  };
  const Rgb perTriangle = light.irradiance * float(cell * cell / 2);
  auto flux = [&](uint32_t, uint32_t, uint32_t) { return perTriangle; };
  addGrid(n, used, float(cell), 0.0f, corner, flux, seeds);
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
  }
  for (size_t t = first; t < last; ++t) {
    out.triangles.push_back({id[triangles[t][0]], id[triangles[t][1]], id[triangles[t][2]]});
    out.flux.push_back(flux[t]);
  }
  return out;
}

BeamSeeds seedBeams(const BeamLights& lights, std::span<const Box3> boxes, const Box3& sceneBounds, int resolution) {
  BeamSeeds seeds;
  if (boxes.empty() || resolution < 1) return seeds;
  for (const PointLight& p : lights.points)
    seedFromPoint(p.position, [&](Vec3) { return p.intensity; }, boxes, resolution, seeds);
  for (const SpotLight& s : lights.spots)
    seedFromPoint(s.position, [&](Vec3 d) { return s.intensity * s.falloff(dot(d, s.direction)); }, boxes, resolution,
                  seeds);
  for (const AreaLightPoint& a : areaLightPoints(lights.patches, lights.areaSamples, sceneBounds))
    seedFromPoint(a.position, [&](Vec3 d) { return a.intensity * std::max(0.0f, dot(d, a.normal)); }, boxes,
                  resolution, seeds);
  for (const DistantLight& d : lights.distants) seedFromDistant(d, boxes, sceneBounds, resolution, seeds);
  return seeds;
}

}  // namespace rayes
