#include "shading/light_path.h"
#include <algorithm>
#include <cmath>
#include <limits>
#include "shading/ray_spawning.h"
#include "shading/roulette.h"

namespace rayes {
namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();
// 2D ones (kLightPoint, kLightDir, kBsdf) are scrambled Sobol pairs, the others 1D; 38-39 are
// the light tracer's lens (light_tracer.cpp).
enum Dim : uint32_t { kLightPick = 32, kLightPoint = 33, kLightDir = 35, kTime = 37, kBsdf = 40, kBsdfLobe = 42,
                      kRoulette = 43 };
}  // namespace

bool sampleLightPathStart(const ShadingScene& scene, const RngKey& key, LightPathStart& out) {
  const Sample2D point = sample2D(key, kLightPoint), direction = sample2D(key, kLightDir);
  EmissionSample& e = out.e;
  if (!scene.lights.sampleEmission(sample1D(key, kLightPick), point.u, point.v, direction.u, direction.v, e) ||
      isBlack(e.weight))
    return false;
  out.time = scene.camera.timeAt(sample1D(key, kTime));
  out.back = e.onSurface ? originOffset(scene.sideOf(e.leaf), scene.dicingErrorOf(e.leaf), 0, e.org, e.org)
                         : 0.0f;
  return true;
}

void writeLightPathStart(const LightPathStart& s, uint32_t path, size_t cs, RayBatch& rays) {
  rays.set(cs, RayKind::Closest, s.leaving(s.e.dir), s.e.dir, kInf, 0.0f, kDiffuseSpread,
           s.e.leaf, kNoLeaf, 0, s.time);
}

bool lightPathHit(const ShadingScene& scene, const RayBatch& rays, size_t cs, ShadeStats& stats, LightPathHit& out) {
  const RayHit h = rays.hitOf(cs);
  if (!h.valid()) return false;  // left the scene
  const Vec3 d = rays.ray[cs].dir();  // unit: the decoded direction is the ray
  const Vec3 p = rays.ray[cs].org + d * h.t;
  const Vec3 wi = -d;
  if (!isFinite(p) || !isFinite(wi)) {  // the normals are finite: decoded from their codes
    stats.nonFinite.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  stats.shadedHits.fetch_add(1, std::memory_order_relaxed);
  const Vec3 ng = h.ng();
  const float wiNg = dot(ng, wi);
  if (wiNg == 0) return false;
  out.h = h;
  out.wi = wi;
  out.ns = h.ns();
  out.at = {p, ng, originOffset(scene.sideOf(h.leaf), scene.dicingErrorOf(h.leaf), h.level, p, rays.ray[cs].org)};
  out.arrival = std::fabs(dot(out.ns, wi)) / std::fabs(wiNg);
  out.mat = &scene.materials[scene.materialOf(h.leaf)];
  return true;
}

bool continueLightPath(const ShadingScene& scene, const LightPathHit& hit, const Bsdf& bsdf, uint32_t vertex,
                       const RngKey& key, uint32_t path, size_t cs, Rgb& T, RayBatch& rays, ShadeStats& stats) {
  if (int(vertex) >= scene.integrator.maxDepth) return false;
  const RayHit& h = hit.h;
  const ShadingFrame frame(bsdf.transmits() || dot(hit.ns, hit.wi) > 0 ? hit.ns : -hit.ns);
  const Vec3 wiL = frame.toLocal(hit.wi);
  BsdfSample bs;
  const Sample2D bu = sample2D(key, kBsdf);
  if (!bsdf.sampleAdjoint(wiL, bu.u, bu.v, sample1D(key, kBsdfLobe), bs)) return false;
  const Vec3 wo = Ray::traced(frame.toWorld(bs.wi));  // the direction the ray will trace
  const float woNs = std::fabs(bs.wi.z);
  if (!hit.at.consistent(hit.wi, wiL, wo, bs.wi) || wo == Vec3{} || !(woNs > 0)) return false;
  T *= bs.weight * (bs.etaRel * bs.etaRel * hit.arrival * std::fabs(dot(hit.at.ng, wo)) / woNs);
  if (!throughputSurvives(T, int(vertex) >= scene.integrator.rouletteDepth, 1.0f, key, kRoulette, stats))
    return false;
  const float spread = rays.ray[cs].coneSpread(), width = rays.ray[cs].coneWidth + h.t * spread;
  rays.set(cs, RayKind::Closest, hit.at.originToward(wo), wo, kInf, width,
           spreadAfterBounce(spread, bs.pdf, bs.delta), kNoLeaf, h.leaf, h.level,
           rays.timeOf(cs));
  stats.continuationRays.fetch_add(1, std::memory_order_relaxed);
  return true;
}

}  // namespace rayes
