// Lights for next-event estimation. A PointLight is a delta light; a PatchLight is any patch
// with an emissive material, sampled uniformly in its (u, v) square: the area density is then
// 1 / |dP/du x dP/dv|, exact for any patch shape (planar rectangles get uniform area sampling).
// Shading knows nothing of patches: the scene hands each PatchLight a function evaluating its
// surface. LightSampler picks a light with probability proportional to its estimated power.
// Immutable after construction; all methods const and thread-safe.
#pragma once
#include <cstdint>
#include <functional>
#include <vector>
#include "core/vec.h"

namespace rayes {

struct PointLight {
  Vec3 position;
  Rgb intensity;  // W / sr
};

struct PatchLight {
  // Position and unnormalised normal dP/du x dP/dv at (u, v).
  std::function<void(float u, float v, Vec3& p, Vec3& n)> evaluate;
  Rgb radiance;
  bool twoSided = false;
  uint32_t leaf = 0;
};

struct LightSample {
  Vec3 position;      // point on the light
  Vec3 normal;        // unit, zero for point lights
  Rgb radiance;       // radiance toward the receiver (or intensity for a point light)
  float pdfArea = 0;  // area density of the point given the light; 0 for point lights
  float pickPdf = 0;  // probability of having chosen this light
  bool delta = false;
  bool twoSided = false;
  uint32_t leaf = 0xffffffffu;
};

class LightSampler {
 public:
  LightSampler() = default;
  LightSampler(std::vector<PointLight> points, std::vector<PatchLight> patches);
  bool empty() const { return cdf_.empty(); }
  size_t size() const { return cdf_.size(); }
  // Picks a light with u0 and a point on it with (u1, u2). Returns false if there is no light
  // or the sampled point is degenerate (zero Jacobian).
  bool sample(float u0, float u1, float u2, LightSample& out) const;
  // Index of the PatchLight on `leaf`, or -1.
  int patchLightOfLeaf(uint32_t leaf) const;
  const std::vector<PatchLight>& patchLights() const { return patches_; }

 private:
  std::vector<PointLight> points_;
  std::vector<PatchLight> patches_;
  std::vector<float> cdf_;  // over points_ then patches_, last entry 1
  std::vector<int> leafToPatchLight_;
};

}  // namespace rayes
