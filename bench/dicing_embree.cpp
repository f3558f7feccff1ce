// Peer comparison for the bottom level: the same diced teapot patch (m = 8) and the same rays
// as bench/dicing_bvh.cpp, traced by our implicit quad-tree and by Embree 3 (the grid as a
// triangle mesh with the same diagonal split, single-threaded device, default build quality).
// BM_Compare traces both in the same run and reports the ratio.
#include <embree3/rtcore.h>
#include <benchmark/benchmark.h>
#include <chrono>
#include <limits>
#include <string>
#include <vector>
#include "core/rng.h"
#include "geometry/bezier_patch.h"
#include "dicing/dice_buffer.h"
#include "dicing_bench_setup.h"

namespace {

using namespace rayes;
using rayes::bench::benchPatch;
using rayes::bench::benchRays;
using rayes::bench::Ray;
constexpr int kLevel = 8;
constexpr float kInf = std::numeric_limits<float>::infinity();



class EmbreeGrid {
 public:
  explicit EmbreeGrid(const DiceBuffer& grid) {
    device_ = rtcNewDevice("threads=1");
    scene_ = rtcNewScene(device_);
    RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    const int res = grid.resolution(), n = res - 1;
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), size_t(res) * res));
    for (int j = 0; j < res; ++j)
      for (int i = 0; i < res; ++i) {
        const Vec3 p = grid.position(i, j);
        float* d = v + 3 * (size_t(j) * res + i);
        d[0] = p.x; d[1] = p.y; d[2] = p.z;
      }
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                3 * sizeof(unsigned), size_t(2) * n * n));
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const unsigned p00 = unsigned(y * res + x), p10 = p00 + 1, p01 = p00 + unsigned(res), p11 = p01 + 1;
        unsigned* t = idx + 6 * (size_t(y) * n + x);
        t[0] = p00; t[1] = p10; t[2] = p11;  // the same split as micro_quad.h
        t[3] = p00; t[4] = p11; t[5] = p01;
      }
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene_, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(scene_);
  }
  ~EmbreeGrid() {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  bool intersect(const Ray& r) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    rh.ray.org_x = r.org.x; rh.ray.org_y = r.org.y; rh.ray.org_z = r.org.z;
    rh.ray.dir_x = r.dir.x; rh.ray.dir_y = r.dir.y; rh.ray.dir_z = r.dir.z;
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = kInf;
    rh.ray.mask = 0xffffffffu;
    rh.ray.flags = 0;
    rh.ray.time = 0.0f;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &ctx, &rh);
    return rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
  }

 private:
  RTCDevice device_;
  RTCScene scene_;
};

struct Setup {
  DiceBuffer grid{kLevel};
  std::vector<Ray> rays;
  Setup() {
    grid.dice(benchPatch(), kLevel);
    rays = benchRays(benchPatch(), 1 << 16);
  }
};
const Setup& setup() {
  static const Setup s;
  return s;
}

void BM_Embree(benchmark::State& state) {
  const EmbreeGrid embree(setup().grid);
  size_t hits = 0;
  for (auto _ : state)
    for (const Ray& r : setup().rays) hits += embree.intersect(r);
  state.counters["rays"] = benchmark::Counter(double(state.iterations()) * setup().rays.size(),
                                              benchmark::Counter::kIsRate);
  state.counters["hit_fraction"] = double(hits) / (double(state.iterations()) * setup().rays.size());
}

void BM_Rayes(benchmark::State& state) {
  size_t hits = 0;
  for (auto _ : state)
    for (const Ray& r : setup().rays) {
      GridHit h;
      hits += setup().grid.intersect(r.org, r.dir, 0.0f, kInf, kLevel, h);
    }
  state.counters["rays"] = benchmark::Counter(double(state.iterations()) * setup().rays.size(),
                                              benchmark::Counter::kIsRate);
  state.counters["hit_fraction"] = double(hits) / (double(state.iterations()) * setup().rays.size());
}

// Both in one run, alternating, so machine noise hits both alike: ratio = ours / Embree.
void BM_Compare(benchmark::State& state) {
  const EmbreeGrid embree(setup().grid);
  using Clock = std::chrono::steady_clock;
  double ours = 0, theirs = 0;
  size_t agree = 0, total = 0;
  for (auto _ : state) {
    std::vector<char> a(setup().rays.size()), b(setup().rays.size());
    auto t0 = Clock::now();
    for (size_t k = 0; k < setup().rays.size(); ++k) {
      GridHit h;
      const Ray& r = setup().rays[k];
      a[k] = setup().grid.intersect(r.org, r.dir, 0.0f, kInf, kLevel, h);
    }
    auto t1 = Clock::now();
    for (size_t k = 0; k < setup().rays.size(); ++k) b[k] = embree.intersect(setup().rays[k]);
    auto t2 = Clock::now();
    ours += std::chrono::duration<double>(t1 - t0).count();
    theirs += std::chrono::duration<double>(t2 - t1).count();
    for (size_t k = 0; k < a.size(); ++k) agree += a[k] == b[k];
    total += a.size();
  }
  const double rays = double(total);
  state.counters["rayes_Mrays_s"] = rays / ours * 1e-6;
  state.counters["embree_Mrays_s"] = rays / theirs * 1e-6;
  state.counters["ratio_rayes_over_embree"] = theirs / ours;
  state.counters["hit_agreement"] = double(agree) / rays;
}

// Build of the same grid: ours is dice + tree (bench_dicing_bvh BM_DiceAndBuild/8); Embree's
// is from already diced vertices.
void BM_EmbreeBuild(benchmark::State& state) {
  for (auto _ : state) {
    EmbreeGrid embree(setup().grid);
    benchmark::DoNotOptimize(&embree);
  }
  state.counters["per_micropolygon"] = benchmark::Counter(
      double(state.iterations()) * double(1 << (2 * kLevel)), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

BENCHMARK(BM_Rayes)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Embree)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Compare)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EmbreeBuild)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
