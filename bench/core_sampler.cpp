// Cost of one 2D sample: scrambled Sobol (sample2D: three hashes for the seeds, the index
// shuffle, two Sobol points and two Owen scrambles) against two independent hashed numbers
// (sampleUniform twice). The renderer draws 4 2D and 4 1D samples per path vertex.
// Run: bench_core_sampler ; figures in bench/RESULTS.md (low-discrepancy sampling).
#include <benchmark/benchmark.h>

#include <cstdint>

#include "core/rng.h"

namespace {

using namespace rayes;

void BM_Sobol2D(benchmark::State& state) {
  uint32_t i = 0;
  for (auto _ : state) {
    const Sample2D s = sample2D(RngKey{i * 7919u, i >> 10, 1, 0}, 3);
    benchmark::DoNotOptimize(s);
    ++i;
  }
}
BENCHMARK(BM_Sobol2D);

void BM_Independent2D(benchmark::State& state) {
  uint32_t i = 0;
  for (auto _ : state) {
    const RngKey key{i * 7919u, i >> 10, 1, 0};
    const Sample2D s{sampleUniform(key, 3), sampleUniform(key, 4)};
    benchmark::DoNotOptimize(s);
    ++i;
  }
}
BENCHMARK(BM_Independent2D);

}  // namespace

BENCHMARK_MAIN();
