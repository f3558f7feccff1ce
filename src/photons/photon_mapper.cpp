#include "photons/photon_mapper.h"
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include "core/error.h"
#include "core/memory.h"
#include "photons/photon_map.h"
#include "shading/light_path.h"
#include "shading/path_tracer.h"

namespace rayes {
namespace {

// Gathered photons must lie on a surface facing the same way as the receiver's (cos > this).
constexpr float kSameSurfaceCos = 0.7f;
// pm's gather radii: at most this many r0, and at least r0 over this (more than k coincident
// photons would otherwise get a zero radius and lose their flux).
constexpr float kMaxRadiusOverR0 = 4.0f;
constexpr float kR0OverMinRadius = 64.0f;

class PhotonMapper final : public Integrator, private CausticRadiance {
 public:
  PhotonMapper(const ShadingScene& scene, const PhotonOptions& options)
      : scene_(scene), options_(options), progressive_(options.progressive),
        // Photons leave every kind of light: the estimate alone (Only) keeps no path-traced
        // caustic path, and Without leaves out those of every light.
        pt_(scene, options.causticPaths == CausticPaths::Only
                       ? PathTracer::Options{.causticPaths = CausticPaths::Only, .causticRadiance = this, .causticLights = 0,
                                             .laterGatherProbability = options.laterGatherProbability}
                       : PathTracer::Options{.causticPaths = CausticPaths::Without, .causticRadiance = this,
                                             .causticLights = kAllLights,
                                             .laterGatherProbability = options.laterGatherProbability}) {}

  IntegratorTraits traits() const override { return {.progressive = progressive_, .lightPasses = true, .shadowPairs = true}; }
  uint32_t raysPerPath() const override { return kRaysPerPath; }
  size_t bytesPerPath() const override {
    return std::max(pt_.bytesPerPath(), lightBatchBytesPerPath());
  }
  size_t sortScratchBytesPerPath() const override { return pt_.sortScratchBytesPerPath(); }  // light batches sort none
  static size_t lightBatchBytesPerPath() { return sizeof(Rgb) + sizeof(LightRun) + sizeof(Photon) + 1; }
  // Refuses, before any photon is traced, a map that might not fit: the worst case stores a
  // photon for every light path of the largest map (checkPhotonMemory).
  void prepare(const IntegratorSetup& setup) override {
    checkPhotonMemory(options_, scene_.samplesPerPixel, setup.pathsPerBatch * lightBatchBytesPerPath());
  }
  void start(uint64_t first, uint32_t count, RayBatch& rays) override { pt_.start(first, count, rays); }
  size_t shade(uint32_t bounce, RayBatch& rays, ShadeStats& stats) override { return pt_.shade(bounce, rays, stats); }
  void finish(Film& film, ShadeStats& stats) override { pt_.finish(film, stats); }
  void addFirstHits(RayBatch& rays, Film& film, uint64_t from) override { pt_.addFirstHits(rays, film, from); }
  bool setPixelWindow(const PixelWindow& window) override { return pt_.setPixelWindow(window); }
  int64_t cameraPixelOf(uint64_t id) const override { return pt_.cameraPixelOf(id); }

  IdRange lightPaths(int s0, int s1) const override {
    const uint64_t n = options_.photonsPerSample;
    if (progressive_) return {n * uint64_t(s0), n * uint64_t(s1)};
    return s0 == 0 ? IdRange{0, n * uint64_t(scene_.samplesPerPixel)} : IdRange{};
  }

  void startLight(uint64_t first, uint32_t count, RayBatch& rays) override {
    // A new pass's map replaces the last one, whose camera paths are done: free it first.
    if (pathsThisPass_ == 0) map_ = PhotonMap();
    first_ = first;
    pathsThisPass_ += count;
    throughput_.assign(count, Rgb{});
    run_.assign(count, LightRun::AtLight);
    landed_.assign(count, 0);
    landing_.resize(count);
    rays.resize(kRaysPerPath * size_t(count));
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, count, 1024), [&](const auto& r) {
      for (uint32_t k = r.begin(); k != r.end(); ++k) {
        const size_t cs = kRaysPerPath * size_t(k);
        rays.ray[cs].kind = rays.ray[cs + 1].kind = RayKind::Inactive;
        LightPathStart start;
        if (scene_.integrator.maxDepth < 1 || !sampleLightPathStart(scene_, keyOf(first + k, 0), start)) continue;
        throughput_[k] = start.e.weight;
        writeLightPathStart(start, k, cs, rays);
      }
    });
  }

  size_t shadeLight(uint32_t bounce, RayBatch& rays, ShadeStats& stats) override {
    std::atomic<size_t> emitted{0};
    const uint32_t vertex = bounce + 1;
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, uint32_t(throughput_.size()), 256), [&](const auto& r) {
      size_t local = 0;
      for (uint32_t k = r.begin(); k != r.end(); ++k) {
        const size_t cs = kRaysPerPath * size_t(k);
        if (rays.ray[cs].kind != RayKind::Closest) continue;
        rays.ray[cs].kind = RayKind::Inactive;
        LightPathHit hit;
        if (!lightPathHit(scene_, rays, cs, stats, hit) || hit.mat->reflectsNothing()) continue;
        const LightRun run = run_[k] = nextRun(run_[k], isCausticScatterer(*hit.mat));
        if (run == LightRun::NotCaustic) continue;  // no caustic path can follow
        if (run == LightRun::CausticPath) {
          const Vec3 n = dot(hit.at.ng, hit.wi) > 0 ? hit.at.ng : -hit.at.ng;
          landing_[k] = Photon{hit.at.p, hit.wi, n, throughput_[k], vertex};
          landed_[k] = 1;
          continue;
        }
        const Bsdf bsdf = hit.mat->bsdfAt(textureQueryAt(scene_, hit.h));
        if (continueLightPath(scene_, hit, bsdf, vertex, keyOf(first_ + k, vertex), k, cs, throughput_[k], rays, stats))
          ++local;
      }
      emitted.fetch_add(local, std::memory_order_relaxed);
    });
    return emitted.load();
  }

  void finishLightBatch(ShadeStats& stats) override {
    // In path order: the map is the same for any batching.
    for (size_t k = 0; k < landed_.size(); ++k)
      if (landed_[k]) gathered_.push_back(landing_[k]);
    stats.photonsTraced.fetch_add(throughput_.size(), std::memory_order_relaxed);
  }

  void lightPassDone(ShadeStats& stats) override {
    // Each photon carries its path's flux estimate over the number of paths of its map.
    const float share = pathsThisPass_ > 0 ? float(1.0 / double(pathsThisPass_)) : 0.0f;
    pathsThisPass_ = 0;
    for (Photon& ph : gathered_) ph.power = ph.power * share;
    stats.photonsStored.fetch_add(gathered_.size(), std::memory_order_relaxed);
    map_ = PhotonMap(std::move(gathered_));
    gathered_ = {};
    if (!(r0_ > 0)) {
      r0_ = options_.radius > 0 ? options_.radius : medianNeighbourDistance();
      // ppm's radius of every camera sample, fixed before any is shaded (shading is parallel).
      radius2_.resize(size_t(std::max(1, scene_.samplesPerPixel)));
      for (size_t i = 0; i < radius2_.size(); ++i)
        radius2_[i] = i == 0 ? r0_ * r0_ : radius2_[i - 1] * (float(i) + options_.alpha) / float(i + 1);
    }
    if (!progressive_ && r0_ > 0) {
      const float maxR = kMaxRadiusOverR0 * r0_, minR = r0_ / kR0OverMinRadius;
      map_.setGatherRadii(options_.neighbours, minR * minR, maxR * maxR);
    }
    uint64_t peak = stats.photonMapBytes.load();
    while (map_.bytes() > peak && !stats.photonMapBytes.compare_exchange_weak(peak, map_.bytes())) {}
  }

 private:
  RngKey keyOf(uint64_t id, uint32_t vertex) const {
    const uint64_t pixels = uint64_t(scene_.width) * uint64_t(scene_.height);
    return {uint32_t(id % pixels), uint32_t(id / pixels), vertex, scene_.integrator.seed};
  }
  float medianNeighbourDistance() const {
    if (map_.size() < 2) return 0;
    std::vector<float> d;
    std::vector<uint32_t> near;
    const int k = int(std::min<size_t>(size_t(options_.neighbours), map_.size()));
    const size_t step = std::max<size_t>(1, map_.size() / 64);
    for (size_t i = 0; i < map_.size(); i += step)
      d.push_back(std::sqrt(map_.nearest(map_[i].p, k, std::numeric_limits<float>::max(), near)));
    std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
    const float r = d[d.size() / 2];
    return std::isfinite(r) ? r : 0;
  }

  Rgb radiance(const DiffuseVertex& v) const override {
    if (map_.size() == 0 || !(r0_ > 0)) return {};
    const Vec3 n = dot(v.ng, v.wo) > 0 ? v.ng : -v.ng;
    // The path the photon closes has bounce + vertex scattering events before the light: the
    // path tracer, which pm complements, counts it only within max_depth.
    auto counted = [&](const Photon& ph) {
      return dot(ph.n, n) > kSameSurfaceCos && int(v.bounce + ph.vertex) <= scene_.integrator.maxDepth;
    };
    auto reflected = [&](const Photon& ph) { return v.bsdf->eval(v.woL, v.frame->toLocal(ph.wi)) * ph.power; };
    Rgb sum{};
    if (progressive_) {
      // ppm: a fixed radius per sample, the uniform kernel 1 / (pi r²).
      const float r2 = radius2_[std::min<size_t>(v.sample, radius2_.size() - 1)];
      map_.within(v.p, r2, [&](uint32_t i) {
        if (counted(map_[i])) sum += reflected(map_[i]);
      });
      return r2 > 0 ? sum * float(1.0 / (std::numbers::pi * double(r2))) : Rgb{};
    }
    // pm: each photon's own disk, reaching its k-th nearest other photon (PhotonMap::
    // setGatherRadii), normalised to 1 / (pi r_p²): the sample-point estimate. For a locally
    // uniform density λ (photon positions a Poisson or binomial process, powers and directions
    // independent of them) its mean is exactly λ E[Φ f] whatever k: summed over photons, each
    // disk's indicator over its area integrates to 1 at any radius. The balloon estimate it
    // replaces, the k nearest over pi r_k², has mean k/(k - 1) of that (π r_k² λ is Gamma(k, 1)
    // distributed, E[1/G] = 1/(k - 1)): +3.2 % at k = 32. Besides, a photon's disk integrates to
    // its power, so no flux is made or lost at a caustic's edge (the balloon estimate's radius
    // grows outside the edge and adds flux there: measured 1.063 of the closed form at k = 32).
    // r_p² >= (r0/64)² > 0, so the division is finite; k = 1 is unbiased too but of infinite
    // variance (E[1/(π r_1² λ)] diverges), finite at every point.
    map_.covering(v.p, [&](uint32_t i) {
      const Photon& ph = map_[i];
      if (counted(ph)) sum += reflected(ph) * float(1.0 / (std::numbers::pi * double(map_.gatherRadius2(i))));
    });
    return sum;
  }

  const ShadingScene& scene_;
  PhotonOptions options_;
  bool progressive_;
  PathTracer pt_;
  // The light batch in flight.
  uint64_t first_ = 0;
  std::vector<Rgb> throughput_;
  std::vector<LightRun> run_;
  std::vector<uint8_t> landed_;
  std::vector<Photon> landing_;
  std::vector<Photon> gathered_;  // this pass's photons so far, in id order
  PhotonMap map_;
  uint64_t pathsThisPass_ = 0;
  float r0_ = 0;
  std::vector<float> radius2_;  // ppm: r² per camera sample
};

}  // namespace

uint64_t photonMapPeakBytes(uint64_t photons) { return photons * kPhotonPeakBytes; }

uint64_t largestPhotonMap(const PhotonOptions& options, int samplesPerPixel) {
  if (!options.progressive) return options.photonsPerSample * uint64_t(std::max(1, samplesPerPixel));
  // ppm's passes are the Renderer's progressive schedule: 1, 1, 2, 4, ... samples.
  int largest = 1;
  for (int s0 = 0; s0 < samplesPerPixel;) {
    const int s1 = std::min(samplesPerPixel, s0 + std::max(1, s0));
    largest = std::max(largest, s1 - s0);
    s0 = s1;
  }
  return options.photonsPerSample * uint64_t(largest);
}

void checkPhotonMemory(const PhotonOptions& options, int samplesPerPixel, uint64_t lightBatchBytes) {
  const uint64_t photons = largestPhotonMap(options, samplesPerPixel);
  const char* which = options.progressive ? "ppm's largest pass" : "pm's map";
  // Photons are indexed by 32 bits in the map.
  if (photons > uint64_t(UINT32_MAX))
    throw ResourceError("--photons", std::string(which) + " would trace " + std::to_string(photons) +
                                         " photons; a photon map holds at most 2^32 - 1 (--photons x spp for pm, x the "
                                         "largest pass's samples for ppm)");
  const uint64_t budget = options.memoryBytes > 0 ? options.memoryBytes : processMemoryLimit().bytes / 2;
  if (budget == 0) return;  // no memory limit can be read: nothing to check against
  const uint64_t needed = photonMapPeakBytes(photons) + lightBatchBytes;
  if (needed > budget)
    throw ResourceError("--photons", std::string(which) + " of " + std::to_string(photons) + " photons may need " +
                                         readableBytes(needed) + " (" + std::to_string(kPhotonPeakBytes) +
                                         " bytes per photon if every one is stored, and the light batch) but the "
                                         "photon maps may use " + readableBytes(budget) +
                                         (options.memoryBytes > 0 ? std::string(" (the budget)") : " (half of the memory limit: " + processMemoryLimit().source + ")") + "; lower --photons or --spp");
}

std::unique_ptr<Integrator> makePhotonMapper(const ShadingScene& scene, const PhotonOptions& options) {
  return std::make_unique<PhotonMapper>(scene, options);
}

}  // namespace rayes
