#include "rays/embree_engine.h"
#include "core/memory.h"
#include <embree3/rtcore.h>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include "core/error.h"
#include "core/timer.h"
#include "dicing/dice_buffer.h"
#include "dicing/micro_quad.h"
#include "geometry/moving_patch.h"

namespace rayes {
namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr int kMaxTimeSegments = 64;
constexpr size_t kChunk = 256;  // rays per stream call

size_t gridVertices(int level) {
  const size_t res = (size_t(1) << level) + 1;
  return res * res;
}

// Embree's allocations, counted through the device's memory monitor.
struct MemoryMonitor {
  std::atomic<int64_t> current{0}, peak{0};
  static bool callback(void* user, ssize_t bytes, bool /*post*/) {
    auto* m = static_cast<MemoryMonitor*>(user);
    const int64_t now = m->current.fetch_add(bytes) + bytes;
    int64_t p = m->peak.load();
    while (now > p && !m->peak.compare_exchange_weak(p, now)) {}
    return true;
  }
};

// The intersect context with what the filter needs: the leaf each ray must not hit, by ray id.
struct FilterContext {
  RTCIntersectContext context;
  const Ray* rays = nullptr;
};

void rejectIgnoredLeaf(const RTCFilterFunctionNArguments* a) {
  const auto* ctx = reinterpret_cast<const FilterContext*>(a->context);
  for (unsigned k = 0; k < a->N; ++k) {
    if (a->valid[k] != -1) continue;
    if (RTCHitN_geomID(a->hit, a->N, k) == ctx->rays[RTCRayN_id(a->ray, a->N, k)].ignoreLeaf) a->valid[k] = 0;
  }
}

// A ray Embree may see: finite origin, a non-empty interval (the decoded direction is always a
// finite unit vector; a zero or non-finite one was aimed with tmax 0). The SortedEngine gives the
// others no hit; so does this engine, without asking Embree.
bool traceable(const RayBatch& b, uint32_t i) {
  const Vec3 o = b.ray[i].org;
  const bool finite = std::isfinite(o.x) && std::isfinite(o.y) && std::isfinite(o.z);
  return finite && 0.0f < b.ray[i].tmax;
}

void setRay(const RayBatch& b, uint32_t i, RTCRay& r) {
  const Vec3 d = b.ray[i].dir();
  r.org_x = b.ray[i].org.x; r.org_y = b.ray[i].org.y; r.org_z = b.ray[i].org.z;
  r.dir_x = d.x; r.dir_y = d.y; r.dir_z = d.z;
  r.tnear = 0.0f;
  r.tfar = b.ray[i].tmax;
  r.time = std::clamp(b.timeOf(i), 0.0f, 1.0f);
  r.mask = 0xffffffffu;
  r.id = i;
  r.flags = 0;
}
}  // namespace

struct EmbreeEngine::Device {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  MemoryMonitor memory;
  std::vector<RTCGrid> grids;  // one per leaf
  ~Device() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

int EmbreeEngine::autoLevel(const Box3& bounds, float size, const CameraFootprint& camera, int maxLod) {
  const Vec3 p = camera.position;
  const Vec3 out = vmax(vmax(bounds.lo - p, p - bounds.hi), Vec3{0, 0, 0});
  const float distance = std::max(0.0f, length(out) - camera.apertureRadius);
  return levelForFootprint(size, distance * camera.spread, maxLod);
}

int EmbreeEngine::timeSteps(const Patch& patch) {
  const int k = patch.timeSamples();
  if (k < 2) return 1;
  for (int n = 1; n <= kMaxTimeSegments; ++n) {
    bool onGrid = true;
    for (int s = 0; s < k && onGrid; ++s) {
      const double x = double(std::clamp(patch.sampleTime(s), 0.0f, 1.0f)) * n;
      onGrid = std::fabs(x - std::round(x)) <= 1e-4;
    }
    if (onGrid) return n + 1;
  }
  return kMaxTimeSegments + 1;
}

EmbreeEngine::EmbreeEngine(const LeafSource& patches, const EmbreeSettings& s) {
  stats_.name = "embree";
  leaves_.resize(patches.size());
  stats_.leafTableBytes = leaves_.capacity() * sizeof(Leaf);
  stats_.minLevel = s.maxLod;
  size_t vertices = 0;
  for (size_t i = 0; i < patches.size(); ++i) {
    const LeafFacts f = patches.facts(i);
    Leaf& leaf = leaves_[i];
    leaf.level = s.autoLod ? autoLevel(patches.bounds(i), f.sizeBound, s.camera, s.maxLod) : s.maxLod;
    leaf.steps = f.timeSamples > 1 ? timeSteps(*patches.patch(i)) : 1;
    leaf.first = vertices;
    vertices += gridVertices(leaf.level) * size_t(leaf.steps);
    stats_.micropolygons += (uint64_t(1) << (2 * leaf.level)) * uint64_t(leaf.steps);
    stats_.minLevel = std::min(stats_.minLevel, leaf.level);
    stats_.maxLevel = std::max(stats_.maxLevel, leaf.level);
  }
  if (patches.size() == 0) stats_.minLevel = 0;
  stats_.vertices = vertices;
  stats_.estimatedBytes = vertices * (kOwnBytesPerVertex + kEmbreeBytesPerVertex);
  const std::string perVertex = " (" + std::to_string(vertices) + " grid vertices x " +
                                std::to_string(kOwnBytesPerVertex + kEmbreeBytesPerVertex) + " B)";
  if (s.memoryLimit > 0 && stats_.estimatedBytes > s.memoryLimit)
    throw ResourceError("--memory-limit", "the Embree engine's full tessellation needs about " +
                                              readableBytes(stats_.estimatedBytes) + perVertex + ", more than the limit of " +
                                              readableBytes(s.memoryLimit) +
                                              " (by default 80 % of the memory limit: " + readMemoryLimit().describe() +
                                              "); lower --max-lod, use --embree-lod auto, or raise --memory-limit");
  // A --memory-limit above the memory limit that applies (a cgroup, ulimit -v) lets nothing more through.
  checkMemoryFits(stats_.estimatedBytes, "--memory-limit", "the Embree engine's full tessellation" + perVertex,
                  "--memory-limit cannot raise the memory limit that applies: lower --max-lod or use --embree-lod auto");
  tessellate(patches);
  build(s.robust);
}

EmbreeEngine::~EmbreeEngine() = default;

void EmbreeEngine::tessellate(const LeafSource& patches) {
  const auto t0 = Clock::now();
  positions_.resize(stats_.vertices + 1);  // + 1: Embree reads 16 bytes at the last vertex
  normals_.resize(stats_.vertices);
  stats_.vertexBytes = positions_.size() * sizeof(Vec3) + normals_.size() * sizeof(Vec3);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, patches.size(), 1), [&](const auto& r) {
    std::vector<Vec3> pa, na, pb, nb;
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const PatchPtr made = patches.patch(i);
      const Patch& patch = *made;
      const Leaf& leaf = leaves_[i];
      const size_t n = gridVertices(leaf.level), res = (size_t(1) << leaf.level) + 1;
      // Step j: the patch at time j / (steps - 1), blended between its keyframes like
      // MovingPatch (a static patch: its one dicing).
      int diced = -1;  // keyframe interval now in (pa, pb)
      for (int j = 0; j < leaf.steps; ++j) {
        Vec3* pos = positions_.data() + leaf.first + size_t(j) * n;
        Vec3* nrm = normals_.data() + leaf.first + size_t(j) * n;
        pa.resize(n); na.resize(n);
        if (leaf.steps == 1) {
          patch.dice(leaf.level, pa.data(), na.data());
          std::copy(na.begin(), na.end(), nrm);
        } else {
          const TimeInterval when = timeInterval(patch, float(j) / float(leaf.steps - 1));
          if (when.interval != diced) {
            pb.resize(n); nb.resize(n);
            patch.diceAt(when.interval, leaf.level, pa.data(), na.data());
            patch.diceAt(when.interval + 1, leaf.level, pb.data(), nb.data());
            diced = when.interval;
          }
          const float w1 = when.alpha, w0 = 1.0f - w1;
          for (size_t k = 0; k < n; ++k) {
            const Vec3 p = lerpPoint(pa[k], pb[k], w0, w1);
            nrm[k] = lerpPoint(na[k], nb[k], w0, w1);
            pos[(k / res) * res + (res - 1 - k % res)] = p;
          }
          continue;
        }
        for (size_t k = 0; k < n; ++k) pos[(k / res) * res + (res - 1 - k % res)] = pa[k];
      }
    }
  });
  stats_.tessellateSeconds = secondsSince(t0);
}

void EmbreeEngine::build(bool robust) {
  device_ = std::make_unique<Device>();
  Device& d = *device_;
  d.device = rtcNewDevice(nullptr);
  if (!d.device) throw std::runtime_error("Embree: rtcNewDevice failed");
  rtcSetDeviceMemoryMonitorFunction(d.device, &MemoryMonitor::callback, &d.memory);
  const auto t0 = Clock::now();
  d.scene = rtcNewScene(d.device);
  rtcSetSceneFlags(d.scene, RTCSceneFlags(RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION |
                                           (robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE)));
  d.grids.resize(leaves_.size());
  for (size_t i = 0; i < leaves_.size(); ++i) {
    const Leaf& leaf = leaves_[i];
    const unsigned res = (1u << leaf.level) + 1;
    const size_t n = gridVertices(leaf.level);
    d.grids[i] = RTCGrid{0, res, (unsigned short)res, (unsigned short)res};
    RTCGeometry g = rtcNewGeometry(d.device, RTC_GEOMETRY_TYPE_GRID);
    rtcSetGeometryTimeStepCount(g, unsigned(leaf.steps));
    for (int j = 0; j < leaf.steps; ++j)
      rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, unsigned(j), RTC_FORMAT_FLOAT3, positions_.data(),
                                 (leaf.first + size_t(j) * n) * sizeof(Vec3), sizeof(Vec3), n);
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_GRID, 0, RTC_FORMAT_GRID, &d.grids[i], 0, sizeof(RTCGrid), 1);
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(d.scene, g, unsigned(i));
    rtcReleaseGeometry(g);
  }
  rtcCommitScene(d.scene);
  stats_.buildSeconds = secondsSince(t0);
  if (rtcGetDeviceError(d.device) != RTC_ERROR_NONE) throw std::runtime_error("Embree: scene build failed");
  stats_.embreeBytes = size_t(std::max<int64_t>(0, d.memory.current.load()));
  stats_.embreePeakBytes = size_t(std::max<int64_t>(0, d.memory.peak.load()));
  stats_.fixedBytes = stats_.vertexBytes + stats_.embreeBytes + d.grids.size() * sizeof(RTCGrid);
}

// The RayHit of Embree's hit on `leaf` at grid coordinates (eu, ev): the micro-quad and its
// local (s, r) in patch parameters (rows are mirrored in u), the vertices at the ray's time, and
// the normals as the micro-quad test and DiceBuffer compute them.
void EmbreeEngine::closestHit(const RayBatch& b, uint32_t i, uint32_t leafId, float t, float eu, float ev,
                              RayHit& hit, HitDerivatives* dpd) const {
  const Leaf& leaf = leaves_[leafId];
  const int k = leaf.level;
  const uint32_t cells = 1u << k;
  const size_t res = size_t(cells) + 1, n = res * res;
  const float u = std::clamp(1.0f - eu, 0.0f, 1.0f), v = std::clamp(ev, 0.0f, 1.0f);
  const float fu = u * float(cells), fv = v * float(cells);
  const uint32_t x = std::min(cells - 1, uint32_t(fu)), y = std::min(cells - 1, uint32_t(fv));
  const float s = std::clamp(fu - float(x), 0.0f, 1.0f), r = std::clamp(fv - float(y), 0.0f, 1.0f);
  // Time steps around the ray's time and the weight of the later one.
  size_t step = 0;
  float w1 = 0;
  if (leaf.steps > 1) {
    const float f = std::clamp(b.timeOf(i), 0.0f, 1.0f) * float(leaf.steps - 1);
    step = std::min(size_t(leaf.steps - 2), size_t(f));
    w1 = std::clamp(f - float(step), 0.0f, 1.0f);
  }
  const float w0 = 1.0f - w1;
  const Vec3* p0 = positions_.data() + leaf.first + step * n;
  const Vec3* n0 = normals_.data() + leaf.first + step * n;
  const size_t next = leaf.steps > 1 ? n : 0;
  auto at = [&](const Vec3* a, size_t xi, size_t yi, bool mirrored) {
    const size_t idx = yi * res + (mirrored ? res - 1 - xi : xi);
    return leaf.steps > 1 ? lerpPoint(a[idx], a[idx + next], w0, w1) : a[idx];
  };
  const Vec3 p00 = at(p0, x, y, true), p10 = at(p0, x + 1, y, true), p01 = at(p0, x, y + 1, true),
             p11 = at(p0, x + 1, y + 1, true);
  const bool first = s >= r;  // (p00, p10, p11) holds s >= r; (p00, p11, p01) the rest
  Vec3 ng;
  if (!detail::unitTriangleNormal(p00, first ? p10 : p11, first ? p11 : p01, ng) &&
      !detail::unitTriangleNormal(p00, first ? p11 : p10, first ? p01 : p11, ng))
    ng = Vec3{0, 0, 0};
  Vec3 ns = blendNormals(at(n0, x, y, false), at(n0, x + 1, y, false), at(n0, x, y + 1, false),
                         at(n0, x + 1, y + 1, false), s, r);
  if (ng == Vec3{0, 0, 0}) ng = ns;
  if (ns == Vec3{0, 0, 0}) ns = ng;
  hit.t = t;
  hit.u = u;
  hit.v = v;
  hit.leaf = leafId;
  hit.quad = (y << k) | x;
  hit.level = uint8_t(k);
  hit.setNormals(ng, ns);
  if (dpd) quadPartials(p00, p10, p01, p11, s, r, float(cells), dpd->dpdu, dpd->dpdv);
}

void EmbreeEngine::trace(RayBatch& b, GenerationStats& stats, TraceTimes& times) {
  const size_t n = b.size();
  std::atomic<uint64_t> rays{0}, shadow{0};
  RTCScene scene = device_->scene;
  // simple_partitioner: ranges are never larger than kChunk, the size of the stream arrays.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, kChunk), [&](const auto& range) {
    ScopedTimer timer(times.bottom);
    RTCRayHit closest[kChunk];
    RTCRay occl[kChunk];
    unsigned nc = 0, ns = 0;
    bool ignores = false;
    uint64_t counted = 0, countedShadow = 0;
    for (size_t i = range.begin(); i != range.end(); ++i) {
      if (b.ray[i].kind == RayKind::Inactive) continue;
      b.clearForTrace(i);
      ++counted;
      const bool isShadow = b.ray[i].kind == RayKind::Shadow;
      countedShadow += isShadow;
      if (!traceable(b, uint32_t(i))) continue;
      ignores |= b.ray[i].ignoreLeaf != kNoLeaf;
      if (isShadow) {
        setRay(b, uint32_t(i), occl[ns++]);
      } else {
        RTCRayHit& rh = closest[nc++];
        setRay(b, uint32_t(i), rh.ray);
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      }
    }
    FilterContext ctx;
    rtcInitIntersectContext(&ctx.context);
    if (ignores) {
      ctx.context.filter = &rejectIgnoredLeaf;
      ctx.rays = b.ray.data();
    }
    if (nc) rtcIntersect1M(scene, &ctx.context, closest, nc, sizeof(RTCRayHit));
    if (ns) rtcOccluded1M(scene, &ctx.context, occl, ns, sizeof(RTCRay));
    for (unsigned k = 0; k < nc; ++k) {
      const RTCRayHit& rh = closest[k];
      if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
      closestHit(b, rh.ray.id, rh.hit.geomID, rh.ray.tfar, rh.hit.u, rh.hit.v, b.hitOf(rh.ray.id),
                 b.derivativesOf(rh.ray.id));
    }
    for (unsigned k = 0; k < ns; ++k) {
      if (occl[k].tfar != -kInf) continue;
      // Which leaf occludes is not known here (occluded() reads only that one does).
      if (b.keepsFullHit(occl[k].id)) b.hitOf(occl[k].id).t = 0;
      b.occluderOf(occl[k].id) = 0;
    }
    rays.fetch_add(counted, std::memory_order_relaxed);
    shadow.fetch_add(countedShadow, std::memory_order_relaxed);
  }, tbb::simple_partitioner());
  stats.rays += rays.load();
  stats.shadowRays += shadow.load();
  stats.iterations.push_back({rays.load(), 0.0, 0});
  // No per-leaf stage: the leaf queries grouped by leaf, in a plain loop.
  if (b.queries && queries_.group(*b.queries)) queries_.runAll(times.leafQueries);
}

}  // namespace rayes
