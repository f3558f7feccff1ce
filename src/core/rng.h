// Counter-based random numbers: a value is a pure function of (pixel, sample, bounce,
// dimension, seed), never of processing order, so images do not depend on thread count, sort
// order, batch size or memory budget (docs/design.md, invariant 2). Thread-safe: no state.
//
// Two samplers share the key:
// - sample1D / sample2D, the renderer's: scrambled low-discrepancy points (Burley 2020). Each
//   dimension id of a (pixel, bounce) gets its own index shuffle and Owen scrambles, hashed from
//   (pixel, bounce, dimension, seed); a 2D dimension draws Sobol dimensions 0 and 1, a 1D one
//   Sobol dimension 0 ("padded" Sobol). The sample index is the pixel's global sample number,
//   so the first 2^k samples of a pixel are a (0,k,2)-net in each 2D dimension and stratified
//   in 2^k strata in each 1D one, whichever passes or batches they were rendered in. Dimension
//   ids name either a 1D or a 2D sample, never both: the two would share their seeds.
// - sampleUniform: independent hashed numbers, for tests and tools whose estimates assume
//   independent samples (a variance from per-sample values, rejection counts).
#pragma once
#include <cstdint>
#include "core/sobol.h"

namespace rayes {

// A 64-bit finaliser (SplitMix64 / Stafford variant 13): full avalanche, cheap.
constexpr uint64_t mix64(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

// Uniform float in [0, 1). Built from the top 24 bits, so it can never round to 1.0f
// (the pitfall of v * 2^-32, docs/design.md "Precision").
constexpr float bitsToUnitFloat(uint64_t bits) {
  return static_cast<float>(bits >> 40) * (1.0f / 16777216.0f);
}

struct RngKey {
  uint32_t pixel = 0;
  uint32_t sample = 0;
  uint32_t bounce = 0;
  uint64_t seed = 0;
};

// The dimension-th independent random number of the path vertex identified by the key.
constexpr float sampleUniform(const RngKey& k, uint32_t dimension) {
  uint64_t h = mix64(k.seed ^ 0x9e3779b97f4a7c15ull);
  h = mix64(h ^ k.pixel);
  h = mix64(h ^ (uint64_t(k.sample) << 32 | k.bounce));
  h = mix64(h ^ dimension);
  return bitsToUnitFloat(h);
}

// The seeds of one low-discrepancy dimension of a (pixel, bounce): the sample index's shuffle
// and an Owen scramble per Sobol dimension. Not keyed by the sample: all samples of a pixel
// must be points of one scrambled sequence.
struct SobolSeeds {
  uint32_t shuffle, scramble0, scramble1;
};
constexpr SobolSeeds sobolSeedsOf(const RngKey& k, uint32_t dimension) {
  uint64_t h = mix64(k.seed ^ 0x5851f42d4c957f2dull);
  h = mix64(h ^ k.pixel);
  h = mix64(h ^ (uint64_t(k.bounce) << 32 | dimension));
  return {uint32_t(h), uint32_t(h >> 32), uint32_t(mix64(h))};
}

// A 32-bit fixed-point value (bit 31 = 1/2) as a float in [0, 1), from its top 24 bits.
constexpr float fixedToUnitFloat(uint32_t x) { return bitsToUnitFloat(uint64_t(x) << 32); }

constexpr float sample1D(const RngKey& k, uint32_t dimension) {
  const SobolSeeds s = sobolSeedsOf(k, dimension);
  const uint32_t index = nestedUniformScramble(k.sample, s.shuffle);
  return fixedToUnitFloat(nestedUniformScramble(sobolPoint(index, 0), s.scramble0));
}

struct Sample2D {
  float u, v;
};
constexpr Sample2D sample2D(const RngKey& k, uint32_t dimension) {
  const SobolSeeds s = sobolSeedsOf(k, dimension);
  const uint32_t index = nestedUniformScramble(k.sample, s.shuffle);
  return {fixedToUnitFloat(nestedUniformScramble(sobolPoint(index, 0), s.scramble0)),
          fixedToUnitFloat(nestedUniformScramble(sobolPoint(index, 1), s.scramble1))};
}

}  // namespace rayes
