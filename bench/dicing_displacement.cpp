// Dicing throughput with and without displacement (bench/history/RESULTS-displacement.md): the
// teapot body patch of the other dicing benchmarks, diced into a DiceBuffer (grid + implicit
// tree) at m = 6 and 8, bare, with fractal noise (3 and 8 octaves) and with a height map; and
// the cost of one boundsOver() of a micro-quad (what crack-free borders call).
#include <benchmark/benchmark.h>
#include <memory>
#include "dicing/dice_buffer.h"
#include "geometry/displaced_patch.h"
#include "dicing_bench_setup.h"

namespace rayes::bench {
namespace {

enum Variant { kBare, kNoise3, kNoise8, kHeightMap };

PatchPtr variantPatch(int v) {
  static const PatchPtr base = std::make_shared<BezierPatch>(loadBezierPatchFile(teapotPath())[0]);
  if (v == kBare) return base;
  const float size = base->bounds().longestSide();
  if (v == kHeightMap) {
    std::vector<float> t(256 * 256);
    for (size_t k = 0; k < t.size(); ++k) t[k] = sampleUniform({uint32_t(k), 0, 0, 3}, 0);
    return std::make_shared<DisplacedPatch>(base, std::make_shared<HeightMapDisplacement>(
                                                      std::make_shared<HeightMap>(256, 256, std::move(t)), 0.05f * size, 0.0f));
  }
  NoiseParams np;
  np.amplitude = 0.05f * size;
  np.frequency = 4.0f / size;
  np.octaves = v == kNoise3 ? 3 : 8;
  return std::make_shared<DisplacedPatch>(base, std::make_shared<NoiseDisplacement>(np));
}

const char* variantName(int v) {
  switch (v) {
    case kBare: return "bare";
    case kNoise3: return "noise3";
    case kNoise8: return "noise8";
    default: return "heightmap";
  }
}

void BM_DiceDisplaced(benchmark::State& state) {
  const int variant = int(state.range(0)), level = int(state.range(1));
  const PatchPtr patch = variantPatch(variant);
  DiceBuffer buffer(level);
  for (auto _ : state) {
    buffer.dice(*patch, level);
    benchmark::DoNotOptimize(buffer.node(0, 0, 0));
  }
  state.SetLabel(variantName(variant));
  state.SetItemsProcessed(int64_t(state.iterations()) << (2 * level));  // micropolygons
}
BENCHMARK(BM_DiceDisplaced)->ArgsProduct({{kBare, kNoise3, kNoise8, kHeightMap}, {6, 8}})->Unit(benchmark::kMillisecond);

void BM_BoundsOverMicroQuad(benchmark::State& state) {
  const int variant = int(state.range(0));
  const PatchPtr patch = variantPatch(variant);
  const float h = 1.0f / 256;
  uint32_t k = 0;
  for (auto _ : state) {
    const float u0 = float(k % 256) * h, v0 = float((k / 256) % 256) * h;
    benchmark::DoNotOptimize(patch->boundsOver(u0, u0 + h, v0, v0 + h));
    ++k;
  }
  state.SetLabel(variantName(variant));
  state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_BoundsOverMicroQuad)->DenseRange(kBare, kHeightMap);

}  // namespace
}  // namespace rayes::bench

BENCHMARK_MAIN();
