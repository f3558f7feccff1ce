// Peer comparison (the brief: "performance is measured against a peer in one run, as a ratio:
// Embree with full tessellation"). One program, one run, a plain table on stdout.
//
// Scene: the Utah teapot (scenes/teapot.bpt, 32 bicubic Bezier patches) on a floor quad (one
// bilinear patch; --no-floor leaves it out). Two ray sets:
//   primary     512x512 camera rays of a view that frames the teapot, pixel footprint as the
//               renderer gives it (coneWidth 0, coneSpread = 2 tan(fov/2) / height);
//   incoherent  the same number of rays from random points on a sphere around the teapot
//               towards random points inside its box (same cone spread).
// For each level m (default 4, 6, 8) and two LOD modes:
//   footprint   TraceSettings.maxLod = m, each ray at its own level <= m (the renderer's way);
//   forced      coneWidth = coneSpread = 0, so every ray is intersected at level m exactly:
//               the like-for-like comparison with Embree's full tessellation at m.
// Engines:
//   Rayes   TopLevelBvh over the patch boxes + SortedEngine::trace of the whole RayBatch (all threads,
//           then 1 thread via tbb::global_control); a fresh SortedEngine per thread setting so its
//           dice-buffer bytes are that setting's; one untimed warm-up trace, best of --repeat.
//   Embree  the renderer's EmbreeEngine (rays/embree_engine.h) at --embree-lod fixed m: every
//           patch diced at m up front into one Embree grid per patch (rows mirrored so both
//           engines intersect the same triangles), traced with rtcIntersect1M in parallel chunks;
//           its tessellation and rtcCommitScene are timed separately; best of --repeat.
// Memory: Rayes = top-level nodes + dice buffers (all threads) + candidate buffer with the
// sort's scratch (SortedEngine::candidateBufferBytes) + per-ray state. Embree = the engine's vertices (positions and normals: what a renderer
// needs to shade) + every byte Embree allocates, from its memory monitor (peak during the build
// and held after it).
// Agreement: per ray, hit/miss differs; for rays both hit, |t_rayes - t_embree| (median, p99)
// and whether the patch differs.
//
// Run (from anywhere): bench_peer_embree [--teapot PATH] [--levels 4,6,8] [--size 512]
//                      [--repeat 3] [--no-floor] [--no-single]
// For whole renders, Rayes against the Embree engine: bench/peer_render.sh.
// Figures in bench/history/RESULTS-peer.md.
#include <embree3/rtcore_config.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <unistd.h>
#include <vector>

#include "core/memory.h"
#include "core/ray_batch.h"
#include "core/rng.h"
#include "core/timer.h"
#include "geometry/bezier_patch.h"
#include "geometry/bilinear_patch.h"
#include "rays/embree_engine.h"
#include "rays/sorted_engine.h"
#include "toplevel/toplevel_bvh.h"

namespace {

using namespace rayes;
constexpr float kInf = std::numeric_limits<float>::infinity();

// ---- options ----------------------------------------------------------------------------
struct Options {
  std::string teapot;
  std::vector<int> levels{4, 6, 8};
  int size = 512;
  int repeat = 3;
  bool floor = true, single = true;
};

std::string findTeapot(const char* argv0) {
  namespace fs = std::filesystem;
  std::vector<fs::path> tries{"scenes/teapot.bpt", "../scenes/teapot.bpt", "../../scenes/teapot.bpt"};
  std::error_code ec;
  const fs::path exe = fs::canonical("/proc/self/exe", ec);
  if (!ec)  // <build>/bin/bench_peer_embree: the tree is usually <build>/..
    for (fs::path d = exe.parent_path(); !d.empty() && d != d.root_path(); d = d.parent_path())
      tries.push_back(d / "scenes/teapot.bpt");
  (void)argv0;
  tries.push_back("/work/main/scenes/teapot.bpt");
  for (const fs::path& p : tries)
    if (fs::exists(p, ec)) return p.string();
  return {};
}

bool parse(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> const char* { return i + 1 < argc ? argv[++i] : nullptr; };
    if (a == "--teapot") { const char* v = next(); if (!v) return false; o.teapot = v; }
    else if (a == "--levels") {
      const char* v = next(); if (!v) return false;
      o.levels.clear();
      for (const char* p = v; *p;) {
        char* end;
        const long m = std::strtol(p, &end, 10);
        if (end == p || m < 0 || m > 12) return false;
        o.levels.push_back(int(m));
        p = *end == ',' ? end + 1 : end;
        if (*end && *end != ',') return false;
      }
    }
    else if (a == "--size") { const char* v = next(); if (!v) return false; o.size = std::atoi(v); }
    else if (a == "--repeat") { const char* v = next(); if (!v) return false; o.repeat = std::max(1, std::atoi(v)); }
    else if (a == "--no-floor") o.floor = false;
    else if (a == "--no-single") o.single = false;
    else return false;
  }
  return o.size > 0;
}

// ---- scene and rays ---------------------------------------------------------------------
struct Scene {
  std::vector<PatchPtr> patches;
  Box3 teapotBox;
  int teapotPatches = 0;
};

Scene makeScene(const Options& o) {
  Scene s;
  for (const auto& cp : loadBezierPatchFile(o.teapot)) {
    s.patches.push_back(std::make_shared<BezierPatch>(cp));
    s.teapotBox.extend(s.patches.back()->bounds());
  }
  s.teapotPatches = int(s.patches.size());
  if (o.floor) {  // z-up, under the teapot, 3x its footprint
    const Vec3 c = s.teapotBox.center(), e = s.teapotBox.extent();
    const float r = 1.5f * std::max(e.x, e.y);
    const float z = s.teapotBox.lo.z;
    s.patches.push_back(std::make_shared<BilinearPatch>(Vec3{c.x - r, c.y - r, z}, Vec3{c.x + r, c.y - r, z},
                                                        Vec3{c.x - r, c.y + r, z}, Vec3{c.x + r, c.y + r, z}));
  }
  return s;
}

// Camera from scenes/teapot.json's direction (front, above), 40 degree field of view, at the
// distance where the teapot's bounding sphere just fills the frame.
struct Camera {
  Vec3 pos, forward, right, up;
  float tanHalf, spread;
};

Camera makeCamera(const Box3& box, int size) {
  const float fov = 40.0f * std::numbers::pi_v<float> / 180.0f;
  const Vec3 c = box.center();
  const float radius = 0.5f * length(box.extent());
  const Vec3 back = normalize(Vec3{-0.25f, -9.5f, 2.7f});  // teapot.json: position - look_at
  Camera cam;
  cam.pos = c + back * (radius / std::sin(0.5f * fov));
  cam.forward = -back;
  cam.right = normalize(cross(cam.forward, Vec3{0, 0, 1}));
  cam.up = cross(cam.right, cam.forward);
  cam.tanHalf = std::tan(0.5f * fov);
  cam.spread = 2.0f * cam.tanHalf / float(size);
  return cam;
}

struct RaySet {
  std::string name;
  std::vector<Vec3> org, dir;
  float spread = 0;  // coneSpread in footprint mode
};

RaySet primaryRays(const Camera& cam, int size) {
  RaySet r{"primary", {}, {}, cam.spread};
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const float sx = (2.0f * (float(x) + 0.5f) / float(size) - 1.0f) * cam.tanHalf;
      const float sy = (1.0f - 2.0f * (float(y) + 0.5f) / float(size)) * cam.tanHalf;
      r.org.push_back(cam.pos);
      r.dir.push_back(normalize(cam.forward + cam.right * sx + cam.up * sy));
    }
  return r;
}

RaySet incoherentRays(const Box3& box, size_t n, float spread) {
  RaySet r{"incoherent", {}, {}, spread};
  auto uni = [](uint64_t i, uint64_t d) { return bitsToUnitFloat(mix64(mix64(i * 0x9e3779b97f4a7c15ull + 7) ^ d)); };
  const Vec3 c = box.center(), e = box.extent();
  const float radius = length(e);  // twice the bounding sphere's radius
  for (size_t i = 0; i < n; ++i) {
    // uniform direction on the sphere
    const float z = 2.0f * uni(i, 1) - 1.0f, phi = 2.0f * std::numbers::pi_v<float> * uni(i, 2);
    const float s = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const Vec3 o = c + Vec3{s * std::cos(phi), s * std::sin(phi), z} * radius;
    const Vec3 target = box.lo + Vec3{uni(i, 3), uni(i, 4), uni(i, 5)} * e;
    r.org.push_back(o);
    r.dir.push_back(normalize(target - o));
  }
  return r;
}

void fillBatch(const RaySet& rs, bool forced, RayBatch& b) {
  b.resize(rs.org.size());
  for (size_t i = 0; i < rs.org.size(); ++i)
    b.setFromNowhere(i, RayKind::Closest, rs.org[i], rs.dir[i], kInf, 0.0f, forced ? 0.0f : rs.spread);
}

// ---- Embree -----------------------------------------------------------------------------
struct EmbreeRun {
  std::unique_ptr<EmbreeEngine> engine;
  EngineStats stats;
};

EmbreeRun buildEmbree(const std::vector<PatchPtr>& patches, int m) {
  EmbreeSettings es;
  es.maxLod = m;
  EmbreeRun run{std::make_unique<EmbreeEngine>(StoredLeaves(patches), es), {}};
  run.stats = run.engine->engineStats();
  return run;
}

// Best wall time of --repeat traces of the whole set (hits left in `batch`).
double traceEmbree(EmbreeEngine& engine, const RaySet& rs, int repeat, RayBatch& batch) {
  double best = kInf;
  for (int r = 0; r < repeat; ++r) {
    fillBatch(rs, true, batch);
    GenerationStats st;
    TraceTimes tt;
    const auto t0 = Clock::now();
    engine.trace(batch, st, tt);
    best = std::min(best, secondsSince(t0));
  }
  return best;
}

// ---- Rayes ------------------------------------------------------------------------------
struct RayesRun {
  double seconds = 0;  // best trace wall time
  struct { double toplevel = 0, sort = 0, dice = 0, bottom = 0; } times;  // of the best run (s)
  GenerationStats stats;
  size_t diceBytes = 0, candBytes = 0, rayStateBytes = 0;
  size_t iterations = 0;
};

RayesRun runRayes(const TopLevelBvh& top, const std::vector<PatchPtr>& patches, const TraceSettings& ts,
                  const RaySet& rs, bool forced, int repeat, RayBatch& batch) {
  RayesRun run;
  const StoredLeaves source(patches);
  SortedEngine engine(top, source, ts);
  {  // warm-up: allocates the dice buffers and per-ray state
    fillBatch(rs, forced, batch);
    GenerationStats st;
    TraceTimes tt;
    engine.trace(batch, st, tt);
  }
  run.seconds = kInf;
  for (int r = 0; r < repeat; ++r) {
    fillBatch(rs, forced, batch);
    auto st = std::make_unique<GenerationStats>();
    auto tt = std::make_unique<TraceTimes>();
    const auto t0 = Clock::now();
    engine.trace(batch, *st, *tt);
    const double s = secondsSince(t0);
    if (s < run.seconds) {
      run.seconds = s;
      run.stats = *st;
      run.times = {tt->toplevel.seconds(), tt->sort.seconds(), tt->dice.seconds(), tt->bottom.seconds()};
    }
  }
  run.diceBytes = engine.diceBufferBytes();
  run.candBytes = engine.candidateBufferBytes();
  run.rayStateBytes = SortedEngine::bytesPerRayState() * rs.org.size();
  run.iterations = run.stats.iterations.size();
  return run;
}

// ---- agreement --------------------------------------------------------------------------
struct Agreement {
  double hitMissDiffers = 0, leafDiffers = 0, medianDt = 0, p99Dt = 0, medianRelDt = 0;
  size_t bothHit = 0, rayesHits = 0, embreeHits = 0;
};

Agreement compare(const RayBatch& b, const RayBatch& e) {
  Agreement a;
  std::vector<float> dt, rel;
  size_t differ = 0, leafDiff = 0;
  for (size_t i = 0; i < b.size(); ++i) {
    const bool rh = b.hit[i].valid(), eh = e.hit[i].valid();
    a.rayesHits += rh;
    a.embreeHits += eh;
    if (rh != eh) { ++differ; continue; }
    if (!rh) continue;
    ++a.bothHit;
    leafDiff += b.hit[i].leaf != e.hit[i].leaf;
    dt.push_back(std::fabs(b.hit[i].t - e.hit[i].t));
    rel.push_back(dt.back() / std::max(e.hit[i].t, 1e-30f));
  }
  const double n = double(b.size());
  a.hitMissDiffers = double(differ) / n;
  a.leafDiffers = a.bothHit ? double(leafDiff) / double(a.bothHit) : 0;
  auto quantile = [](std::vector<float>& v, double q) -> double {
    if (v.empty()) return 0;
    const size_t k = std::min(v.size() - 1, size_t(q * double(v.size())));
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
    return v[k];
  };
  a.medianDt = quantile(dt, 0.5);
  a.p99Dt = quantile(dt, 0.99);
  a.medianRelDt = quantile(rel, 0.5);
  return a;
}

double mb(double bytes) { return bytes / (1024.0 * 1024.0); }

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (!parse(argc, argv, o)) {
    std::fprintf(stderr,
                 "usage: %s [--teapot PATH] [--levels 4,6,8] [--size 512] [--repeat 3] [--no-floor] "
                 "[--no-single]\n", argv[0]);
    return 2;
  }
  if (o.teapot.empty()) o.teapot = findTeapot(argv[0]);
  if (o.teapot.empty()) {
    std::fprintf(stderr, "scenes/teapot.bpt not found; pass --teapot PATH\n");
    return 2;
  }
  const Scene scene = makeScene(o);
  const Camera cam = makeCamera(scene.teapotBox, o.size);
  const std::vector<RaySet> sets{primaryRays(cam, o.size),
                                 incoherentRays(scene.teapotBox, size_t(o.size) * size_t(o.size), cam.spread)};
  const int threads = tbb::info::default_concurrency();
  const size_t nRays = sets[0].org.size();
  char cpu[512] = "?";
  if (FILE* f = std::fopen("/proc/cpuinfo", "r")) {
    char line[512];
    while (std::fgets(line, sizeof line, f))
      if (std::strncmp(line, "model name", 10) == 0) {
        const char* c = std::strchr(line, ':');
        std::snprintf(cpu, sizeof cpu, "%s", c ? c + 2 : line);
        cpu[std::strcspn(cpu, "\n")] = 0;
        break;
      }
    std::fclose(f);
  }
  std::printf("# peer_embree: Rayes vs Embree %d.%d.%d (grid geometry, full tessellation)\n", RTC_VERSION_MAJOR,
              RTC_VERSION_MINOR, RTC_VERSION_PATCH);
  std::printf("machine: %s, %d threads (tbb default_concurrency), nproc %ld\n", cpu, threads,
              sysconf(_SC_NPROCESSORS_ONLN));
  std::printf("scene: %s, %d teapot patches%s; %zu rays per set, %dx%d view, fov 40, cone spread %.3g\n",
              o.teapot.c_str(), scene.teapotPatches, o.floor ? " + 1 floor patch" : "", nRays, o.size, o.size,
              double(cam.spread));
  std::printf("repeat %d (best of); Embree: the renderer's EmbreeEngine (grid rows mirrored: same triangles as Rayes)\n\n", o.repeat);

  // Embree's first commit in a process pays its one-time start-up (measured 56 ms for a level-4
  // teapot whose second build takes 1 ms): a throwaway scene takes it out of the build times.
  { EmbreeRun warmUp = buildEmbree(scene.patches, 0); }

  // Top level: built once (33 boxes); its build time is reported.
  std::vector<Box3> boxes;
  for (const PatchPtr& p : scene.patches) boxes.push_back(p->bounds());
  TopLevelBvh top;
  const auto tb = Clock::now();
  top.build(boxes);
  const double topBuild = secondsSince(tb);

  struct Row {
    std::string rays, lod;
    int m;
    RayesRun rayesAll, rayesOne;
    double embreeAll = 0, embreeOne = 0, tess = 0, build = 0, buildOne = 0;
    size_t embreeVertexBytes = 0;
    int64_t embreeHeld = 0, embreePeak = 0;
    Agreement agree;
    uint64_t embreeMicropolygons = 0;
  };
  std::vector<Row> rows;
  RayBatch batch, embreeBatch;
  for (int m : o.levels) {
    // Embree scene at level m, built with all threads (and once more with 1 thread for the
    // single-thread build time).
    EmbreeRun embree = buildEmbree(scene.patches, m);
    double buildOne = 0;
    if (o.single) {
      tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
      const EmbreeRun e1 = buildEmbree(scene.patches, m);
      buildOne = e1.stats.tessellateSeconds + e1.stats.buildSeconds;
    }
    for (const RaySet& rs : sets)
      for (bool forced : {false, true}) {
        Row row;
        row.rays = rs.name;
        row.lod = forced ? "forced" : "footprint";
        row.m = m;
        row.tess = embree.stats.tessellateSeconds;
        row.build = embree.stats.buildSeconds;
        row.buildOne = buildOne;
        row.embreeVertexBytes = embree.stats.vertexBytes;
        row.embreeHeld = int64_t(embree.stats.embreeBytes);
        row.embreePeak = int64_t(embree.stats.embreePeakBytes);
        row.embreeMicropolygons = embree.stats.micropolygons;
        TraceSettings ts;
        ts.maxLod = m;
        ts.candidateCapacity = 8 * nRays;  // the renderer's: 4 slots per ray slot, 2 per path
        // Embree, all threads then 1 thread.
        if (o.single) {
          tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
          row.embreeOne = traceEmbree(*embree.engine, rs, o.repeat, embreeBatch);
        }
        row.embreeAll = traceEmbree(*embree.engine, rs, o.repeat, embreeBatch);
        // Rayes.
        row.rayesAll = runRayes(top, scene.patches, ts, rs, forced, o.repeat, batch);
        row.agree = compare(batch, embreeBatch);
        if (o.single) {
          tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
          row.rayesOne = runRayes(top, scene.patches, ts, rs, forced, o.repeat, batch);
        }
        rows.push_back(std::move(row));
        const Row& w = rows.back();
        std::fprintf(stderr, "done %s %s m=%d: rayes %.1f ms, embree %.1f ms\n", w.rays.c_str(), w.lod.c_str(),
                     m, w.rayesAll.seconds * 1e3, w.embreeAll * 1e3);
      }
  }

  const double mr = double(nRays) * 1e-6;
  std::printf("## Speed (%d threads; 1 thread in the t1 columns). Mrays/s = rays / best trace wall time\n\n", threads);
  std::printf("| rays | LOD | m | Rayes Mrays/s | Embree Mrays/s | Rayes/Embree time | incl. build | Rayes t1 Mrays/s | Embree t1 Mrays/s | t1 ratio | t1 incl. build | Embree tess+build ms (t1) |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows) {
    const double incl = (topBuild + r.rayesAll.seconds) / (r.tess + r.build + r.embreeAll);
    std::printf("| %s | %s | %d | %.2f | %.2f | %.2f | %.2f |", r.rays.c_str(), r.lod.c_str(), r.m,
                mr / r.rayesAll.seconds, mr / r.embreeAll, r.rayesAll.seconds / r.embreeAll, incl);
    if (o.single)
      std::printf(" %.2f | %.2f | %.2f | %.2f | %.1f+%.1f (%.1f) |\n", mr / r.rayesOne.seconds, mr / r.embreeOne,
                  r.rayesOne.seconds / r.embreeOne, (topBuild + r.rayesOne.seconds) / (r.buildOne + r.embreeOne),
                  r.tess * 1e3, r.build * 1e3, r.buildOne * 1e3);
    else
      std::printf(" - | - | - | - | %.1f+%.1f |\n", r.tess * 1e3, r.build * 1e3);
  }
  std::printf("\nRayes top-level build (33 boxes, once): %.3f ms. 'incl. build' = (top build + Rayes trace) / "
              "(Embree tessellation + rtcCommitScene + trace).\n\n", topBuild * 1e3);

  std::printf("## Where Rayes's time goes (all threads; toplevel and sort wall clock, dice and bottom summed over threads)\n\n");
  std::printf("| rays | LOD | m | trace ms | toplevel ms | sort ms | dice ms | bottom ms | iterations | candidates/ray | leaves diced | micropolygons Rayes | micropolygons Embree | t1 trace ms | t1 toplevel | t1 sort | t1 dice | t1 bottom |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows) {
    const RayesRun& a = r.rayesAll;
    uint64_t candidates = 0;
    for (const IterationStats& it : a.stats.iterations) candidates += it.candidates;
    std::printf("| %s | %s | %d | %.1f | %.1f | %.1f | %.1f | %.1f | %zu | %.2f | %llu | %.3g | %.3g |", r.rays.c_str(),
                r.lod.c_str(), r.m, a.seconds * 1e3, a.times.toplevel * 1e3, a.times.sort * 1e3,
                a.times.dice * 1e3, a.times.bottom * 1e3, a.iterations, double(candidates) / double(nRays),
                (unsigned long long)a.stats.leavesDiced, double(a.stats.micropolygonsCreated),
                double(r.embreeMicropolygons));
    if (o.single) {
      const RayesRun& b = r.rayesOne;
      std::printf(" %.1f | %.1f | %.1f | %.1f | %.1f |\n", b.seconds * 1e3, b.times.toplevel * 1e3,
                  b.times.sort * 1e3, b.times.dice * 1e3, b.times.bottom * 1e3);
    } else {
      std::printf(" - | - | - | - | - |\n");
    }
  }

  std::printf("\n## Memory (MiB; Rayes all threads = %d dice buffers)\n\n", threads);
  std::printf("| rays | LOD | m | Rayes top | dice bufs | cand buf + sort | ray state | Rayes total | Rayes total excl. ray-sized | Embree vertices | Embree held | Embree peak | Embree total (vert+peak) | Rayes/Embree | excl. ray-sized |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows) {
    const RayesRun& a = r.rayesAll;
    const double rayes = double(top.bytes() + a.diceBytes + a.candBytes + a.rayStateBytes);
    const double fixed = double(top.bytes() + a.diceBytes);
    const double embree = double(r.embreeVertexBytes) + double(r.embreePeak);
    std::printf("| %s | %s | %d | %.3f | %.2f | %.1f | %.1f | %.1f | %.2f | %.1f | %.1f | %.1f | %.1f | %.3f | %.3f |\n",
                r.rays.c_str(), r.lod.c_str(), r.m, mb(double(top.bytes())), mb(double(a.diceBytes)),
                mb(double(a.candBytes)), mb(double(a.rayStateBytes)), mb(rayes),
                mb(fixed), mb(double(r.embreeVertexBytes)), mb(double(r.embreeHeld)), mb(double(r.embreePeak)),
                mb(embree), rayes / embree, fixed / embree);
  }

  std::printf("\n## Agreement (Rayes all-thread run vs Embree, per ray)\n\n");
  std::printf("| rays | LOD | m | Rayes hits | Embree hits | hit/miss differs | patch differs (both hit) | median abs dt | p99 abs dt | median rel dt |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows) {
    const Agreement& g = r.agree;
    std::printf("| %s | %s | %d | %zu | %zu | %.2e | %.2e | %.3g | %.3g | %.3g |\n", r.rays.c_str(), r.lod.c_str(),
                r.m, g.rayesHits, g.embreeHits, g.hitMissDiffers, g.leafDiffers, g.medianDt, g.p99Dt,
                g.medianRelDt);
  }
  std::printf("\npeak RSS of the process: %.1f MiB\n", mb(double(peakRssBytes())));
  return 0;
}
