#include "shading/light_tracer.h"
#include <algorithm>
#include <cmath>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include "core/rng.h"
#include "shading/bsdf.h"
#include "shading/light_path.h"
#include "shading/ray_spawning.h"
#include "shading/sampling.h"
#include "shading/surface_hit.h"

namespace rayes {
namespace {
// Random-number dimensions of one light-path vertex (apart from the path tracer's): 2D ones
// (kLightPoint, kLightDir, kLens, kBsdf) are scrambled Sobol pairs, the others 1D.
// The lens point of a connection (2D); the path's other dimensions are light_path.cpp's.
constexpr uint32_t kLens = 38;

RngKey keyOf(uint64_t id, uint32_t pixels, uint32_t vertex, uint64_t seed) {
  return {static_cast<uint32_t>(id % pixels), static_cast<uint32_t>(id / pixels), vertex, seed};
}

uint32_t pixelOf(const CameraConnection& c, int width) {
  return uint32_t(c.py) * uint32_t(width) + uint32_t(c.px);
}
}  // namespace

LightTracer::LightTracer(const ShadingScene& scene, CausticPaths causticPaths)
    : scene_(scene), causticPaths_(causticPaths), splatsPerPath_(uint32_t(std::max(0, scene.integrator.maxDepth)) + 1) {}

size_t LightTracer::bytesPerPath() const {
  return sizeof(Rgb) + sizeof(Splat) + 2 + splatsPerPath_ * sizeof(Splat);
}

bool LightTracer::writeConnection(uint32_t k, uint32_t vertex, const CameraConnection& c, Rgb value, Vec3 origin,
                                  uint32_t ignoreLeaf, uint32_t fromLeaf, uint8_t fromLevel, float time,
                                  RayBatch& rays) {
  if (isBlack(value) || !isFinite(value)) return false;
  const Vec3 d = c.lens - origin;
  const float dist = length(d);
  if (!(dist > 0) || !std::isfinite(dist)) return false;
  pending_[k] = {pixelOf(c, scene_.width), value};
  pendingVertex_[k] = uint8_t(vertex);
  rays.set(kRaysPerPath * size_t(k) + 1, RayKind::Shadow, origin, d * (1.0f / dist), dist * (1.0f - 1e-4f),
           c.coneWidth, c.coneSpread, ignoreLeaf, fromLeaf, fromLevel, time);
  return true;
}

void LightTracer::start(uint64_t first, uint32_t count, RayBatch& rays) {
  const uint32_t pixels = uint32_t(scene_.width) * uint32_t(scene_.height);
  first_ = first;
  throughput_.resize(count);
  pending_.assign(count, Splat{});
  pendingVertex_.assign(count, 0);
  run_.assign(count, LightRun::AtLight);
  splats_.assign(size_t(count) * splatsPerPath_, Splat{});
  rays.resize(kRaysPerPath * size_t(count));
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, count, 1024), [&](const auto& r) {
    for (uint32_t k = r.begin(); k != r.end(); ++k) {
      const size_t cs = kRaysPerPath * size_t(k), ss = cs + 1;
      rays.ray[cs].kind = rays.ray[ss].kind = RayKind::Inactive;
      const RngKey key = keyOf(first + k, pixels, 0, scene_.integrator.seed);
      LightPathStart start;
      if (!sampleLightPathStart(scene_, key, start)) continue;
      const EmissionSample& e = start.e;
      throughput_[k] = e.weight;
      // The light's own point seen by the camera: Le |cos| W / (pick x area density).
      CameraConnection c;
      const Sample2D lens = sample2D(key, kLens);
      if (e.onSurface && counts(causticPaths_, false) && scene_.camera.connect(e.org, lens.u, lens.v, c)) {
        const Vec3 toLens = normalize(c.lens - e.org);
        const float cosL = dot(e.normal, toLens);
        if (cosL > 0 || e.twoSided)
          writeConnection(k, 0, c, e.radiance * (std::fabs(cosL) * c.importance / e.pdfArea), start.leaving(toLens),
                          e.leaf, kNoLeaf, 0, start.time, rays);
      }
      if (scene_.integrator.maxDepth < 1) continue;
      writeLightPathStart(start, k, cs, rays);
    }
  });
}

size_t LightTracer::shade(uint32_t bounce, RayBatch& rays, ShadeStats& stats) {
  ScopedTimer shadeTimer(stats.shade);
  const uint32_t pixels = uint32_t(scene_.width) * uint32_t(scene_.height);
  const uint32_t n = uint32_t(throughput_.size());
  const uint32_t vertex = bounce + 1;  // the scattering vertex this generation's hits are
  std::atomic<size_t> emitted{0};
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n, 256), [&](const auto& r) {
    size_t localEmitted = 0;
    for (uint32_t k = r.begin(); k != r.end(); ++k) {
      const size_t cs = kRaysPerPath * size_t(k), ss = cs + 1;
      if (rays.ray[ss].kind == RayKind::Shadow && !rays.occluded(ss)) {
        splats_[size_t(k) * splatsPerPath_ + pendingVertex_[k]] = pending_[k];
        stats.splats.fetch_add(1, std::memory_order_relaxed);
      }
      rays.ray[ss].kind = RayKind::Inactive;
      if (rays.ray[cs].kind != RayKind::Closest) continue;
      rays.ray[cs].kind = RayKind::Inactive;
      LightPathHit hit;
      if (!lightPathHit(scene_, rays, cs, stats, hit)) continue;
      const Material& mat = *hit.mat;
      if (mat.reflectsNothing()) continue;
      const Bsdf bsdf = mat.bsdfAt(textureQueryAt(scene_, hit.h));
      const RayHit& h = hit.h;
      const Vec3 p = hit.at.p, wi = hit.wi;
      const SurfaceHit& at = hit.at;
      auto frameFacing = [&](Vec3 w) { return ShadingFrame(bsdf.transmits() || dot(hit.ns, w) > 0 ? hit.ns : -hit.ns); };
      Rgb& T = throughput_[k];
      const RngKey key = keyOf(first_ + k, pixels, vertex, scene_.integrator.seed);
      const LightRun run = run_[k] = nextRun(run_[k], isCausticScatterer(mat));
      const bool counted = counts(causticPaths_, run == LightRun::CausticPath);
      // Nothing this path could still reach would be counted.
      if (causticPaths_ == CausticPaths::Only && run == LightRun::NotCaustic) continue;
      if (causticPaths_ == CausticPaths::Without && run == LightRun::CausticPath) continue;

      // Connection to the camera: the path tracer's BSDF evaluation with the camera as viewer.
      CameraConnection c;
      const Sample2D lens = sample2D(key, kLens);
      if (counted && !bsdf.isDelta() && scene_.camera.connect(p, lens.u, lens.v, c)) {
        const Vec3 wc = normalize(c.lens - p);
        const ShadingFrame frame = frameFacing(wc);
        const Vec3 wcL = frame.toLocal(wc), wiL = frame.toLocal(wi);
        const Rgb f = bsdf.eval(wcL, wiL);
        if (!isBlack(f) && at.consistent(wi, wiL, wc, wcL)) {
          const Rgb value = T * f * (hit.arrival * std::fabs(dot(at.ng, wc)) * c.importance);
          if (!isFinite(value)) {
            stats.nonFinite.fetch_add(1, std::memory_order_relaxed);
          } else if (writeConnection(k, vertex, c, value, at.originToward(wc), kNoLeaf, h.leaf, h.level, rays.timeOf(cs),
                                     rays)) {
            ++localEmitted;
            stats.shadowRays.fetch_add(1, std::memory_order_relaxed);
          }
        }
      }

      // The next segment.
      if (continueLightPath(scene_, hit, bsdf, vertex, key, k, cs, T, rays, stats)) ++localEmitted;
    }
    emitted.fetch_add(localEmitted, std::memory_order_relaxed);
  });
  return emitted.load();
}

void LightTracer::finish(Film& film, ShadeStats& stats) {
  // The film's splat buffer is exact (fixed point): any order of adding gives the same sums.
  for (const Splat& s : splats_)
    if (s.pixel != kNoPixel && film.contains(s.pixel)) film.addSplat(s.pixel, s.value);
  film.countSplatPaths(throughput_.size());
}

}  // namespace rayes
