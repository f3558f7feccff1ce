#include "photons/photon_mapper.h"
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include "photons/photon_map.h"
#include "shading/light_path.h"
#include "shading/path_tracer.h"

namespace rayes {
namespace {

// Gathered photons must lie on a surface facing the same way as the receiver's (cos > this).
constexpr float kSameSurfaceCos = 0.7f;
// pm's k-nearest search reaches at most this many r0.
constexpr float kMaxRadiusOverR0 = 4.0f;

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

  IntegratorTraits traits() const override { return {.progressive = progressive_, .lightPasses = true}; }
  uint32_t raysPerPath() const override { return kRaysPerPath; }
  size_t bytesPerPath() const override {
    return std::max(pt_.bytesPerPath(), sizeof(Rgb) + sizeof(LightRun) + sizeof(Photon) + 1);
  }
  void start(uint64_t first, uint32_t count, RayBatch& rays) override { pt_.start(first, count, rays); }
  size_t shade(uint32_t bounce, RayBatch& rays, ShadeStats& stats) override { return pt_.shade(bounce, rays, stats); }
  void finish(Film& film, ShadeStats& stats) override { pt_.finish(film, stats); }

  IdRange lightPaths(int s0, int s1) const override {
    const uint64_t n = options_.photonsPerSample;
    if (progressive_) return {n * uint64_t(s0), n * uint64_t(s1)};
    return s0 == 0 ? IdRange{0, n * uint64_t(scene_.samplesPerPixel)} : IdRange{};
  }

  void startLight(uint64_t first, uint32_t count, RayBatch& rays) override {
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
        const Bsdf bsdf = hit.mat->bsdfAt(hit.h.u, hit.h.v);
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
    gathered_.clear();
    uint64_t peak = stats.photonMapBytes.load();
    while (map_.bytes() > peak && !stats.photonMapBytes.compare_exchange_weak(peak, map_.bytes())) {}
    if (!(r0_ > 0)) {
      r0_ = options_.radius > 0 ? options_.radius : medianNeighbourDistance();
      // ppm's radius of every camera sample, fixed before any is shaded (shading is parallel).
      radius2_.resize(size_t(std::max(1, scene_.samplesPerPixel)));
      for (size_t i = 0; i < radius2_.size(); ++i)
        radius2_[i] = i == 0 ? r0_ * r0_ : radius2_[i - 1] * (float(i) + options_.alpha) / float(i + 1);
    }
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
    Rgb sum{};
    auto add = [&](uint32_t i) {
      const Photon& ph = map_[i];
      // The path the photon closes has bounce + vertex scattering events before the light: the
      // path tracer, which pm complements, counts it only within max_depth.
      if (dot(ph.n, n) <= kSameSurfaceCos || int(v.bounce + ph.vertex) > scene_.integrator.maxDepth) return;
      sum += v.bsdf->eval(v.woL, v.frame->toLocal(ph.wi)) * ph.power;
    };
    float r2;
    if (progressive_) {
      r2 = radius2_[std::min<size_t>(v.sample, radius2_.size() - 1)];
      map_.within(v.p, r2, add);
    } else {
      thread_local std::vector<uint32_t> near;
      const float maxR = kMaxRadiusOverR0 * r0_;
      r2 = map_.nearest(v.p, options_.neighbours, maxR * maxR, near);
      for (uint32_t i : near) add(i);
    }
    return r2 > 0 ? sum * float(1.0 / (std::numbers::pi * double(r2))) : Rgb{};
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

std::unique_ptr<Integrator> makePhotonMapper(const ShadingScene& scene, const PhotonOptions& options) {
  return std::make_unique<PhotonMapper>(scene, options);
}

}  // namespace rayes
