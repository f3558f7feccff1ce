// Counter-based random numbers: a value is a pure function of (pixel, sample, bounce,
// dimension, seed), never of processing order, so images do not depend on thread count, sort
// order or batch size (docs/design.md, invariant 2). Thread-safe: there is no state.
#pragma once
#include <cstdint>

namespace rayes {

// A 64-bit finaliser (SplitMix64 / Stafford variant 13): full avalanche, cheap.
constexpr uint64_t mix64(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

// Uniform float in [0, 1). Built from the top 24 bits, so it can never round to 1.0f
// (the pitfall of v * 2^-32: docs/design.md, "Precision").
constexpr float bitsToUnitFloat(uint64_t bits) {
  return static_cast<float>(bits >> 40) * (1.0f / 16777216.0f);
}

struct RngKey {
  uint32_t pixel = 0;
  uint32_t sample = 0;
  uint32_t bounce = 0;
  uint64_t seed = 0;
};

// The dimension-th random number of the path vertex identified by the key.
constexpr float sampleUniform(const RngKey& k, uint32_t dimension) {
  uint64_t h = mix64(k.seed ^ 0x9e3779b97f4a7c15ull);
  h = mix64(h ^ k.pixel);
  h = mix64(h ^ (uint64_t(k.sample) << 32 | k.bounce));
  h = mix64(h ^ dimension);
  return bitsToUnitFloat(h);
}

}  // namespace rayes
