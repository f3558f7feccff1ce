// The light tracer (`--method lt`): paths start on the lights and every vertex that can
// scatter toward the camera is connected to it and splatted onto the film. It converges to the
// path tracer's image wherever the camera sees no delta-only path (a mirror or smooth glass
// seen directly), and it is the unbiased reference for caustics (light through glass onto a
// diffuse surface), which the path tracer finds only by chance.
//
// Per generation, through the same pipeline as the path tracer: path k owns ray slots 2k (the
// light path's next segment, closest hit) and 2k+1 (its connection to the camera, any hit).
//   start:  a light is picked by power (LightSampler::sampleEmission, the choice next-event
//           estimation makes) and a ray leaves it. An emissive patch's point is also connected
//           to the camera (the camera sees area lights, as camera rays do); point and spot
//           lights are not (no camera ray can hit a point either), nor are lights at infinity
//           (no ray reaches the lens from a point at infinity: the environment and the sun are
//           missing from a light-traced image where the camera sees them directly).
//   shade:  a connection that reached the lens unoccluded becomes a splat; at the hit of the
//           segment, a non-delta BSDF is connected to a lens point (PerspectiveCamera::connect
//           derives the importance); the BSDF is sampled from the incoming direction for the
//           next segment with the adjoint's weight: eta² undone for refraction (importance is
//           not compressed like radiance) and Veach's shading-normal correction
//           |ns·wi| |ng·wo| / (|ng·wi| |ns·wo|). Russian roulette on the throughput.
//   finish: the batch's splats inside the film's window are added to its exact (fixed-point)
//           splat buffer: the sum does not depend on the order, so any batching, thread count
//           or farm split (ranges of light path ids, summed by rayes merge) gives the same bits.
// A path has at most max_depth scattering vertices, like the path tracer's paths. Random
// numbers are keyed like the path tracer's ((pixel, sample) of the path id, vertex, seed) with
// their own dimensions. The AOVs stay empty: nothing is seen from the camera.
// With CausticPaths Only (Without), a vertex is connected only if (unless) the light path so
// far is light -> (caustic scatterer)+ -> diffuse -> ... (integrator.h); a path that can no
// longer change what it counts is ended.
#pragma once
#include <cstdint>
#include <vector>
#include "shading/integrator.h"
#include "shading/light_path.h"
#include "shading/ray_spawning.h"

namespace rayes {

class LightTracer final : public Integrator {
 public:
  explicit LightTracer(const ShadingScene& scene, CausticPaths causticPaths = CausticPaths::All);

  IntegratorTraits traits() const override { return {.lightPathIds = true, .shadowPairs = true}; }
  uint32_t raysPerPath() const override { return kRaysPerPath; }
  size_t bytesPerPath() const override;
  void start(uint64_t first, uint32_t count, RayBatch& rays) override;
  size_t shade(uint32_t bounce, RayBatch& rays, ShadeStats& stats) override;
  void finish(Film& film, ShadeStats& stats) override;

 private:
  struct Splat {
    uint32_t pixel = kNoPixel;
    Rgb value;
  };
  static constexpr uint32_t kNoPixel = 0xffffffffu;

  // Writes path k's connection from `origin` to the lens point of `c` into slot 2k+1; the
  // splat `value` lands on c's pixel if the ray arrives. Returns whether a ray was written.
  bool writeConnection(uint32_t k, uint32_t vertex, const CameraConnection& c, Rgb value, Vec3 origin,
                       uint32_t ignoreLeaf, uint32_t fromLeaf, uint8_t fromLevel, float time, RayBatch& rays);

  const ShadingScene& scene_;
  CausticPaths causticPaths_;
  std::vector<LightRun> run_;
  uint32_t splatsPerPath_;  // one per vertex: the light's and max_depth scattering vertices
  uint64_t first_ = 0;
  std::vector<Rgb> throughput_;
  std::vector<Splat> pending_;       // the connection in flight
  std::vector<uint8_t> pendingVertex_;
  std::vector<Splat> splats_;        // splatsPerPath_ per path
};

}  // namespace rayes
