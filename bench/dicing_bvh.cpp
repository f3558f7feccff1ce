// Bottom level: dicing cost, implicit-BVH build cost (per micropolygon, m = 4..10) and
// single-ray traversal speed on a diced teapot patch. Not part of ctest; see
// bench/RESULTS-dicing.md for figures and the command line.
#include <benchmark/benchmark.h>
#include <limits>
#include <string>
#include <vector>
#include "core/rng.h"
#include "dicing/bezier_patch.h"
#include "dicing/dice_buffer.h"

namespace {

using namespace rayes;

std::string teapotPath() {
  const std::string here = __FILE__;
  return here.substr(0, here.rfind('/')) + "/../scenes/teapot.bpt";
}

const BezierPatch& benchPatch() {
  static const BezierPatch patch(loadBezierPatchFile(teapotPath())[0]);  // a body patch
  return patch;
}

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

// Rays from a sphere around the patch (radius 2x its box diagonal) to random points on it.
// bench/dicing_embree.cpp traces the same rays (same seed and construction).
struct Ray {
  Vec3 org, dir;
};
std::vector<Ray> benchRays(const Patch& patch, int count) {
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

}  // namespace

BENCHMARK_MAIN();
