#include "shading/path_tracer.h"
#include <algorithm>
#include <cmath>
#include <numbers>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include "core/box.h"
#include "core/rng.h"
#include "shading/bsdf.h"
#include "shading/sampling.h"

namespace rayes {
namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();

// Random-number dimensions of one path vertex.
enum Dim : uint32_t { kPixelX = 0, kPixelY = 1, kLightPick = 2, kLightU = 3, kLightV = 4,
                      kBsdfU = 5, kBsdfV = 6, kRoulette = 7, kLensU = 8, kLensV = 9, kTime = 10, kBsdfLobe = 11 };

struct PathIds { uint32_t pixel, sample; };
PathIds idsOf(uint64_t id, uint32_t pixels) {
  return {static_cast<uint32_t>(id % pixels), static_cast<uint32_t>(id / pixels)};
}
}  // namespace

// The offset is a bound, not a guess: how far the origin may lie on the wrong side of the
// surface it leaves, along the geometric normal.
//   Dicing: the micro-triangle hit at level m lies within C / 4^m of the true surface
//   (Patch::dicingErrorCoefficient; 0 for planar patches). The ray sees its own leaf at that
//   same level, but neighbours and emitters are the true surface diced at their own levels.
//   Rounding: p = o + t d with t from the watertight test. Its sheared-space t is a sum of the
//   vertices' distances along the ray weighted by non-negative barycentrics, so t |d| is off by
//   a few gamma of |p - o| + side; the vertices themselves are evaluations off the surface by
//   a few gamma of |p| + side; o + t d rounds by u (|o| + |p|). With |p - o| <= |p| + |o| (and
//   sqrt 3 between the norms) all of it is below gamma(32) (|p| + |o| + side), max norms.
// Computed in double so no input overflows on the way; an infinite or NaN C (a broken patch)
// falls back to the rounding term; the result is clamped to the largest float.
float PathTracer::originOffset(float side, float errorCoefficient, int level, Vec3 p, Vec3 from) {
  const double dicing = double(errorCoefficient) * std::ldexp(1.0, -2 * level);  // C / 4^level
  const double magnitude = double(maxComponent(vabs(p))) + double(maxComponent(vabs(from))) + double(side);
  const double rounding = double(gammaBound(32)) * magnitude + double(std::numeric_limits<float>::min());
  const double offset = std::isfinite(dicing) ? dicing + rounding : rounding;
  return float(std::min(offset, double(std::numeric_limits<float>::max())));
}

float PathTracer::spreadAfterBounce(float incoming, float pdf, bool delta) {
  if (delta) return incoming;
  const float lobe = pdf > 0 ? std::sqrt(1.0f / pdf) : kDiffuseSpread;
  return std::max(incoming, std::min(kDiffuseSpread, lobe));
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
      paths.bsdfPdf[k] = 0;
      paths.bsdfDelta[k] = 1;  // the camera ray: emission it finds is counted in full
      paths.etaScale[k] = 1;
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
  const LightSampler& lights = scene_.lights;
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
      Rgb& T = paths.throughput[k];
      const bool prevDelta = paths.bsdfDelta[k] != 0;
      if (!h.valid()) {
        // Escaped: the lights at infinity (only if the scene has any).
        if (lights.hasInfinite()) {
          const Rgb c = T * lights.escaped(-wo, paths.bsdfPdf[k], prevDelta);
          if (isFinite(c)) paths.radiance[k] += c;
          else stats.nonFinite.fetch_add(1, std::memory_order_relaxed);
        }
        paths.alive[k] = 0;
        continue;
      }
      const Vec3 p = rays.org[cs] + rays.dir[cs] * h.t;
      // A broken hit (non-finite point or normals) ends the path here, before it can reach
      // the film or the AOVs (docs/design.md, invariant 5).
      if (!isFinite(p) || !isFinite(h.ns) || !isFinite(h.ng) || !isFinite(wo)) {
        stats.nonFinite.fetch_add(1, std::memory_order_relaxed);
        paths.alive[k] = 0;
        continue;
      }
      stats.shadedHits.fetch_add(1, std::memory_order_relaxed);

      const uint32_t matId = scene_.leafMaterial[h.leaf];
      const Material& mat = scene_.materials[matId];
      const bool front = dot(h.ns, wo) > 0;
      const float woNg = dot(h.ng, wo);

      // Emission found by this ray: MIS-weighted against light sampling unless the ray came
      // from the camera or a delta lobe.
      if (mat.emits() && (front || mat.twoSided)) {
        float w = 1;
        if (!prevDelta) {
          const float dist = h.t * length(rays.dir[cs]);
          w = powerHeuristic(paths.bsdfPdf[k], lights.patchPdf(lights.patchLightOfLeaf(h.leaf), h.u, h.v, -wo, dist));
        }
        const Rgb c = T * mat.emission * w;
        if (isFinite(c)) paths.radiance[k] += c;
        else stats.nonFinite.fetch_add(1, std::memory_order_relaxed);
      }
      const bool reflects = !mat.reflectsNothing();
      const Bsdf bsdf = reflects ? mat.bsdfAt(h.u, h.v) : Bsdf{};
      if (bounce == 0) {
        paths.aov[k].hitSurface = true;
        paths.aov[k].depth = h.t;
        paths.aov[k].normal = front ? h.ns : -h.ns;
        paths.aov[k].lod = h.level;
        paths.aov[k].albedo = reflects ? bsdf.reflectance() : Rgb{};
        paths.aov[k].materialId = int32_t(matId);
      }
      if (int(bounce) >= scene_.integrator.maxDepth || !reflects) { paths.alive[k] = 0; continue; }

      const PathIds ids = idsOf(paths.first + k, pixels);
      const RngKey key{ids.pixel, ids.sample, bounce + 1, scene_.integrator.seed};
      const float offset = originOffset(scene_.leafSide[h.leaf], scene_.leafDicingError[h.leaf], h.level, p, rays.org[cs]);
      const float width = rays.coneWidth[cs] + h.t * rays.coneSpread[cs];
      // Reflection-only models see the side the viewer is on; a transmitting one keeps the
      // patch normal as "outside".
      const ShadingFrame frame(bsdf.transmits() ? h.ns : (front ? h.ns : -h.ns));
      const Vec3 woL = frame.toLocal(wo);
      // A direction must leave on the true surface's side that its local frame claims:
      // reflection stays on the viewer's side of the geometric normal, transmission crosses.
      // Otherwise it is the light leak of shading normals at silhouettes: no contribution.
      auto consistent = [&](Vec3 wi, Vec3 wiL) {
        const float a = dot(h.ng, wi) * woNg;
        return wiL.z * woL.z > 0 ? a > 0 : a < 0;
      };
      auto originToward = [&](Vec3 wi) { return p + (dot(h.ng, wi) >= 0 ? h.ng : -h.ng) * offset; };

      // Next-event estimation.
      LightSample ls;
      if (!bsdf.isDelta() &&
          lights.sample(p, sampleUniform(key, kLightPick), sampleUniform(key, kLightU), sampleUniform(key, kLightV), ls)) {
        const Vec3 wiL = frame.toLocal(ls.wi);
        const Rgb f = bsdf.eval(woL, wiL);
        if (!isBlack(f) && !isBlack(ls.radiance) && consistent(ls.wi, wiL)) {
          const float w = ls.delta ? 1.0f : powerHeuristic(ls.pdf, bsdf.pdf(woL, wiL));
          const Rgb c = T * f * ls.radiance * (std::fabs(wiL.z) * w / ls.pdf);
          if (!isFinite(c)) {
            stats.nonFinite.fetch_add(1, std::memory_order_relaxed);
          } else if (!isBlack(c)) {
            // The segment from the offset origin to the light point, not a ray from p along
            // ls.wi: a ray of length ls.distance from the offset origin would end beyond the
            // light and find whatever lies just behind it. An emitter's point is first moved
            // off its own surface toward the receiver by its own offset (at level 0, the
            // largest), so the emitter's neighbours and anything flush with it do not occlude.
            const Vec3 origin = originToward(ls.wi);
            Vec3 dir = ls.wi;
            float tmax = kInf;
            if (std::isfinite(ls.distance)) {
              Vec3 target = ls.point;
              if (ls.leaf != kNoLeaf) {
                const float back = originOffset(scene_.leafSide[ls.leaf], scene_.leafDicingError[ls.leaf], 0, ls.point, ls.point);
                target += ls.normal * (dot(ls.normal, p - ls.point) >= 0 ? back : -back);
              }
              tmax = length(target - origin);
              dir = (target - origin) * (1.0f / tmax);
            }
            // A light point within the offsets of the receiver leaves no segment to test.
            if (tmax > 0 && isFinite(dir) && dot(dir, ls.wi) > 0) {
              paths.shadowContribution[k] = c;
              rays.set(ss, RayKind::Shadow, origin, dir, 0.0f, tmax, width, kDiffuseSpread, k, ls.leaf, h.leaf,
                       h.level, rays.time[cs]);
              ++localEmitted;
              stats.shadowRays.fetch_add(1, std::memory_order_relaxed);
            }
          }
        }
      }

      // Continuation. At the last vertex it only looks for emission, so it is not traced
      // when there is nothing such a ray could find.
      if (int(bounce) + 1 >= scene_.integrator.maxDepth && !lights.hasHittable()) { paths.alive[k] = 0; continue; }
      BsdfSample bs;
      if (!bsdf.sample(woL, sampleUniform(key, kBsdfU), sampleUniform(key, kBsdfV), sampleUniform(key, kBsdfLobe), bs)) {
        paths.alive[k] = 0;
        continue;
      }
      const Vec3 wi = normalize(frame.toWorld(bs.wi));
      if (!consistent(wi, bs.wi) || wi == Vec3{}) { paths.alive[k] = 0; continue; }
      T *= bs.weight;
      paths.bsdfPdf[k] = bs.pdf;
      paths.bsdfDelta[k] = bs.delta ? 1 : 0;
      paths.etaScale[k] *= bs.etaRel * bs.etaRel;
      if (int(bounce) + 1 >= scene_.integrator.rouletteDepth) {
        // Survival by throughput with the radiance scaling of refraction undone, so a path
        // inside glass is not killed for the factor it will regain on the way out.
        const float q = std::min(1.0f, maxComponent(T) * paths.etaScale[k]);
        if (!(sampleUniform(key, kRoulette) < q)) {
          paths.alive[k] = 0;
          stats.rouletteKills.fetch_add(1, std::memory_order_relaxed);
          continue;
        }
        T = T * (1.0f / q);
      }
      if (!isFinite(T)) { stats.nonFinite.fetch_add(1, std::memory_order_relaxed); paths.alive[k] = 0; continue; }
      if (isBlack(T)) { paths.alive[k] = 0; continue; }
      rays.set(cs, RayKind::Closest, originToward(wi), wi, 0.0f, kInf, width,
               spreadAfterBounce(rays.coneSpread[cs], bs.pdf, bs.delta), k, kNoLeaf, h.leaf, h.level, rays.time[cs]);
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
