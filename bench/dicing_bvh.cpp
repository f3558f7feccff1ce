// Bottom level: dicing cost, implicit-BVH build cost (per micropolygon, m = 4..10) and
// single-ray traversal speed on a diced teapot patch. Not part of ctest; see
// bench/history/RESULTS-dicing.md for figures and the command line.
#include <benchmark/benchmark.h>
#include <limits>
#include <string>
#include <vector>
#include "core/rng.h"
#include "geometry/bezier_patch.h"
#include "dicing/dice_buffer.h"
#include "geometry/moving_patch.h"
#include "dicing_bench_setup.h"

namespace {

using namespace rayes;
using rayes::bench::benchPatch;
using rayes::bench::benchRays;
using rayes::bench::Ray;


// Seconds per micropolygon (printed with an SI prefix: "5.1n" is 5.1 ns).
void perMicropolygon(benchmark::State& state, int m) {
  state.counters["per_micropolygon"] = benchmark::Counter(
      double(state.iterations()) * double(1 << (2 * m)), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// Patch::dice alone: evaluation of (2^m+1)^2 vertices.
void BM_Evaluate(benchmark::State& state) {
  const int m = int(state.range(0));
  const size_t n = size_t((1 << m) + 1) * ((1 << m) + 1);
  std::vector<Vec3> p(n), nrm(n);
  for (auto _ : state) {
    benchPatch().dice(m, p.data(), nrm.data());
    benchmark::DoNotOptimize(p.data());
  }
  perMicropolygon(state, m);
}

// DiceBuffer::dice: evaluation + normal normalisation + bottom-up tree build. The build's own
// cost is this minus BM_Evaluate at the same m.
void BM_DiceAndBuild(benchmark::State& state) {
  const int m = int(state.range(0));
  DiceBuffer buffer(m);
  for (auto _ : state) {
    buffer.dice(benchPatch(), m);
    benchmark::DoNotOptimize(&buffer);
  }
  perMicropolygon(state, m);
}

BENCHMARK(BM_Evaluate)->DenseRange(4, 10)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DiceAndBuild)->DenseRange(4, 10)->Unit(benchmark::kMicrosecond);


void BM_Traverse(benchmark::State& state) {
  const int m = int(state.range(0));
  DiceBuffer buffer(m);
  buffer.dice(benchPatch(), m);
  const std::vector<Ray> rays = benchRays(benchPatch(), 1 << 16);
  size_t hits = 0;
  for (auto _ : state) {
    for (const Ray& r : rays) {
      GridHit h;
      hits += buffer.intersect(r.org, r.dir, 0.0f, std::numeric_limits<float>::infinity(), m, h);
    }
  }
  state.counters["rays"] = benchmark::Counter(double(state.iterations()) * double(rays.size()),
                                              benchmark::Counter::kIsRate);
  state.counters["hit_fraction"] = double(hits) / (double(state.iterations()) * double(rays.size()));
}

void BM_Occluded(benchmark::State& state) {
  const int m = int(state.range(0));
  DiceBuffer buffer(m);
  buffer.dice(benchPatch(), m);
  const std::vector<Ray> rays = benchRays(benchPatch(), 1 << 16);
  size_t hits = 0;
  for (auto _ : state)
    for (const Ray& r : rays)
      hits += buffer.occluded(r.org, r.dir, 0.0f, std::numeric_limits<float>::infinity(), m);
  state.counters["rays"] = benchmark::Counter(double(state.iterations()) * double(rays.size()),
                                              benchmark::Counter::kIsRate);
}

BENCHMARK(BM_Traverse)->Arg(4)->Arg(6)->Arg(8)->Arg(10)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Occluded)->Arg(4)->Arg(6)->Arg(8)->Arg(10)->Unit(benchmark::kMillisecond);

// The same rays with the crack-free border boxes (what the SortedEngine does on curved patches),
// and on the patch moving between two samples at a random time weight (motion blur).
void BM_TraverseVariant(benchmark::State& state, bool borders, bool moving) {
  const int m = int(state.range(0));
  DiceBuffer buffer(m);
  std::vector<PatchPtr> samples;
  for (float dx : {0.0f, 0.02f}) {  // a small move: most rays aimed at the still patch still hit
    auto cp = benchPatch().controlPoints();
    for (auto& p : cp) p = p + Vec3{dx, 0.1f * dx, 0};
    samples.push_back(std::make_shared<BezierPatch>(cp));
  }
  const MovingPatch movingPatch(samples, {0.0f, 1.0f});
  if (moving) buffer.diceInterval(movingPatch, 0, m);
  else buffer.dice(benchPatch(), m);
  const std::vector<Ray> rays = benchRays(benchPatch(), 1 << 16);
  size_t hits = 0;
  for (auto _ : state) {
    uint32_t k = 0;
    for (const Ray& r : rays) {
      GridHit h;
      BottomQuery q;
      q.closeBorders = borders;
      q.alpha = moving ? float(++k & 1023) / 1024.0f : 0.0f;
      hits += buffer.intersect(r.org, r.dir, 0.0f, std::numeric_limits<float>::infinity(), m, h, q);
    }
  }
  state.counters["rays"] = benchmark::Counter(double(state.iterations()) * double(rays.size()),
                                              benchmark::Counter::kIsRate);
  state.counters["hit_fraction"] = double(hits) / (double(state.iterations()) * double(rays.size()));
}
void BM_TraverseBorders(benchmark::State& state) { BM_TraverseVariant(state, true, false); }
void BM_TraverseMoving(benchmark::State& state) { BM_TraverseVariant(state, false, true); }
BENCHMARK(BM_TraverseBorders)->Arg(4)->Arg(6)->Arg(8)->Arg(10)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TraverseMoving)->Arg(4)->Arg(6)->Arg(8)->Arg(10)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
