#include "shading/path_tracer.h"
#include <algorithm>
#include <cmath>
#include <numbers>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include "core/rng.h"
#include "shading/sampling.h"

namespace rayes {
namespace {
constexpr float kInvPi = std::numbers::inv_pi_v<float>;
constexpr float kInf = std::numeric_limits<float>::infinity();

// Random-number dimensions of one path vertex.
enum Dim : uint32_t { kPixelX = 0, kPixelY = 1, kLightPick = 2, kLightU = 3, kLightV = 4,
                      kBsdfU = 5, kBsdfV = 6, kRoulette = 7, kLensU = 8, kLensV = 9, kTime = 10 };

struct PathIds { uint32_t pixel, sample; };
PathIds idsOf(uint64_t id, uint32_t pixels) {
  return {static_cast<uint32_t>(id % pixels), static_cast<uint32_t>(id / pixels)};
}
}  // namespace

float PathTracer::originOffset(float side, float errorCoefficient, int level, Vec3 p) {
  const float scale = std::ldexp(1.0f, -2 * level);  // 4^-level, exact
  const float thesis = std::ldexp(side, -level);      // l / 2^level
  const float bound = 2.0f * errorCoefficient * scale;
  const float floor = 1e-5f * side + 1e-6f * maxComponent(vabs(p));
  const float offset = std::max(floor, std::min(thesis, bound));
  return std::isfinite(offset) ? offset : floor;
}

void PathTracer::start(uint64_t first, uint32_t count, PathBatch& paths, RayBatch& rays) const {
  const uint32_t pixels = uint32_t(scene_.width) * uint32_t(scene_.height);
  paths.first = first;
  paths.resize(count);
  rays.resize(2 * size_t(count));
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, count, 1024), [&](const auto& r) {
    for (uint32_t k = r.begin(); k != r.end(); ++k) {
      const PathIds ids = idsOf(first + k, pixels);
      const RngKey key{ids.pixel, ids.sample, 0, scene_.integrator.seed};
      const float px = float(ids.pixel % uint32_t(scene_.width)) + sampleUniform(key, kPixelX);
      const float py = float(ids.pixel / uint32_t(scene_.width)) + sampleUniform(key, kPixelY);
      const CameraRay cr = scene_.camera.generate(px, py, sampleUniform(key, kLensU), sampleUniform(key, kLensV),
                                                  sampleUniform(key, kTime));
      paths.throughput[k] = {1, 1, 1};
      paths.radiance[k] = {0, 0, 0};
      paths.shadowContribution[k] = {0, 0, 0};
      paths.alive[k] = 1;
      paths.aov[k] = PixelSample{};
      rays.set(2 * size_t(k), RayKind::Closest, cr.org, cr.dir, 0.0f, kInf, cr.coneWidth, cr.coneSpread, k, kNoLeaf,
               kNoLeaf, 0, cr.time);
      rays.kind[2 * size_t(k) + 1] = RayKind::Inactive;
    }
  });
}

size_t PathTracer::shade(uint32_t bounce, PathBatch& paths, RayBatch& rays, ShadeStats& stats) {
  ScopedTimer shadeTimer(stats.shade);
  const uint32_t pixels = uint32_t(scene_.width) * uint32_t(scene_.height);
  const size_t n = paths.size();

  // The second sorting step: live paths by (material, leaf) of their hit; misses last.
  {
    ScopedTimer sortTimer(stats.sort);
    order_.clear();
    for (uint32_t k = 0; k < n; ++k) {
      const RayHit& h = rays.hit[2 * size_t(k)];
      const bool traced = rays.kind[2 * size_t(k)] == RayKind::Closest;
      const bool shadowed = rays.kind[2 * size_t(k) + 1] == RayKind::Shadow;
      if (!traced && !shadowed) continue;
      uint64_t key = ~uint64_t(0);
      if (traced && h.valid()) key = (uint64_t(scene_.leafMaterial[h.leaf]) << 32) | h.leaf;
      order_.push_back({key, k});
    }
    tbb::parallel_sort(order_.begin(), order_.end(), [](const SortItem& a, const SortItem& b) {
      return a.key != b.key ? a.key < b.key : a.path < b.path;
    });
  }

  std::atomic<size_t> emitted{0};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, order_.size(), 256), [&](const auto& r) {
    size_t localEmitted = 0;
    for (size_t o = r.begin(); o != r.end(); ++o) {
      const uint32_t k = order_[o].path;
      const size_t cs = 2 * size_t(k), ss = cs + 1;
      // Last generation's shadow ray: its contribution counts if nothing was in the way.
      if (rays.kind[ss] == RayKind::Shadow && !rays.hit[ss].valid())
        paths.radiance[k] += paths.shadowContribution[k];
      rays.kind[ss] = RayKind::Inactive;
      if (rays.kind[cs] != RayKind::Closest) continue;
      rays.kind[cs] = RayKind::Inactive;

      const RayHit h = rays.hit[cs];
      const Vec3 wo = -normalize(rays.dir[cs]);
      if (!h.valid()) { paths.alive[k] = 0; continue; }  // v1 has no environment light
      const Vec3 p = rays.org[cs] + rays.dir[cs] * h.t;
      // A broken hit (non-finite point or normals) ends the path here, before it can reach
      // the film or the AOVs (DESIGN invariant 5).
      if (!isFinite(p) || !isFinite(h.ns) || !isFinite(h.ng) || !isFinite(wo)) {
        stats.nonFinite.fetch_add(1, std::memory_order_relaxed);
        paths.alive[k] = 0;
        continue;
      }
      stats.shadedHits.fetch_add(1, std::memory_order_relaxed);

      const Material& mat = scene_.materials[scene_.leafMaterial[h.leaf]];
      const bool front = dot(h.ns, wo) > 0;
      const Vec3 ns = front ? h.ns : -h.ns;
      const Vec3 ng = dot(h.ng, wo) >= 0 ? h.ng : -h.ng;
      Rgb& T = paths.throughput[k];

      if (bounce == 0) {
        paths.aov[k].hitSurface = true;
        paths.aov[k].depth = h.t;
        paths.aov[k].normal = ns;
        paths.aov[k].lod = h.level;
        if (mat.emits() && (front || mat.twoSided)) paths.radiance[k] += T * mat.emission;
      }
      if (int(bounce) >= scene_.integrator.maxDepth) { paths.alive[k] = 0; continue; }

      const RngKey key{idsOf(paths.first + k, pixels).pixel, idsOf(paths.first + k, pixels).sample,
                       bounce + 1, scene_.integrator.seed};
      const float offset = originOffset(scene_.leafSide[h.leaf], scene_.leafDicingError[h.leaf], h.level, p);
      const Vec3 origin = p + ng * offset;
      const float width = rays.coneWidth[cs] + h.t * rays.coneSpread[cs];
      const Rgb f = mat.albedo * kInvPi;

      // Next-event estimation.
      LightSample ls;
      if ((f.x > 0 || f.y > 0 || f.z > 0) &&
          scene_.lights.sample(sampleUniform(key, kLightPick), sampleUniform(key, kLightU),
                               sampleUniform(key, kLightV), ls)) {
        const Vec3 d = ls.position - origin;
        const float dist2 = dot(d, d);
        const float dist = std::sqrt(dist2);
        const Vec3 wi = dist > 0 ? d * (1.0f / dist) : Vec3{};
        const float cosX = dot(ns, wi);
        float cosY = ls.delta ? 1.0f : -dot(ls.normal, wi);
        if (ls.twoSided) cosY = std::fabs(cosY);
        if (dist > 0 && cosX > 0 && dot(ng, wi) > 0 && cosY > 0) {
          const float pdf = ls.delta ? ls.pickPdf : ls.pickPdf * ls.pdfArea;
          const Rgb c = T * f * ls.radiance * (cosX * cosY / (dist2 * pdf));
          if (!isFinite(c)) {
            stats.nonFinite.fetch_add(1, std::memory_order_relaxed);
          } else if (c.x > 0 || c.y > 0 || c.z > 0) {
            paths.shadowContribution[k] = c;
            rays.set(ss, RayKind::Shadow, origin, wi, 0.0f, dist * (1.0f - 1e-4f), width,
                     kDiffuseSpread, k, ls.leaf, h.leaf, h.level, rays.time[cs]);
            ++localEmitted;
            stats.shadowRays.fetch_add(1, std::memory_order_relaxed);
          }
        }
      }

      // Continuation.
      if (int(bounce) + 1 >= scene_.integrator.maxDepth) { paths.alive[k] = 0; continue; }
      const Vec3 wi = toWorld(sampleCosineHemisphere(sampleUniform(key, kBsdfU), sampleUniform(key, kBsdfV)), ns);
      // Below the true surface though above the shading normal's horizon: the light leak
      // shading normals cause at silhouettes. Ending the path is the unbiased choice.
      if (!(dot(wi, ng) > 0)) { paths.alive[k] = 0; continue; }
      T *= mat.albedo;  // f cos / pdf for a cosine-sampled Lambertian
      if (int(bounce) + 1 >= scene_.integrator.rouletteDepth) {
        const float q = std::min(1.0f, maxComponent(T));
        if (!(sampleUniform(key, kRoulette) < q)) {
          paths.alive[k] = 0;
          stats.rouletteKills.fetch_add(1, std::memory_order_relaxed);
          continue;
        }
        T = T * (1.0f / q);
      }
      if (!isFinite(T)) { stats.nonFinite.fetch_add(1, std::memory_order_relaxed); paths.alive[k] = 0; continue; }
      rays.set(cs, RayKind::Closest, origin, wi, 0.0f, kInf, width, std::max(rays.coneSpread[cs], kDiffuseSpread), k,
               kNoLeaf, h.leaf, h.level, rays.time[cs]);
      ++localEmitted;
      stats.continuationRays.fetch_add(1, std::memory_order_relaxed);
    }
    emitted.fetch_add(localEmitted, std::memory_order_relaxed);
  });
  return emitted.load();
}

void PathTracer::finish(const PathBatch& paths, Film& film, ShadeStats& stats) const {
  const uint64_t pixels = uint64_t(scene_.width) * uint64_t(scene_.height);
  const uint64_t first = paths.first, end = paths.first + paths.size();
  if (first == end) return;
  const uint64_t s0 = first / pixels, s1 = (end - 1) / pixels;
  tbb::parallel_for(tbb::blocked_range<uint64_t>(0, pixels, 4096), [&](const auto& r) {
    for (uint64_t p = r.begin(); p != r.end(); ++p)
      for (uint64_t s = s0; s <= s1; ++s) {
        const uint64_t id = s * pixels + p;
        if (id < first || id >= end) continue;
        PixelSample sample = paths.aov[id - first];
        sample.radiance = paths.radiance[id - first];
        if (!isFinite(sample.radiance)) {
          sample.radiance = {0, 0, 0};
          stats.nonFinite.fetch_add(1, std::memory_order_relaxed);
        }
        film.add(static_cast<uint32_t>(p), sample);
      }
  });
}

}  // namespace rayes
