#include "shading/path_tracer.h"
#include <cstdlib>
#include <cstring>
#include <string_view>
#include "shading/roulette.h"
#include <algorithm>
#include <cmath>
#include <numbers>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include "core/box.h"
#include "core/rng.h"
#include "shading/bsdf.h"
#include "shading/footprint.h"
#include "shading/ray_spawning.h"
#include "shading/sampling.h"
#include "shading/surface_hit.h"
#include "shading/volume_tracking.h"

namespace rayes {
namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();

// Random-number dimensions of one path vertex (core/rng.h): pixel, lens, light and BSDF
// positions are 2D low-discrepancy samples, the others 1D.
enum Dim : uint32_t { kPixel = 0, kLightPick = 2, kLight = 3, kBsdf = 5, kRoulette = 7, kLens = 8, kTime = 10,
                      kBsdfLobe = 11, kGather = 12 };

}  // namespace

PathTracer::PathIds PathTracer::idsOf(uint64_t id) const {
  const IdBlocks l = idBlocks();
  const uint64_t b = id / l.perBlock, size = l.pixelsIn(b), r = id - b * l.perBlock;
  return {fullPixel(window(), b * l.block + r % size), static_cast<uint32_t>(r / size)};
}

void PathTracer::start(uint64_t first, uint32_t count, PathBatch& paths, RayBatch& rays) const {
  paths.first = first;
  paths.firstHits = scene_.integrator.firstHitAovs;
  paths.resize(count);
  rays.resize(kRaysPerPath * size_t(count));
  rays.queries = nullptr;  // shade() posts gathers
  prepareMediumTracking(0, paths, rays);
  if (options_.gathersAsLeafQueries) {
    paths.gatherQueries.leaf.assign(count, kNoLeaf);
    paths.gathers.resize(count);
  }
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, count, 1024), [&](const auto& r) {
    for (uint32_t k = r.begin(); k != r.end(); ++k) {
      const PathIds ids = idsOf(first + k);
      const RngKey key{ids.pixel, ids.sample, 0, scene_.integrator.seed};
      const Sample2D film = sample2D(key, kPixel), lens = sample2D(key, kLens);
      const float px = float(ids.pixel % uint32_t(scene_.width)) + film.u;
      const float py = float(ids.pixel / uint32_t(scene_.width)) + film.v;
      const CameraRay cr = scene_.camera.generate(px, py, lens.u, lens.v, sample1D(key, kTime));
      paths.throughput[k] = {1, 1, 1};
      paths.radiance[k] = {0, 0, 0};
      paths.shadowContribution[k] = {0, 0, 0};
      paths.bsdfPdf[k] = 0;
      paths.flags[k] = 0;
      paths.setBsdfDelta(k, true);  // the camera ray: emission it finds is counted in full
      paths.etaScale[k] = 1;
      paths.setCausticRun(k, kNoDiffuseYet);
      rays.set(kRaysPerPath * size_t(k), RayKind::Closest, cr.org, cr.dir, kInf, cr.coneWidth, cr.coneSpread, kNoLeaf,
               kNoLeaf, 0, cr.time);
      rays.ray[kRaysPerPath * size_t(k) + 1].kind = RayKind::Inactive;
    }
  });
}

namespace {

// Adds a contribution where it is finite; counts it otherwise (docs/design.md, invariant 5).
void addFinite(Rgb& sum, Rgb c, ShadeStats& stats) {
  if (isFinite(c)) sum += c;
  else stats.nonFinite.fetch_add(1, std::memory_order_relaxed);
}

// What the steps of shading one path's hit share.
struct Vertex {
  uint32_t k;        // the path
  size_t cs, ss;     // its closest-hit and shadow ray slots
  RayHit h;
  Vec3 wo;           // unit, toward where the ray came from
  bool front;        // wo is on the shading normal's side
  SurfaceHit at;
  float width;       // the ray's footprint at the hit
  const Material* mat;
  uint32_t matId;
  bool reflects;
  Bsdf bsdf;
};

// Step 2, escaped: the lights at infinity (only if the scene has any).
void gatherEscaped(const LightSampler& lights, uint32_t k, Vec3 wo, uint8_t kinds, PathBatch& paths,
                   ShadeStats& stats) {
  if (!lights.hasInfinite()) return;
  addFinite(paths.radiance[k],
            paths.throughput[k] * lights.escaped(-wo, paths.bsdfPdf[k], paths.bsdfDelta(k), kinds), stats);
}

// Step 2, emission found by this ray: MIS-weighted against light sampling unless the ray came
// from the camera or a delta lobe.
void gatherEmission(const LightSampler& lights, const Vertex& v, const RayBatch& rays, PathBatch& paths,
                    ShadeStats& stats) {
  const Material& mat = *v.mat;
  if (!mat.emits() || !(v.front || mat.twoSided)) return;
  float w = 1;
  if (!paths.bsdfDelta(v.k)) {
    const float dist = v.h.t;  // t is a distance: the ray's direction is unit
    w = powerHeuristic(paths.bsdfPdf[v.k],
                       lights.patchPdf(lights.patchLightOfLeaf(v.h.leaf), v.h.u, v.h.v, -v.wo, dist));
  }
  addFinite(paths.radiance[v.k], paths.throughput[v.k] * mat.emission * w, stats);
}

// Step 3's first-hit AOVs (camera rays only).
void recordFirstHit(const Vertex& v, FirstHitRecord& aov) {
  aov.flags = FirstHitRecord::kHitSurface | (v.front ? 0 : FirstHitRecord::kNormalFlipped);
  aov.depth = v.h.t;
  aov.normalCode = v.h.nsCode;
  aov.lod = v.h.level;
  aov.albedo = v.reflects ? v.bsdf.reflectance() : Rgb{};
  aov.materialId = int32_t(v.matId);
}

// The shadow ray's segment from `origin` (near the receiver `p`) to the light sample: the segment
// to the light point, not a ray from p along ls.wi: a ray of length ls.distance from the offset
// origin would end beyond the light and find whatever lies just behind it. An emitter's point
// is first moved off its own surface toward the receiver by its own offset (at level 0, the
// largest), so the emitter's neighbours and anything flush with it do not occlude. False when a
// light point within the offsets of the receiver leaves no segment to test.
bool shadowSegment(const ShadingScene& scene, Vec3 origin, Vec3 p, const LightSample& ls, Vec3& dir, float& tmax) {
  dir = ls.wi;
  tmax = kInf;
  if (std::isfinite(ls.distance)) {
    Vec3 target = ls.point;
    if (ls.leaf != kNoLeaf) {
      const float back =
          originOffset(scene.sideOf(ls.leaf), scene.dicingErrorOf(ls.leaf), 0, ls.point, ls.point);
      target += ls.normal * (dot(ls.normal, p - ls.point) >= 0 ? back : -back);
    }
    tmax = length(target - origin);
    dir = (target - origin) * (1.0f / tmax);
  }
  return tmax > 0 && isFinite(dir) && dot(dir, ls.wi) > 0;
}

// The transmittance of a shadow segment through the scene's media by ratio tracking (1 without
// media: no work). Keyed by the vertex, so the same bits for any thread count.
float mediumTransmittance(const ShadingScene& scene, Vec3 origin, Vec3 dir, float tmax, const RngKey& key,
                          ShadeStats& stats) {
  if (scene.media.empty()) return 1;
  ScopedTimer timer(stats.volume);
  TrackingRng rng{key, kTransmittanceDimensions};
  TrackingCounts counts;
  // Delta tracking's estimate is 1 or 0 (a real collision before the light); ratio tracking's
  // the product of 1 − ρ/m over the tentative collisions: the same mean, less variance.
  const float T = walkTransmittance(scene.media, origin, dir, tmax, scene.integrator.deltaTransmittance, rng, counts,
                                    scene.volumeCache.get());
  stats.transmittanceEstimates.fetch_add(1, std::memory_order_relaxed);
  stats.densityLookups.fetch_add(counts.lookups, std::memory_order_relaxed);
  stats.brickCellsWalked.fetch_add(counts.cells, std::memory_order_relaxed);
  return T;
}

// Step 4, next-event estimation: one light sampled, its MIS-weighted contribution stored and a
// shadow ray written into slot 2k+1. Returns whether a ray was written.
bool writeShadowRay(const ShadingScene& scene, const Vertex& v, const ShadingFrame& frame, Vec3 woL, const RngKey& key,
                    uint8_t kinds, PathBatch& paths, RayBatch& rays, ShadeStats& stats) {
  const LightSampler& lights = scene.lights;
  LightSample ls;
  const Sample2D lu = sample2D(key, kLight);
  if (v.bsdf.isDelta() || !lights.sample(v.at.p, sample1D(key, kLightPick), lu.u, lu.v, ls)) return false;
  if (!(ls.kind & kinds)) return false;  // a light whose paths here are not counted
  const Vec3 wiL = frame.toLocal(ls.wi);
  const Rgb f = v.bsdf.eval(woL, wiL);
  if (isBlack(f) || isBlack(ls.radiance) || !v.at.consistent(ls.wi, wiL, v.wo, woL)) return false;
  const float w = ls.delta ? 1.0f : powerHeuristic(ls.pdf, v.bsdf.pdf(woL, wiL));
  Rgb c = paths.throughput[v.k] * f * ls.radiance * (std::fabs(wiL.z) * w / ls.pdf);
  if (!isFinite(c)) {
    stats.nonFinite.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  if (isBlack(c)) return false;
  const Vec3 origin = v.at.originToward(ls.wi);
  Vec3 dir;
  float tmax;
  // Its transmittance through media multiplies it when it arrives (shadowTransmittance).
  if (!shadowSegment(scene, origin, v.at.p, ls, dir, tmax)) return false;
  paths.shadowContribution[v.k] = c;
  rays.set(v.ss, RayKind::Shadow, origin, dir, tmax, v.width, kDiffuseSpread, ls.leaf, v.h.leaf, v.h.level,
           rays.timeOf(v.cs));
  stats.shadowRays.fetch_add(1, std::memory_order_relaxed);
  return true;
}

// Step 5, continuation: the BSDF sampled into slot 2k, Russian roulette on the throughput
// times eta². Returns whether the path goes on (a ray was written).
bool writeContinuation(const ShadingScene& scene, uint32_t bounce, const Vertex& v, const ShadingFrame& frame, Vec3 woL,
                       const RngKey& key, PathBatch& paths, RayBatch& rays, ShadeStats& stats) {
  // At the last vertex it only looks for emission, so it is not traced when there is nothing
  // such a ray could find.
  if (int(bounce) + 1 >= scene.integrator.maxDepth && !scene.lights.hasHittable()) return false;
  BsdfSample bs;
  const Sample2D bu = sample2D(key, kBsdf);
  if (!v.bsdf.sample(woL, bu.u, bu.v, sample1D(key, kBsdfLobe), bs)) return false;
  const Vec3 wi = Ray::traced(frame.toWorld(bs.wi));  // the direction the ray will trace
  if (!v.at.consistent(wi, bs.wi, v.wo, woL) || wi == Vec3{}) return false;
  const uint32_t k = v.k;
  Rgb& T = paths.throughput[k];
  T *= bs.weight;
  paths.bsdfPdf[k] = bs.pdf;
  paths.setBsdfDelta(k, bs.delta);
  paths.etaScale[k] *= bs.etaRel * bs.etaRel;
  // Survival by throughput with the radiance scaling of refraction undone, so a path inside
  // glass is not killed for the factor it will regain on the way out.
  if (!throughputSurvives(T, int(bounce) + 1 >= scene.integrator.rouletteDepth, paths.etaScale[k], key, kRoulette,
                          stats))
    return false;
  rays.set(v.cs, RayKind::Closest, v.at.originToward(wi), wi, kInf, v.width,
           spreadAfterBounce(rays.ray[v.cs].coneSpread(), bs.pdf, bs.delta), kNoLeaf, v.h.leaf, v.h.level,
           rays.timeOf(v.cs));
  stats.continuationRays.fetch_add(1, std::memory_order_relaxed);
  return true;
}

}  // namespace

// The steps of one path's generation (docs/architecture.md, "Shading"); returns the rays written.
size_t PathTracer::shadePath(uint32_t bounce, uint32_t k, PathBatch& paths, RayBatch& rays, ShadeStats& stats,
                             FirstHitRecord* firstHit) const {
  const size_t cs = kRaysPerPath * size_t(k), ss = cs + 1;
  // 1. Last generation's shadow ray: its contribution counts if nothing was in the way.
  if (rays.ray[ss].kind == RayKind::Shadow && !rays.occluded(ss)) {
    if (scene_.media.empty()) paths.radiance[k] += paths.shadowContribution[k];
    else paths.radiance[k] += paths.shadowContribution[k] * shadowTransmittance(bounce, k, paths, rays, stats);
  }
  rays.ray[ss].kind = RayKind::Inactive;
  if (rays.ray[cs].kind != RayKind::Closest) return 0;
  rays.ray[cs].kind = RayKind::Inactive;

  // 2. What the ray found: the lights at infinity, or a surface and its emission.
  const RayHit h = rays.hitOf(cs);
  const Vec3 d = rays.ray[cs].dir();  // unit: the decoded direction is the ray
  const Vec3 wo = -d;
  // Light found now arrives along a caustic path when the path stands in a diffuse -> caustic chain.
  const uint8_t countedNow = countedLights(paths.causticRun(k) == kInCausticChain);
  // 2a. In a scene with media, the ray's free flight (delta tracking) up to the surface it found:
  // a real collision before it makes a scattering vertex there instead.
  if (!scene_.media.empty()) {
    const PathIds ids = idsOf(paths.first + k);
    const RngKey key{ids.pixel, ids.sample, bounce + 1, scene_.integrator.seed};
    Collision c;
    if (paths.media && paths.media->tracked) {
      // The engine ran the brick leaves: a collision is the hit on a brick's leaf.
      if (h.valid() && paths.media->isBrick(h.leaf))
        c = {h.t, int32_t(scene_.bricks.mediumOfLeaf(h.leaf - scene_.firstBrickLeaf))};
    } else {
      ScopedTimer timer(stats.volume);
      TrackingRng rng{key, kFreeFlightDimensions};
      TrackingCounts counts;
      c = sampleCollision(scene_.media, rays.ray[cs].org, d, h.valid() ? h.t : kInf, rng, counts,
                          scene_.volumeCache.get());
      stats.densityLookups.fetch_add(counts.lookups, std::memory_order_relaxed);
      stats.brickCellsWalked.fetch_add(counts.cells, std::memory_order_relaxed);
    }
    // Emission gathered over the free flight (volume_tracking.h: its length supplies the
    // transmittance); a scene whose media do not emit does none of this.
    if (countedNow && scene_.mediaEmit) {
      ScopedTimer timer(stats.volume);
      TrackingRng rng{key, kEmissionDimensions};
      TrackingCounts counts;
      const float tEnd = c.medium >= 0 ? c.t : h.valid() ? h.t : kInf;
      addFinite(paths.radiance[k],
                paths.throughput[k] * emissionAlong(scene_.media, rays.ray[cs].org, d, tEnd, rng, counts,
                                                    scene_.volumeCache.get()),
                stats);
      stats.emissionLookups.fetch_add(counts.lookups, std::memory_order_relaxed);
    }
    if (c.medium >= 0) return shadeMediumVertex(bounce, k, c.t, *scene_.media[size_t(c.medium)], key, paths, rays, stats);
  }
  if (!h.valid()) {
    if (countedNow) gatherEscaped(scene_.lights, k, wo, countedNow, paths, stats);
    return 0;
  }
  const Vec3 p = rays.ray[cs].org + d * h.t;
  // A broken hit (non-finite point) ends the path here, before it can reach the film or the
  // AOVs (docs/design.md, invariant 5). The normals are finite: decoded from their codes.
  if (!isFinite(p) || !isFinite(wo)) {
    stats.nonFinite.fetch_add(1, std::memory_order_relaxed);
    return 0;
  }
  stats.shadedHits.fetch_add(1, std::memory_order_relaxed);
  const Vec3 ng = h.ng(), ns = h.ns();
  Vertex v{k, cs, ss, h, wo, dot(ns, wo) > 0, {p, ng, 0.0f}, 0.0f, nullptr, 0, false, Bsdf{}};
  v.matId = scene_.materialOf(h.leaf);
  v.mat = &scene_.materials[v.matId];
  if (countedNow & kPatchLight) gatherEmission(scene_.lights, v, rays, paths, stats);

  // 3. The material at the hit becomes one BSDF.
  v.reflects = !v.mat->reflectsNothing();
  if (v.reflects) {
    // The camera ray's cone is a whole pixel, which the pixel's samples already average over.
    const float widthScale = bounce == 0 ? cameraFootprintScale(scene_.samplesPerPixel) : 1.0f;
    v.bsdf = v.mat->bsdfAt(textureQueryAt(scene_, rays.ray[cs], h, rays.derivativesOf(cs), widthScale));
  }
  if (firstHit) recordFirstHit(v, *firstHit);
  if (int(bounce) >= scene_.integrator.maxDepth || !v.reflects) {
    return 0;
  }
  const PathIds ids = idsOf(paths.first + k);
  const RngKey key{ids.pixel, ids.sample, bounce + 1, scene_.integrator.seed};
  v.at.offset = originOffset(scene_.sideOf(h.leaf), scene_.dicingErrorOf(h.leaf), h.level, p, rays.ray[cs].org);
  v.width = rays.ray[cs].coneWidth + h.t * rays.ray[cs].coneSpread();
  // Reflection-only models see the side the viewer is on; a transmitting one keeps the
  // patch normal as "outside".
  const ShadingFrame frame(v.bsdf.transmits() ? ns : (v.front ? ns : -ns));
  const Vec3 woL = frame.toLocal(wo);

  // 4. Caustic paths: where this vertex puts the path, and the caustic estimate at a diffuse one.
  uint8_t run = paths.causticRun(k);
  if (!isCausticScatterer(*v.mat)) {
    // After the first diffuse vertex, the gather survives a roulette (Options::laterGatherProbability).
    const float q = run == kNoDiffuseYet ? 1.0f : options_.laterGatherProbability;
    run = kAfterDiffuse;
    if (options_.causticRadiance) {
      const bool gathers = q >= 1 || sample1D(key, kGather) < q;
      (gathers ? stats.gathers : stats.gathersSkipped).fetch_add(1, std::memory_order_relaxed);
      const Rgb weight = q >= 1 ? paths.throughput[k] : paths.throughput[k] * (1 / q);
      if (gathers && options_.gathersAsLeafQueries) {
        paths.gatherQueries.leaf[k] = h.leaf;
        paths.gathers[k] = {p, ng, wo, woL, frame.n, v.bsdf, ids.sample, bounce, weight, Rgb{}};
      } else if (gathers) {
        const DiffuseVertex dv{p, ng, wo, woL, &frame, &v.bsdf, ids.sample, h.leaf, bounce, uint32_t(k)};
        addFinite(paths.radiance[k], weight * options_.causticRadiance->radiance(dv), stats);
      }
    }
  } else if (run != kNoDiffuseYet) {
    run = kInCausticChain;
  }
  paths.setCausticRun(k, run);
  const uint8_t countedNext = countedLights(run == kInCausticChain);

  // 5. Next-event estimation (not from lights whose paths are not counted here); 6. the continuation.
  const size_t shadow =
      countedNext && writeShadowRay(scene_, v, frame, woL, key, countedNext, paths, rays, stats) ? 1 : 0;
  if (writeContinuation(scene_, bounce, v, frame, woL, key, paths, rays, stats)) return shadow + 1;
  return shadow;
}

// A scattering vertex at t along path k's closest ray, in medium m: the throughput times the
// scattering albedo (absorption as a weight, not a random end), next-event estimation with the
// phase function and the shadow segment's ratio-tracked transmittance, and a continuation
// sampled exactly from the phase function (weight 1; its density is the MIS density). For the
// caustic-path bookkeeping the vertex counts as diffuse. No AOVs: the first-hit AOVs are
// surfaces'.
size_t PathTracer::shadeMediumVertex(uint32_t bounce, uint32_t k, float t, const Medium& m, const RngKey& key,
                                     PathBatch& paths, RayBatch& rays, ShadeStats& stats) const {
  const size_t cs = kRaysPerPath * size_t(k), ss = cs + 1;
  stats.mediumCollisions.fetch_add(1, std::memory_order_relaxed);
  const Ray ray = rays.ray[cs];
  const Vec3 in = ray.dir(), p = ray.org + in * t;  // unit: the decoded direction is the ray
  if (int(bounce) >= scene_.integrator.maxDepth || !isFinite(p) || !isFinite(in)) {
    return 0;
  }
  const float g = m.coefficients().g;
  Rgb& T = paths.throughput[k];
  T *= m.coefficients().albedo();
  if (isBlack(T)) {  // a purely absorbing medium: nothing more can reach the film
    return 0;
  }
  paths.setCausticRun(k, kAfterDiffuse);
  const uint8_t kinds = countedLights(false);
  const float width = ray.coneWidth + t * ray.coneSpread();
  size_t written = 0;

  // Next-event estimation.
  const LightSampler& lights = scene_.lights;
  LightSample ls;
  const Sample2D lu = sample2D(key, kLight);
  if (kinds && lights.sample(p, sample1D(key, kLightPick), lu.u, lu.v, ls) && (ls.kind & kinds) &&
      !isBlack(ls.radiance)) {
    const float phase = henyeyGreenstein(dot(in, ls.wi), g);
    const float w = ls.delta ? 1.0f : powerHeuristic(ls.pdf, phase);
    Rgb c = T * ls.radiance * (phase * w / ls.pdf);
    Vec3 dir;
    float tmax;
    if (!isFinite(c)) {
      stats.nonFinite.fetch_add(1, std::memory_order_relaxed);
    } else if (!isBlack(c) && shadowSegment(scene_, p, p, ls, dir, tmax)) {
      paths.shadowContribution[k] = c;  // times the segment's transmittance when it arrives
      rays.set(ss, RayKind::Shadow, p, dir, tmax, width, kDiffuseSpread, ls.leaf, kNoLeaf, 0, rays.timeOf(cs));
      stats.shadowRays.fetch_add(1, std::memory_order_relaxed);
      written = 1;
    }
  }

  // Continuation (as writeContinuation: not traced at the last vertex when nothing could be found).
  if (int(bounce) + 1 >= scene_.integrator.maxDepth && !lights.hasHittable()) {
    return written;
  }
  const Sample2D bu = sample2D(key, kBsdf);
  const Vec3 wi = sampleHenyeyGreenstein(in, g, bu.u, bu.v);
  const float pdf = henyeyGreenstein(dot(in, wi), g);
  paths.bsdfPdf[k] = pdf;
  paths.setBsdfDelta(k, false);
  if (!isFinite(wi) ||
      !throughputSurvives(T, int(bounce) + 1 >= scene_.integrator.rouletteDepth, paths.etaScale[k], key, kRoulette,
                          stats)) {
    return written;
  }
  rays.set(cs, RayKind::Closest, p, wi, kInf, width, spreadAfterBounce(ray.coneSpread(), pdf, false), kNoLeaf, kNoLeaf, 0,
           rays.timeOf(cs));
  stats.continuationRays.fetch_add(1, std::memory_order_relaxed);
  return written + 1;
}

void PathTracer::prepareMediumTracking(uint32_t bounce, PathBatch& paths, RayBatch& rays) const {
  if (scene_.media.empty()) {
    rays.media = nullptr;
    return;
  }
  if (!paths.media) {
    paths.media = std::make_shared<BrickLeafTracker>();
    paths.media->setScene(scene_);
  }
  const uint64_t first = paths.first, seed = scene_.integrator.seed;
  paths.media->prepare(paths.size(), [this, first, seed, bounce](uint32_t slot) {
    const PathIds ids = idsOf(first + slot / kRaysPerPath);
    return RngKey{ids.pixel, ids.sample, slot % kRaysPerPath == 0 ? bounce + 1 : bounce, seed};
  });
  rays.media = paths.media.get();
}

float PathTracer::shadowTransmittance(uint32_t bounce, uint32_t k, const PathBatch& paths, const RayBatch& rays,
                                      ShadeStats& stats) const {
  if (paths.media && paths.media->tracked) {
    stats.transmittanceEstimates.fetch_add(1, std::memory_order_relaxed);
    return paths.media->transmittance(k);
  }
  const PathIds ids = idsOf(paths.first + k);
  const Ray& r = rays.ray[kRaysPerPath * size_t(k) + 1];
  return mediumTransmittance(scene_, r.org, r.dir(), r.tmax, RngKey{ids.pixel, ids.sample, bounce, scene_.integrator.seed},
                             stats);
}

size_t PathTracer::shade(uint32_t bounce, PathBatch& paths, RayBatch& rays, ShadeStats& stats) {
  ScopedTimer shadeTimer(stats.shade);
  if (paths.media) {  // what the engine's brick runs did in the trace just done
    BrickLeafTracker& t = *paths.media;
    stats.densityLookups.fetch_add(t.lookups.exchange(0), std::memory_order_relaxed);
    stats.brickCellsWalked.fetch_add(t.cells.exchange(0), std::memory_order_relaxed);
    stats.volume.add(std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(t.time.seconds())));
    t.time.reset();
  }
  if (options_.gathersAsLeafQueries) {
    addRunGathers(paths, stats);
    gatherRunner_.caustics = options_.causticRadiance;
    gatherRunner_.paths = &paths;
    paths.gatherQueries.runner = &gatherRunner_;
    rays.queries = options_.causticRadiance ? &paths.gatherQueries : nullptr;
  }
  const std::span<const SortItem> order = sortByMaterial(paths, rays, stats);
  const bool firstHits = bounce == 0 && paths.firstHits;
  std::atomic<size_t> emitted{0};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, order.size(), 256), [&](const auto& r) {
    size_t localEmitted = 0;
    for (size_t o = r.begin(); o != r.end(); ++o) {
      const uint32_t k = order[o].path;
      FirstHitRecord first;
      localEmitted += shadePath(bounce, k, paths, rays, stats, firstHits ? &first : nullptr);
      // The hit was read, and a continuation ray written (clearing it): the record takes its
      // bytes until addFirstHits (a miss or a medium vertex leaves no hit: an empty record).
      if (firstHits) std::memcpy(static_cast<void*>(&rays.hitOf(kRaysPerPath * size_t(k))), &first, sizeof first);
    }
    emitted.fetch_add(localEmitted, std::memory_order_relaxed);
  });
  prepareMediumTracking(bounce + 1, paths, rays);
  return emitted.load();
}

// The gathers the last trace() ran, each added to its path's radiance where the direct call
// would have added it: after that vertex's emission, before the next vertex's shadow ray.
void PathTracer::addRunGathers(PathBatch& paths, ShadeStats& stats) const {
  std::vector<uint32_t>& posted = paths.gatherQueries.leaf;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, posted.size(), 4096), [&](const auto& r) {
    for (size_t k = r.begin(); k != r.end(); ++k) {
      if (posted[k] == kNoLeaf) continue;
      const PostedGather& g = paths.gathers[k];
      addFinite(paths.radiance[k], g.throughput * g.radiance, stats);
      posted[k] = kNoLeaf;
    }
  });
}

void PathTracer::GatherRunner::run(uint32_t leaf, std::span<const uint32_t> ids) {
  for (const uint32_t k : ids) {
    PostedGather& g = paths->gathers[k];
    const ShadingFrame frame(g.frameNormal);
    const DiffuseVertex v{g.p, g.ng, g.wo, g.woL, &frame, &g.bsdf, g.sample, leaf, g.bounce, k};
    g.radiance = caustics->radiance(v);
  }
}

// The second sorting step: live paths by (material, leaf) of their hit; misses last.
std::span<const PathTracer::SortItem> PathTracer::sortByMaterial(const PathBatch& paths, RayBatch& rays,
                                                                 ShadeStats& stats) const {
  ScopedTimer sortTimer(stats.sort);
  const size_t n = paths.size();
  const std::span<SortItem> items = rays.sortScratch.take<SortItem>(n);
  size_t live = 0;
  for (uint32_t k = 0; k < n; ++k) {
    const size_t cs = kRaysPerPath * size_t(k);
    const RayHit& h = rays.hitOf(cs);
    const bool traced = rays.ray[cs].kind == RayKind::Closest;
    const bool shadowed = rays.ray[cs + 1].kind == RayKind::Shadow;
    if (!traced && !shadowed) continue;
    // A collision on a brick leaf (a medium vertex) sorts just before the misses.
    const bool brick = paths.media && paths.media->isBrick(h.leaf);
    items[live++] = {traced && h.valid() ? (brick ? kNoHitRank - 1 : shadeRankOf(h.leaf)) : kNoHitRank, k};
  }
  const std::span<SortItem> order = items.first(live);
  // Bench only (bench/texture_cache.sh): RAYES_SHADING_SORT=off shades the paths in id order, to
  // measure what the sort is worth to the texture cache. The image is the same either way:
  // each path touches only its own ray slots.
  static const bool sorted = [] {
    const char* e = std::getenv("RAYES_SHADING_SORT");
    return !(e && std::string_view(e) == "off");
  }();
  if (!sorted) return order;
  tbb::parallel_sort(order.begin(), order.end(), [](const SortItem& a, const SortItem& b) {
    return a.key != b.key ? a.key < b.key : a.path < b.path;
  });
  return order;
}

template <class Add>
void PathTracer::inFilmOrder(uint64_t first, uint64_t end, const Add& add) const {
  if (first >= end) return;
  // The pixels of ids [first, end) (of the window, in its row order): those of the blocks the
  // ids fall in (idsOf's inverse below).
  const IdBlocks l = idBlocks();
  const PixelWindow w = window();
  const uint64_t p0 = first / l.perBlock * l.block, p1 = std::min(l.pixels, ((end - 1) / l.perBlock + 1) * l.block);
  tbb::parallel_for(tbb::blocked_range<uint64_t>(p0, p1, 4096), [&](const auto& r) {
    for (uint64_t p = r.begin(); p != r.end(); ++p) {
      const uint64_t b = p / l.block, size = l.pixelsIn(b), firstId = b * l.perBlock;
      const uint64_t base = firstId + (p - b * l.block);  // the id of (p, sample 0)
      const uint64_t lo = std::max(first, firstId), hi = std::min(end, firstId + l.perBlock);
      const uint64_t s0 = (lo - firstId) / size, s1 = (hi - 1 - firstId) / size;
      const uint32_t pixel = fullPixel(w, p);
      for (uint64_t s = s0; s <= s1; ++s) {
        const uint64_t id = base + s * size;
        if (id < first || id >= end) continue;
        add(pixel, id);
      }
    }
  });
}

void PathTracer::finish(const PathBatch& paths, Film& film, ShadeStats& stats) const {
  const uint64_t first = paths.first;
  inFilmOrder(first, first + paths.size(), [&](uint32_t pixel, uint64_t id) {
    Rgb radiance = paths.radiance[id - first];
    if (!isFinite(radiance)) {
      radiance = {0, 0, 0};
      stats.nonFinite.fetch_add(1, std::memory_order_relaxed);
    }
    film.addRadiance(pixel, radiance);
  });
}

void PathTracer::addFirstHits(const PathBatch& paths, RayBatch& rays, Film& film, uint64_t from) const {
  if (!paths.firstHits) return;
  const uint64_t first = paths.first;
  inFilmOrder(first, first + paths.size(), [&](uint32_t pixel, uint64_t id) {
    RayHit& slot = rays.hitOf(kRaysPerPath * size_t(id - first));
    if (id >= from) {
      FirstHitRecord record;
      std::memcpy(&record, static_cast<const void*>(&slot), sizeof record);
      film.addFirstHit(pixel, record.unpack());
    }
    slot = RayHit{};
  });
}

}  // namespace rayes
