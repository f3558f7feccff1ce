// Texture filtering against point sampling on the grazing checkerboard (tests/support/
// grazing_checker.h: 1 m checks on the ground, a camera 1 m above it, rows from ~3 m to ~95 m
// away, 80° to 89.4° from the normal): the RMSE against each pixel's box-filtered reference, per
// band of rows (distance), filtered and point-sampled at 1, 4, 16, 64 and 256 spp; then the cost of
// one lookup of each (Google Benchmark), which with the table gives the comparison at equal time.
// Run: bench_shading_texture_filter ; figures in bench/RESULTS.md.
#include <benchmark/benchmark.h>

#include <cstdio>

#include "support/grazing_checker.h"

namespace {

using namespace rayes;
using namespace rayes::test;

void printErrorTable() {
  const Ground g;
  const Texture tex = checkerTexture(2000);
  constexpr int kBands = 4, kRowsPerBand = kH / kBands;
  std::vector<std::vector<double>> reference(kH, std::vector<double>(kW));
  for (int j = 0; j < kH; ++j)
    for (int i = 0; i < kW; ++i) {
      double bound;
      reference[j][i] = referenceWeight(g, i, j, bound);
    }
  std::printf("rows (distance m, angle from normal)");
  for (int strata : {1, 2, 4, 8, 16}) std::printf(" | %d spp filtered / point", strata * strata);
  std::printf("\n");
  for (int band = 0; band < kBands; ++band) {
    const int j0 = band * kRowsPerBand, j1 = j0 + kRowsPerBand;
    const double nearY = g.yOf(g.sy(j1)), farY = g.yOf(g.sy(j0));
    std::printf("%2d-%2d (%.0f-%.0f m, %.1f-%.1f deg)", j0, j1 - 1, nearY, farY,
                std::atan(nearY / kHeight) * 180 / std::numbers::pi, std::atan(farY / kHeight) * 180 / std::numbers::pi);
    for (int strata : {1, 2, 4, 8, 16}) {
      double sf = 0, sp = 0;
      for (int j = j0; j < j1; ++j)
        for (int i = 0; i < kW; ++i) {
          const double ef = renderPixel(g, tex, i, j, strata, true).mean - reference[j][i];
          const double ep = renderPixel(g, tex, i, j, strata, false).mean - reference[j][i];
          sf += ef * ef;
          sp += ep * ep;
        }
      const double n = double(kRowsPerBand) * kW;
      std::printf(" | %.4f / %.4f", std::sqrt(sf / n), std::sqrt(sp / n));
    }
    std::printf("\n");
  }
}

// One lookup of the checker at a grazing footprint, filtered or as a point sample.
void lookups(benchmark::State& state, bool filtered) {
  const Texture tex = checkerTexture(2000);
  const HitDerivatives dpd{Vec3{2000, 0, 0}, Vec3{0, 2000, 0}};
  const Vec3 d = normalize(Vec3{0, 20, -1});
  uint32_t i = 0;
  for (auto _ : state) {
    const float u = 0.5f + float(i & 1023) * 1e-5f, v = 0.01f + float(i >> 10 & 1023) * 1e-5f;
    const TextureQuery q = footprintQuery(u, v, d, Vec3{0, 0, 1}, 0.01f, filtered ? &dpd : nullptr, nullptr);
    benchmark::DoNotOptimize(tex.eval(q));
    ++i;
  }
}
void BM_CheckerFiltered(benchmark::State& state) { lookups(state, true); }
void BM_CheckerPoint(benchmark::State& state) { lookups(state, false); }
BENCHMARK(BM_CheckerFiltered);
BENCHMARK(BM_CheckerPoint);

}  // namespace

int main(int argc, char** argv) {
  printErrorTable();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  return 0;
}
