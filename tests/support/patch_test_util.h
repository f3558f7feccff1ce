// Helpers shared by the geometry, dicing and scene tests: deterministic random numbers, the teapot, and the
// search for teapot patches that share a border.
#pragma once
#include <array>
#include <cstring>
#include <vector>
#include "core/box.h"
#include "core/rng.h"
#include "core/vec.h"
#include "geometry/bezier_patch.h"
#include "geometry/patch.h"

namespace rayes::test {

// Counter-based, so every test sees the same numbers whatever runs before it.
class Random {
 public:
  explicit Random(uint64_t seed) : state_(mix64(seed)) {}
  uint64_t bits() { return mix64(state_++); }
  float uniform() { return bitsToUnitFloat(bits()); }              // [0, 1)
  float uniform(float a, float b) { return a + (b - a) * uniform(); }
  int below(int n) { return int(bits() % uint64_t(n)); }
  Vec3 unitVector() {
    const float z = uniform(-1.0f, 1.0f), phi = uniform(0.0f, 6.2831853f);
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    return {r * std::cos(phi), r * std::sin(phi), z};
  }

 private:
  uint64_t state_;
};

// A point of the cube [-2, 2)^3.
inline Vec3 randomPoint(Random& rng) { return {rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-2, 2)}; }

// A ray toward a random point of a random border of `patch` (at t in [t0, t1) along it), from 0.5
// outside along a perturbed normal, at a random level 0..m: it walks the border regions down to
// its level.
struct BorderRay {
  Vec3 org, dir;
  int level;
};
inline BorderRay randomBorderRay(const Patch& patch, Random& rnd, float t0, float t1, int m) {
  const int e = rnd.below(4);
  const float t = rnd.uniform(t0, t1);
  const float u = e == 0 || e == 2 ? t : e == 1 ? 1.0f : 0.0f, v = e == 1 || e == 3 ? t : e == 2 ? 1.0f : 0.0f;
  const SurfacePoint sp = patch.evaluate(u, v);
  const Vec3 n = normalize(sp.n + Vec3{0.3f, -0.2f, 0.1f} * rnd.uniform(-1.0f, 1.0f));
  const Vec3 org = sp.p + n * 0.5f;
  return {org, -n, rnd.below(m + 1)};
}

inline bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }
inline bool sameBits(Vec3 a, Vec3 b) { return std::memcmp(&a, &b, sizeof a) == 0; }

using ControlPoints = std::array<Vec3, 16>;

// A 4x4 control grid near the unit square, each point jittered (z the most).
inline ControlPoints randomControlPoints(test::Random& rng) {
  ControlPoints cp;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i)
      cp[j * 4 + i] = Vec3{float(i), float(j), 0.0f} + Vec3{rng.uniform(-0.8f, 0.8f), rng.uniform(-0.8f, 0.8f),
                                                           rng.uniform(-1.5f, 1.5f)};
  return cp;
}

inline std::vector<ControlPoints> loadTeapot() {
  return loadBezierPatchFile(RAYES_SOURCE_DIR "/scenes/teapot.bpt");
}

inline ControlPoints transformed(const ControlPoints& cp, float scale, Vec3 offset) {
  ControlPoints r;
  for (int k = 0; k < 16; ++k) r[k] = cp[k] * scale + offset;
  return r;
}

// A border of a 4x4 control grid: side 0: v=0, 1: v=1, 2: u=0, 3: u=1. Control points in the
// order of increasing parameter along the border.
inline std::array<Vec3, 4> borderControlPoints(const ControlPoints& cp, int side) {
  std::array<Vec3, 4> b;
  for (int k = 0; k < 4; ++k) {
    switch (side) {
      case 0: b[k] = cp[k]; break;
      case 1: b[k] = cp[12 + k]; break;
      case 2: b[k] = cp[4 * k]; break;
      default: b[k] = cp[4 * k + 3]; break;
    }
  }
  return b;
}

// Grid index (i, j) of the k-th vertex along `side` of a dicing with n = 2^level quads.
inline std::array<int, 2> borderVertex(int side, int k, int n) {
  switch (side) {
    case 0: return {k, 0};
    case 1: return {k, n};
    case 2: return {0, k};
    default: return {n, k};
  }
}

struct SharedBorder {
  int patchA, sideA, patchB, sideB;
  bool reversed;  // B's border runs the other way
};

// Pairs of patches whose border control points coincide exactly (as the same or reversed
// sequence). Collapsed borders (poles: all 4 points equal) are left out.
inline std::vector<SharedBorder> findSharedBorders(const std::vector<ControlPoints>& patches) {
  std::vector<SharedBorder> out;
  for (int a = 0; a < int(patches.size()); ++a)
    for (int sa = 0; sa < 4; ++sa) {
      const auto ba = borderControlPoints(patches[a], sa);
      if (ba[0] == ba[1] && ba[1] == ba[2] && ba[2] == ba[3]) continue;
      for (int b = a + 1; b < int(patches.size()); ++b)
        for (int sb = 0; sb < 4; ++sb) {
          const auto bb = borderControlPoints(patches[b], sb);
          const bool same = ba[0] == bb[0] && ba[1] == bb[1] && ba[2] == bb[2] && ba[3] == bb[3];
          const bool rev = ba[0] == bb[3] && ba[1] == bb[2] && ba[2] == bb[1] && ba[3] == bb[0];
          if (same || rev) out.push_back({a, sa, b, sb, !same});
        }
    }
  return out;
}

}  // namespace rayes::test
