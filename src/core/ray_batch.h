// The rays of one generation and their hits, as a structure of arrays. Data only: shading
// writes rays into a RayBatch and reads the hits back; src/rays traces it. Keeping the type
// here lets both sides use it without knowing each other (docs/design.md, "The two seams": shading knows nothing of
// how rays are sorted).
//
// Ownership: the batch owns its arrays; resize() keeps capacity, so a render reuses one batch
// per generation slot and allocates nothing once warmed up. Not thread-safe as a whole, but
// distinct indices may be written from distinct threads.
#pragma once
#include <cstdint>
#include <limits>
#include <vector>
#include "core/octahedral.h"
#include "core/vec.h"

namespace rayes {

constexpr uint32_t kNoLeaf = 0xffffffffu;
struct LeafQueries;  // core/leaf_queries.h

enum class RayKind : uint8_t {
  Inactive = 0,  // an empty slot: not traced
  Closest = 1,   // nearest hit wanted (camera and continuation rays)
  Shadow = 2,    // any hit wanted (next-event rays)
};

// 32 bytes: the normals are kept octahedral-encoded (core/octahedral.h, 2 x 16-bit snorm, at most
// 1e-4 rad from the exact unit normal; decoding never gives NaN). The Rayes tracer always
// quantised its normals this way, so storing the code changes none of its images; the Embree
// engine's normals are quantised too since the record became compact.
struct RayHit {
  float t = std::numeric_limits<float>::infinity();
  float u = 0, v = 0;       // patch parameters
  uint32_t leaf = kNoLeaf;  // kNoLeaf: no hit (for a shadow ray: not occluded)
  uint32_t quad = 0;        // micro-quad index at the ray's level
  uint32_t ngCode = 0, nsCode = 0;  // encodeOctahedral of the two normals (0 is +z)
  uint8_t level = 0;        // level of detail the ray was intersected at
  bool valid() const { return leaf != kNoLeaf; }
  Vec3 ng() const { return decodeOctahedral(ngCode); }  // unit geometric normal of the micro-triangle hit
  Vec3 ns() const { return decodeOctahedral(nsCode); }  // unit shading normal
  void setNormals(Vec3 geometric, Vec3 shading) {
    ngCode = encodeOctahedral(geometric);
    nsCode = encodeOctahedral(shading);
  }
};

struct RayBatch {
  // What to trace.
  // A ray spans t in [0, tmax] from org: it leaves a surface by originLeaf below, not by an
  // offset tmin, so none is stored (4 bytes a slot).
  std::vector<Vec3> org, dir;         // dir need not be unit; t is in units of |dir|
  std::vector<float> tmax;
  std::vector<float> coneWidth;       // footprint width at the origin
  std::vector<float> coneSpread;      // footprint growth per unit t (2 tan(half angle) * |dir|)
  // Shutter time in [0, 1], per ray only when `timed`: a scene where nothing moves sees the same
  // geometry at every time, so its batches leave the array empty and every ray is at time 0.
  std::vector<float> time;
  bool timed = true;                  // set before resize()
  std::vector<uint32_t> ignoreLeaf;   // a leaf this ray must not hit (a shadow ray's light)
  // The leaf the ray leaves from and the level it was hit at: the ray sees that leaf at exactly
  // that level, the same micro-grid it left, so a coarser footprint cannot make it hit its own
  // patch again (kNoLeaf for camera rays).
  std::vector<uint32_t> originLeaf;
  std::vector<uint8_t> originLevel;
  std::vector<RayKind> kind;
  // What was found.
  std::vector<RayHit> hit;
  // Queries the engine runs per leaf during trace(), besides the rays (core/leaf_queries.h):
  // the poster's (not owned), or none.
  LeafQueries* queries = nullptr;

  size_t size() const { return kind.size(); }
  void resize(size_t n) {
    org.resize(n); dir.resize(n); tmax.resize(n); coneWidth.resize(n);
    coneSpread.resize(n); time.resize(timed ? n : 0); ignoreLeaf.resize(n); originLeaf.resize(n); originLevel.resize(n);
    kind.resize(n);
    hit.resize(n);
  }
  float timeOf(size_t i) const { return timed ? time[i] : 0.0f; }
  // Every argument explicit: a defaulted shutter time or origin leaf let a stale call compile
  // and trace at time 0, or re-hit the surface it leaves.
  void set(size_t i, RayKind k, Vec3 o, Vec3 d, float t1, float width, float spread,
           uint32_t ignore, uint32_t fromLeaf, uint8_t fromLevel, float shutterTime) {
    kind[i] = k; org[i] = o; dir[i] = d; tmax[i] = t1; coneWidth[i] = width;
    coneSpread[i] = spread; ignoreLeaf[i] = ignore;
    if (timed) time[i] = shutterTime;
    originLeaf[i] = fromLeaf; originLevel[i] = fromLevel;
    hit[i] = RayHit{};
  }
  // A ray that leaves no surface and ignores no leaf, at shutter time 0 (tests, benchmarks).
  void setFromNowhere(size_t i, RayKind k, Vec3 o, Vec3 d, float t1, float width, float spread) {
    set(i, k, o, d, t1, width, spread, kNoLeaf, kNoLeaf, 0, 0.0f);
  }
  static constexpr size_t bytesPerRay(bool timed) {
    return 2 * sizeof(Vec3) + (timed ? 4 : 3) * sizeof(float) + 2 * sizeof(uint32_t) + sizeof(uint8_t) +
           sizeof(RayKind) + sizeof(RayHit);
  }
};

}  // namespace rayes
