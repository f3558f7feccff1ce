// Lights for next-event estimation and for the emission that paths find by themselves.
//   PointLight, SpotLight: delta lights (intensity in W/sr).
//   PatchLight: any patch with an emitting material (rect and disk lights are such patches),
//     sampled uniformly in its (u, v) square: area density 1 / |dP/du x dP/dv|, exact for any
//     parametrisation (uniform area sampling for parallelograms, the concentric disk and the
//     sphere). Shading knows nothing of patches: the scene hands each a surface function.
//   DistantLight: a direction with an irradiance; with an angular radius it is a uniform disk
//     of that angular size (the sun), sampled uniformly in its cone, otherwise a delta.
//   Environment: radiance from every direction at infinity: a constant, or a lat-long map
//     read through the texture cache (texture/texture_cache.h; nearest texel of the finest
//     level: the map is piecewise constant) and sampled by a 2D piecewise-constant distribution
//     over luminance x sin θ of a coarse MIP level (at most kEnvironmentCells texels wide, read
//     once through the cache, not the whole image; each cell's value floored at a small
//     fraction of the mean, so every direction with radiance has a positive density and the
//     estimate stays unbiased whatever the map). Direction (x, y, z) maps to u = atan2(y, x) / 2π
//     (wrapped to [0, 1)), v = θ / π with θ measured from +z: the map's top row is the +z sky.
// LightSampler picks one light with probability proportional to its estimated power and
// answers the densities multiple importance sampling needs. Immutable after construction;
// every method const and thread-safe.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>
#include "core/vec.h"
#include "shading/distribution.h"
#include "shading/texture.h"

namespace rayes {

struct PointLight {
  Vec3 position;
  Rgb intensity;  // W / sr
};

struct SpotLight {
  Vec3 position;
  Vec3 direction;          // unit, the axis of the cone
  Rgb intensity;           // W / sr on the axis
  float cosFalloffStart;   // full intensity inside this cone
  float cosFalloffEnd;     // zero outside; smoothstep in cos between (pbrt-v4)
  float falloff(float cosTheta) const;
};

struct PatchLight {
  // Position and unnormalised normal dP/du x dP/dv at (u, v).
  std::function<void(float u, float v, Vec3& p, Vec3& n)> evaluate;
  Rgb radiance;
  bool twoSided = false;
  uint32_t leaf = 0;
};

struct DistantLight {
  Vec3 direction;        // unit, toward the light
  Rgb irradiance;        // W / m^2 on a surface facing the light
  double oneMinusCos = 0;  // 1 - cos(angular radius), 0 for a delta light (kept in double: the sun's is 1e-5)
  Rgb radiance() const;    // irradiance / (π sin² radius) for a disk, unused for a delta
};

class Environment {
 public:
  explicit Environment(Rgb constant) : constant_(constant) {}
  static constexpr int kEnvironmentCells = 1024;
  // A lat-long map (see the header comment), radiance = scale x texel.
  Environment(std::shared_ptr<const TextureImage> map, Rgb scale);
  Rgb eval(Vec3 dir) const;
  float pdf(Vec3 dir) const;  // solid angle
  // Returns false when the sample is degenerate (a pole).
  bool sample(float u1, float u2, Vec3& dir, float& pdf) const;
  Rgb averageRadiance() const { return average_; }
  const TextureImage* map() const { return map_.get(); }
  int distributionLevel() const { return level_; }  // the MIP level the sampling distribution is built from

 private:
  Rgb constant_;
  std::shared_ptr<const TextureImage> map_;
  Rgb scale_{1, 1, 1};
  int level_ = 0;
  Distribution2D dist_;
  Rgb average_;
};

// The lights a scene has besides point lights and emissive patches.
struct SceneLights {
  std::vector<SpotLight> spots;
  std::vector<DistantLight> distants;
  std::shared_ptr<const Environment> environment;
};

// Kinds of light as bits of a set: which lights a caustic estimator covers (PathTracer::Options).
enum LightKind : uint8_t {
  kPointLight = 1, kSpotLight = 2, kPatchLight = 4, kDistantLight = 8, kEnvironmentLight = 16,
  kAllLights = 31,
};

struct LightSample {
  Vec3 wi;              // unit, from the receiver toward the light
  float distance = 0;   // to the sampled point; +inf for lights at infinity
  Vec3 point;           // the sampled point (lights at a finite distance)
  Vec3 normal;          // unit normal of an emissive patch at point; zero for other lights
  Rgb radiance;         // arriving along -wi (intensity / distance² for point and spot lights)
  float pdf = 0;        // solid-angle density including the pick probability; for a delta
                        // light, the pick probability alone
  bool delta = false;
  uint32_t leaf = 0xffffffffu;  // the emitter's leaf (a shadow ray must not hit it), or none
  LightKind kind = kPointLight;
};

// A ray leaving a light, for light tracing (LightSampler::sampleEmission).
struct EmissionSample {
  Vec3 org, dir;        // dir unit; lights at infinity start on a disk just outside the scene
  Rgb weight;           // Le |cos| / (pick x position density x direction density)
  // An emissive patch's point can itself be seen by the camera: what connecting it needs.
  bool onSurface = false;
  Vec3 normal;          // unit dP/du x dP/dv at the point
  Rgb radiance;         // Le
  bool twoSided = false;
  float pdfArea = 0;    // pick x area density of the point
  uint32_t leaf = 0xffffffffu;  // the emitter's leaf (the ray must not hit it again), or none
};

// The power heuristic (β = 2) weight of a strategy with density a against one with density b.
inline float powerHeuristic(float a, float b) {
  if (!(a > 0)) return 0;
  if (!std::isfinite(a)) return 1;
  const float r = b / a;
  return 1.0f / (1.0f + r * r);
}

class LightSampler {
 public:
  LightSampler() = default;
  // sceneRadius: of a sphere holding the scene, for the power of lights at infinity.
  LightSampler(std::vector<PointLight> points, std::vector<PatchLight> patches, SceneLights more = {},
               float sceneRadius = 1, Vec3 sceneCenter = {});
  bool empty() const { return cdf_.empty(); }
  size_t size() const { return cdf_.size(); }
  // Picks a light with u0 and a point or direction on it with (u1, u2), as seen from ref.
  // Returns false if there is no light, the receiver is behind a one-sided emitter, or the
  // sample is degenerate.
  bool sample(Vec3 ref, float u0, float u1, float u2, LightSample& out) const;
  // Picks a light with u0, as sample() does (by power), and an emitted ray: a point with
  // (u1, u2) and a direction with (u3, u4) (cosine-weighted from patches, uniform in the cone
  // of points and spots; lights at infinity: the direction by their own density, the origin
  // uniform on a disk of the scene's radius facing it). Returns false when the pick or the
  // sample is degenerate (the path then carries nothing).
  bool sampleEmission(float u0, float u1, float u2, float u3, float u4, EmissionSample& out) const;
  // Index of the PatchLight on `leaf`, or -1.
  int patchLightOfLeaf(uint32_t leaf) const;
  // Solid-angle density (pick included) with which sample() from ref would produce the point
  // hit at (u, v) on the emissive leaf, reached along unit direction wi at distance dist.
  float patchPdf(int patchLight, float u, float v, Vec3 wi, float dist) const;
  // Radiance from the lights at infinity along unit dir, each weighted by the power heuristic
  // against a BSDF sample of density bsdfPdf (bsdfDelta: weight 1); only the kinds in `kinds`.
  Rgb escaped(Vec3 dir, float bsdfPdf, bool bsdfDelta, uint8_t kinds = kAllLights) const;
  // Something a BSDF-sampled ray can find: an emissive patch or a non-delta light at infinity.
  bool hasHittable() const { return hittable_; }
  bool hasInfinite() const { return !more_.distants.empty() || more_.environment; }
  const std::vector<PatchLight>& patchLights() const { return patches_; }

 private:
  float pick(size_t k) const { return cdf_[k] - (k > 0 ? cdf_[k - 1] : 0.0f); }
  size_t pickIndex(float u0) const;
  std::vector<PointLight> points_;
  std::vector<PatchLight> patches_;
  SceneLights more_;
  // Pick order: points, spots, patches, distants, environment.
  std::vector<float> cdf_;
  std::vector<int> leafToPatchLight_;
  size_t spot0_ = 0, patch0_ = 0, distant0_ = 0, env_ = 0;
  float radius_ = 1;
  Vec3 center_;
  bool hittable_ = false;
};

}  // namespace rayes
