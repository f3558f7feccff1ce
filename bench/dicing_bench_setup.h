// The patch and rays the bottom-level benchmarks share (bench/dicing_bvh.cpp and
// bench/dicing_embree.cpp trace exactly the same rays, so their figures compare).
#pragma once
#include <cmath>
#include <string>
#include <vector>
#include "core/rng.h"
#include "geometry/bezier_patch.h"

namespace rayes::bench {

inline std::string teapotPath() {
  const std::string here = __FILE__;
  return here.substr(0, here.rfind('/')) + "/../scenes/teapot.bpt";
}

// Teapot body patch 0.
inline const BezierPatch& benchPatch() {
  static const BezierPatch patch(loadBezierPatchFile(teapotPath())[0]);
  return patch;
}

struct Ray {
  Vec3 org, dir;
};

// Rays from a sphere around the patch (radius 2x its box diagonal) to random points on it.
inline std::vector<Ray> benchRays(const Patch& patch, int count) {
  std::vector<Ray> rays(static_cast<size_t>(count));
  const Box3 b = patch.bounds();
  const float radius = 2.0f * length(b.extent());
  for (int k = 0; k < count; ++k) {
    auto u = [&](uint32_t d) { return sampleUniform({uint32_t(k), 0, 0, 7}, d); };
    const float z = 2 * u(0) - 1, phi = 6.2831853f * u(1), r = std::sqrt(std::max(0.0f, 1 - z * z));
    const Vec3 org = b.center() + Vec3{r * std::cos(phi), r * std::sin(phi), z} * radius;
    rays[size_t(k)] = {org, patch.evaluate(u(2), u(3)).p - org};
  }
  return rays;
}

}  // namespace rayes::bench
