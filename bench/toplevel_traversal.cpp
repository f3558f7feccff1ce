// Top-level figures: collect() throughput (one thread and all threads), build time and Embree's
// own traversal as a peer. (The candidate sort, now production code in src/rays, is measured by
// bench/rays_candidate_sort.cpp.) Run: bench_toplevel_traversal --benchmark_min_time=0.2 ; figures
// in bench/history/RESULTS-toplevel.md.
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/box.h"
#include "core/rng.h"
#include "toplevel/toplevel_bvh.h"

namespace {

using namespace rayes;
constexpr float kInf = std::numeric_limits<float>::infinity();

struct Rng {
  uint64_t state;
  float uniform() { return bitsToUnitFloat(mix64(state++ * 0x9e3779b97f4a7c15ull + 1)); }
  float uniform(float a, float b) { return a + (b - a) * uniform(); }
};

struct Ray { Vec3 org, dir; };

// n small random boxes (edge 0.2..1.5) in [0,100]^3: an incoherent, deep scene.
std::vector<Box3> randomBoxes(size_t n, uint64_t seed) {
  Rng rng{seed};
  std::vector<Box3> boxes(n);
  for (Box3& b : boxes) {
    const Vec3 lo{rng.uniform(0, 100), rng.uniform(0, 100), rng.uniform(0, 100)};
    b = {lo, lo + Vec3{rng.uniform(0.2f, 1.5f), rng.uniform(0.2f, 1.5f), rng.uniform(0.2f, 1.5f)}};
  }
  return boxes;
}

// A displaced surface cut into 256x256 patches, like the boxes of a diced terrain.
std::vector<Box3> surfaceBoxes() {
  constexpr int kRes = 256;
  auto height = [](float x, float y) { return 5 * std::sin(x / 10) * std::cos(y / 13); };
  std::vector<Box3> boxes;
  for (int j = 0; j < kRes; ++j)
    for (int i = 0; i < kRes; ++i) {
      const float x0 = 100.0f * i / kRes, x1 = 100.0f * (i + 1) / kRes;
      const float y0 = 100.0f * j / kRes, y1 = 100.0f * (j + 1) / kRes;
      Box3 b;
      for (float x : {x0, x1})
        for (float y : {y0, y1}) b.extend(Vec3{x, y, height(x, y)});
      boxes.push_back({b.lo - Vec3{0, 0, 0.3f}, b.hi + Vec3{0, 0, 0.3f}});  // displacement bound
    }
  return boxes;
}

// Rays from a sphere around [0,100]^3 towards random points inside it.
std::vector<Ray> raysThroughCube(size_t n, uint64_t seed) {
  Rng rng{seed};
  std::vector<Ray> rays(n);
  for (Ray& r : rays) {
    const Vec3 d = normalize(Vec3{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)});
    r.org = Vec3{50, 50, 50} + d * 150.0f;
    const Vec3 target{rng.uniform(0, 100), rng.uniform(0, 100), rng.uniform(0, 100)};
    r.dir = normalize(target - r.org);
  }
  return rays;
}

// Camera-like rays from one point above the surface at a grazing angle.
std::vector<Ray> raysOntoSurface(size_t n, uint64_t seed) {
  Rng rng{seed};
  std::vector<Ray> rays(n);
  for (Ray& r : rays) {
    r.org = {50, -40, 40};
    r.dir = normalize(Vec3{rng.uniform(0, 100), rng.uniform(0, 100), 0} - r.org);
  }
  return rays;
}

struct Scene {
  std::vector<Box3> boxes;
  std::vector<Ray> rays;
  TopLevelBvh bvh;
};

Scene& scene(int which) {
  static Scene scenes[2];
  Scene& s = scenes[which];
  if (s.boxes.empty()) {
    s.boxes = which == 0 ? randomBoxes(100000, 1) : surfaceBoxes();
    s.rays = which == 0 ? raysThroughCube(1 << 16, 2) : raysOntoSurface(1 << 16, 3);
    s.bvh.build(s.boxes);
  }
  return s;
}
const char* sceneName(int which) { return which == 0 ? "random100k" : "surface65k"; }

void setRayRate(benchmark::State& state, size_t raysPerIteration) {
  state.counters["Mrays/s"] = benchmark::Counter(
      double(raysPerIteration) * double(state.iterations()) * 1e-6, benchmark::Counter::kIsRate);
}

// One collect() of N candidates per ray (the first call of a trace).
void BM_Collect(benchmark::State& state) {
  Scene& s = scene(int(state.range(0)));
  const int maxCount = int(state.range(1));
  const bool parallel = state.range(2) != 0;
  state.SetLabel(sceneName(int(state.range(0))));
  tbb::enumerable_thread_specific<TraversalScratch> scratch;
  size_t candidates = 0;
  for (auto _ : state) {
    if (parallel) {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, s.rays.size(), 256), [&](const auto& range) {
        Candidate out[128];
        float next;
        TraversalScratch& local = scratch.local();
        for (size_t i = range.begin(); i != range.end(); ++i)
          s.bvh.collect(s.rays[i].org, s.rays[i].dir, 0, kInf, -kInf, 0, out, maxCount, next, local);
      });
    } else {
      Candidate out[128];
      float next;
      TraversalScratch& local = scratch.local();
      candidates = 0;
      for (const Ray& r : s.rays)
        candidates += s.bvh.collect(r.org, r.dir, 0, kInf, -kInf, 0, out, maxCount, next, local);
    }
  }
  setRayRate(state, s.rays.size());
  if (!parallel) state.counters["cand/ray"] = double(candidates) / double(s.rays.size());
}
BENCHMARK(BM_Collect)
    ->ArgNames({"scene", "N", "par"})
    ->ArgsProduct({{0, 1}, {1, 8}, {0, 1}})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// Every candidate of every ray, 8 per call, resuming from the last one: the cost of the
// generation loop's repeated top-level passes.
void BM_CollectAllResumed(benchmark::State& state) {
  Scene& s = scene(int(state.range(0)));
  state.SetLabel(sceneName(int(state.range(0))));
  TraversalScratch scratch;
  size_t calls = 0, candidates = 0;
  for (auto _ : state) {
    calls = candidates = 0;
    for (const Ray& r : s.rays) {
      Candidate out[8];
      float next = 0, resumeEntry = -kInf;
      uint32_t resumeLeaf = 0;
      while (next != kInf) {
        const int n = s.bvh.collect(r.org, r.dir, 0, kInf, resumeEntry, resumeLeaf, out, 8, next, scratch);
        ++calls;
        candidates += size_t(n);
        if (n > 0) { resumeEntry = out[n - 1].entry; resumeLeaf = out[n - 1].leaf; }
      }
    }
  }
  setRayRate(state, s.rays.size());
  state.counters["cand/ray"] = double(candidates) / double(s.rays.size());
  state.counters["calls/ray"] = double(calls) / double(s.rays.size());
}
BENCHMARK(BM_CollectAllResumed)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// ---- Embree peer: user geometry of the same boxes, rtcIntersect1 finds the box with the
// nearest entry (the same answer as collect() with N = 1). The box test is ours (intersectBox),
// with the reciprocal direction precomputed once per ray through the context.
struct BoxContext {
  RTCIntersectContext context;  // first member: Embree hands us back a pointer to it
  RayBoxQuery query{Vec3{}, Vec3{1, 1, 1}};
};

void boxBounds(const RTCBoundsFunctionArguments* args) {
  const Box3& b = static_cast<const Box3*>(args->geometryUserPtr)[args->primID];
  *args->bounds_o = {b.lo.x, b.lo.y, b.lo.z, 0, b.hi.x, b.hi.y, b.hi.z, 0};
}

void boxIntersect(const RTCIntersectFunctionNArguments* args) {
  if (!args->valid[0]) return;  // rtcIntersect1: N == 1
  const Box3& b = static_cast<const Box3*>(args->geometryUserPtr)[args->primID];
  auto* rayhit = reinterpret_cast<RTCRayHit*>(args->rayhit);
  const auto* ctx = reinterpret_cast<const BoxContext*>(args->context);
  float entry, exit;
  if (!intersectBox(ctx->query, b.lo, b.hi, rayhit->ray.tnear, rayhit->ray.tfar, entry, exit)) return;
  if (entry == rayhit->ray.tfar && args->primID > rayhit->hit.primID) return;  // ties by id
  rayhit->ray.tfar = entry;
  rayhit->hit.geomID = args->geomID;
  rayhit->hit.primID = args->primID;
}

struct EmbreePeer {
  RTCDevice device = rtcNewDevice(nullptr);
  RTCScene scene = rtcNewScene(device);
  explicit EmbreePeer(const std::vector<Box3>& boxes) {
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(g, unsigned(boxes.size()));
    rtcSetGeometryUserData(g, const_cast<Box3*>(boxes.data()));
    rtcSetGeometryBoundsFunction(g, boxBounds, nullptr);
    rtcSetGeometryIntersectFunction(g, boxIntersect);
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);  // conservative node culling, like ours
    rtcCommitScene(scene);
  }
  ~EmbreePeer() { rtcReleaseScene(scene); rtcReleaseDevice(device); }
  // Entry distance of the nearest box, +inf if none.
  float first(const Ray& r, uint32_t& leaf) const {
    BoxContext ctx;
    rtcInitIntersectContext(&ctx.context);
    ctx.query = RayBoxQuery(r.org, r.dir);
    RTCRayHit rh{};
    rh.ray = {r.org.x, r.org.y, r.org.z, 0, r.dir.x, r.dir.y, r.dir.z, 0, kInf, 0xffffffffu, 0, 0};
    rh.hit.geomID = rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &ctx.context, &rh);
    leaf = rh.hit.primID;
    return rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? kInf : rh.ray.tfar;
  }
};

void BM_EmbreeFirstBox(benchmark::State& state) {
  Scene& s = scene(int(state.range(0)));
  state.SetLabel(sceneName(int(state.range(0))));
  const EmbreePeer peer(s.boxes);
  // The answers should be collect(N = 1)'s; rays that graze a box edge may differ when Embree's
  // node test rounds differently, so the mismatch rate is reported rather than required zero.
  TraversalScratch scratch;
  size_t mismatches = 0;
  for (const Ray& r : s.rays) {
    Candidate c{0, kInf};
    float next;
    s.bvh.collect(r.org, r.dir, 0, kInf, -kInf, 0, &c, 1, next, scratch);
    uint32_t leaf;
    mismatches += peer.first(r, leaf) != c.entry || (c.entry != kInf && leaf != c.leaf);
  }
  for (auto _ : state) {
    uint32_t leaf;
    for (const Ray& r : s.rays) benchmark::DoNotOptimize(peer.first(r, leaf));
  }
  setRayRate(state, s.rays.size());
  state.counters["mismatch"] = double(mismatches) / double(s.rays.size());
}
BENCHMARK(BM_EmbreeFirstBox)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_Build(benchmark::State& state) {
  const std::vector<Box3> boxes = randomBoxes(size_t(state.range(0)), 7);
  for (auto _ : state) {
    TopLevelBvh bvh;
    bvh.build(boxes);
    benchmark::DoNotOptimize(bvh.nodeCount());
    state.counters["nodes"] = double(bvh.nodeCount());
    state.counters["MB"] = double(bvh.bytes()) / 1e6;
  }
}
BENCHMARK(BM_Build)->Arg(10000)->Arg(100000)->Arg(1000000)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
