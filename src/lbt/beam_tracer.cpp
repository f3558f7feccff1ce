#include "lbt/beam_tracer.h"
#include <algorithm>
#include <cmath>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include "shading/fresnel.h"
#include "shading/path_tracer.h"
#include "shading/surface_hit.h"

namespace rayes {
namespace {

enum class Event : uint8_t { Stop, Reflect, Refract };
constexpr uint32_t kNone = 0xffffffffu;  // no material: the corner ray left the scene
enum class Outcome : uint8_t { Continue, End, Mixed, Silhouette, Tir, Divergent };

// A corner ray's state between generations.
struct Corner {
  Vec3 org, dir;
  float width = 0, spread = 0;
  uint32_t fromLeaf = kNoLeaf;
  uint8_t fromLevel = 0;
};

// What a corner ray found and what it becomes.
struct Scatter {
  float t = 0;          // hit distance (dir is unit), or the far length
  Event event = Event::Stop;
  uint32_t material = kNone;
  bool front = false;   // arrived on the geometric normal's side
  Corner next;
  Rgb rho;
  float sigma = 0;
};

Scatter scatterAt(const ShadingScene& scene, const Corner& c, const RayHit& h, float far) {
  Scatter s;
  s.t = h.valid() ? h.t : far;
  if (!h.valid()) return s;
  const Vec3 p = c.org + c.dir * h.t;
  s.material = scene.leafMaterial[h.leaf];
  s.front = dot(h.ng, c.dir) < 0;
  const Material& m = scene.materials[s.material];
  if (!isCausticScatterer(m) || !isFinite(p) || !isFinite(h.ns)) return s;
  const Vec3 w = -c.dir;  // toward where the light came from
  Vec3 next;
  if (m.type == MaterialType::Dielectric) {
    float etaRel;
    const float cosI = dot(w, h.ns);
    const float f = fresnelDielectric(cosI, m.eta.x);
    if (refract(w, h.ns, m.eta.x, next, etaRel)) {
      s.event = Event::Refract;
      s.rho = Rgb{1, 1, 1} * (1 - f);
    } else {
      s.event = Event::Reflect;
      next = reflect(w, cosI >= 0 ? h.ns : -h.ns);
      s.rho = {1, 1, 1};
    }
  } else {
    const Vec3 n = dot(h.ns, w) >= 0 ? h.ns : -h.ns;
    next = reflect(w, n);
    s.event = Event::Reflect;
    if (m.type == MaterialType::Conductor) {
      s.rho = fresnelConductor(dot(w, n), m.eta, m.k);
    } else {
      s.rho = m.specular.at(h.u, h.v);
      s.sigma = GaussianLobe{s.rho, m.sigma}.smooth() ? 0.0f : m.sigma;
    }
  }
  next = normalize(next);
  // The new direction must leave the true surface on the side the event claims: a shading
  // normal past a silhouette would send it through the surface.
  const float side = dot(h.ng, next) * dot(h.ng, w);
  if (!isFinite(next) || next == Vec3{} || (s.event == Event::Reflect ? !(side > 0) : !(side < 0))) {
    s.event = Event::Stop;
    return s;
  }
  const float offset = PathTracer::originOffset(scene.leafSide[h.leaf], scene.leafDicingError[h.leaf], h.level, p, c.org);
  const SurfaceHit at{p, h.ng, offset};
  s.next = {at.originToward(next), next, c.width + h.t * c.spread, c.spread, h.leaf, h.level};
  return s;
}

bool coaxial(const Vec3 (&d)[3]) {
  const Vec3 c = normalize(d[0] + d[1] + d[2]);
  for (const Vec3& di : d)
    if (!(dot(di, c) >= kCoaxialCos)) return false;
  return true;
}

}  // namespace

std::vector<BeamSegment> traceBeams(const ShadingScene& scene, const BeamSeeds& seeds, int maxDepth, float far,
                                    size_t raysPerTrace, const TraceRays& trace, BeamTraceStats& stats) {
  const size_t nv = seeds.org.size(), nt = seeds.triangles.size();
  stats.generatorTriangles = nt;
  std::vector<Corner> corners(nv);
  for (size_t i = 0; i < nv; ++i)
    corners[i] = {seeds.org[i], seeds.dir[i], seeds.coneWidth[i], seeds.coneSpread[i], kNoLeaf, 0};
  std::vector<uint8_t> cornerLive(nv, 1), triLive(nt, 1);
  std::vector<Rgb> power(seeds.flux);
  std::vector<float> sigma2(nt, 0.0f);
  std::vector<Scatter> scatter(nv);
  std::vector<BeamSegment> segments, generation(nt);
  std::vector<uint8_t> emitted(nt);
  std::vector<Outcome> outcome(nt);
  std::vector<uint32_t> live;
  RayBatch rays;
  for (int g = 0; g <= maxDepth; ++g) {
    live.clear();
    for (uint32_t i = 0; i < nv; ++i)
      if (cornerLive[i]) live.push_back(i);
    if (live.empty()) break;
    stats.generations = g + 1;
    // One generation of corner rays, in chunks the engine's budget holds.
    for (size_t first = 0; first < live.size(); first += raysPerTrace) {
      const size_t count = std::min(raysPerTrace, live.size() - first);
      rays.resize(count);
      for (size_t k = 0; k < count; ++k) {
        const Corner& c = corners[live[first + k]];
        rays.set(k, RayKind::Closest, c.org, c.dir, 0.0f, std::numeric_limits<float>::infinity(), c.width, c.spread,
                 uint32_t(k), kNoLeaf, c.fromLeaf, c.fromLevel);
      }
      trace(rays);
      stats.cornerRays += count;
      tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 1024), [&](const auto& r) {
        for (size_t k = r.begin(); k != r.end(); ++k) {
          const uint32_t i = live[first + k];
          scatter[i] = scatterAt(scene, corners[i], rays.hit[k], far);
        }
      });
    }
    // Each live beam: its segment (after a scattering) and whether it goes on.
    tbb::parallel_for(tbb::blocked_range<size_t>(0, nt, 1024), [&](const auto& r) {
      for (size_t t = r.begin(); t != r.end(); ++t) {
        emitted[t] = 0;
        if (!triLive[t]) continue;
        const auto& v = seeds.triangles[t];
        const Scatter* s[3] = {&scatter[v[0]], &scatter[v[1]], &scatter[v[2]]};
        const Vec3 dirs[3] = {corners[v[0]].dir, corners[v[1]].dir, corners[v[2]].dir};
        // A segment all of whose corners left the scene has nothing to light.
        const bool reachesSomething = s[0]->material != kNone || s[1]->material != kNone || s[2]->material != kNone;
        if (g > 0 && reachesSomething) {
          BeamSegment& seg = generation[t];
          for (int i = 0; i < 3; ++i) seg.o[i] = corners[v[i]].org, seg.d[i] = dirs[i], seg.t[i] = s[i]->t;
          seg.power = power[t];
          seg.sigma = std::sqrt(sigma2[t]);
          emitted[t] = 1;
        }
        Outcome o = Outcome::Continue;
        const bool allScatter = s[0]->event != Event::Stop && s[1]->event != Event::Stop && s[2]->event != Event::Stop;
        const bool sameMaterial = s[0]->material == s[1]->material && s[1]->material == s[2]->material;
        if (g >= maxDepth) o = Outcome::End;
        else if (!sameMaterial || !allScatter) o = sameMaterial && s[0]->event == Event::Stop && s[1]->event == Event::Stop &&
                                                       s[2]->event == Event::Stop ? Outcome::End : Outcome::Mixed;
        else if (s[0]->front != s[1]->front || s[1]->front != s[2]->front) o = Outcome::Silhouette;
        else if (s[0]->event != s[1]->event || s[1]->event != s[2]->event) o = Outcome::Tir;
        else {
          const Vec3 next[3] = {s[0]->next.dir, s[1]->next.dir, s[2]->next.dir};
          if (!coaxial(next)) o = Outcome::Divergent;
        }
        outcome[t] = o;
        if (o == Outcome::Continue) {
          power[t] = power[t] * ((s[0]->rho + s[1]->rho + s[2]->rho) * (1.0f / 3));
          const float sg = (s[0]->sigma + s[1]->sigma + s[2]->sigma) / 3;
          sigma2[t] += sg * sg;
        } else {
          triLive[t] = 0;
        }
      }
    });
    std::fill(cornerLive.begin(), cornerLive.end(), 0);
    for (size_t t = 0; t < nt; ++t) {
      if (emitted[t] && maxComponent(generation[t].power) > 0) segments.push_back(generation[t]);
      switch (outcome[t]) {
        case Outcome::Mixed: ++stats.stoppedMixed; break;
        case Outcome::Silhouette: ++stats.stoppedSilhouette; break;
        case Outcome::Tir: ++stats.stoppedTir; break;
        case Outcome::Divergent: ++stats.stoppedDivergent; break;
        default: break;
      }
      if (triLive[t])
        for (uint32_t i : seeds.triangles[t]) cornerLive[i] = 1;
    }
    for (uint32_t i = 0; i < nv; ++i)
      if (cornerLive[i]) corners[i] = scatter[i].next;
    std::fill(outcome.begin(), outcome.end(), Outcome::End);
  }
  stats.segments = segments.size();
  return segments;
}

}  // namespace rayes
