// The rays of one generation and their hits: the Ray records, their shutter times when anything
// moves, the RayHits, the surface derivatives at the hits when a material reads a texture, indexed
// by ray slot; or, in a batch of shadow pairs (`shadowPairs`: slot 2k any ray, slot 2k+1 shadow
// rays only, the path tracer's layout), the hits and derivatives of the even slots alone and an
// occluding leaf per odd slot (hitOf, occluded, occluderOf). Data only: shading
// writes rays into a RayBatch and reads the hits back; src/rays traces it. Keeping the type
// here lets both sides use it without knowing each other (docs/design.md, "The two seams": shading knows nothing of
// how rays are sorted).
//
// Ownership: the batch owns its arrays; resize() keeps capacity, so a render reuses one batch
// per generation slot and allocates nothing once warmed up. Not thread-safe as a whole, but
// distinct indices may be written from distinct threads.
#pragma once
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>
#include "core/half.h"
#include "core/octahedral.h"
#include "core/sort_scratch.h"
#include "core/vec.h"

namespace rayes {

constexpr uint32_t kNoLeaf = 0xffffffffu;
struct LeafQueries;  // core/leaf_queries.h
class MediumLeafTracker;  // core/medium_leaves.h

enum class RayKind : uint8_t {
  Inactive = 0,  // an empty slot: not traced
  Closest = 1,   // nearest hit wanted (camera and continuation rays)
  Shadow = 2,    // any hit wanted (next-event rays)
};

// 28 bytes: the normals are kept octahedral-encoded (core/octahedral.h, 2 x 16-bit snorm, at most
// 1e-4 rad from the exact unit normal; decoding never gives NaN). The SortedEngine always
// quantised its normals this way, so storing the code changes none of its images; the Embree
// engine's normals are quantised too since the record became compact. The micro-quad index,
// the level and the border flag share one word (exact: --max-lod is at most kMaxHitLevel, so a
// quad index at the ray's level has at most 2 * kMaxHitLevel bits).
inline constexpr int kMaxHitLevel = 12;
struct RayHit {
  float t = std::numeric_limits<float>::infinity();
  float u = 0, v = 0;       // patch parameters
  uint32_t leaf = kNoLeaf;  // kNoLeaf: no hit (for a shadow ray: not occluded)
  uint32_t quad : 2 * kMaxHitLevel = 0;  // micro-quad index at the ray's level
  uint32_t level : 7 = 0;   // level of detail the ray was intersected at (<= kMaxHitLevel)
  uint32_t border : 1 = 0;  // the hit lies in a crack-closing border region, not on a micro-quad
  uint32_t ngCode = 0, nsCode = 0;  // encodeOctahedral of the two normals (0 is +z)
  bool valid() const { return leaf != kNoLeaf; }
  Vec3 ng() const { return decodeOctahedral(ngCode); }  // unit geometric normal of the micro-triangle hit
  Vec3 ns() const { return decodeOctahedral(nsCode); }  // unit shading normal
  void setNormals(Vec3 geometric, Vec3 shading) {
    ngCode = encodeOctahedral(geometric);
    nsCode = encodeOctahedral(shading);
  }
};

// 28 bytes; SortedEngine::offerHit copies it field by field (two fields atomically): a new field
// must be added there too.
static_assert(sizeof(RayHit) == 28);

// The leaf ids a ray can name as its origin: [0, kMaxRayLeaves) (the Renderer refuses a scene with
// more leaves), so the origin leaf, its level and the ray's kind share one word.
inline constexpr uint32_t kRayLeafBits = 26;
inline constexpr uint32_t kMaxRayLeaves = (uint32_t(1) << kRayLeafBits) - 1;
static_assert(kMaxHitLevel < 16);  // an origin level fits 4 bits

// What to trace, one record per ray (36 bytes): the engine reads most of these fields together
// for every (ray, leaf) pair of the bottom level and the top level, in an order set by the sort, so
// one record is one cache miss where separate arrays cost one each (bench/history/2026-11.md). A
// ray spans t in [0, tmax] from org: it leaves a surface by its origin leaf, not by an offset tmin.
//
// The direction is kept as a 48-bit octahedral code of the unit direction and the cone's spread
// as a half (8 bytes saved against four floats; bench/history/2026-11.md, "a compact Ray"). The
// code is set once, by aim(), and dir() decodes it: the decoded direction is the ray, the one the
// engines trace and the one shading reads back (its hit point, its incoming direction, its
// footprint), so every use agrees on one direction. Because dir() is unit, t is a distance:
// aim() takes a direction of any length and rescales tmax and the spread by it.
// Bounds: the direction within kOctahedral48MaxError (3.1e-7 rad) of the one aimed, exactly in a
// coordinate plane when aimed in one; the spread within core/half.h's (relative 2^-11, absolute
// 2^-25 below 2^-14, clamped to ±65504). The width stays a float: it is a length, whose range is
// the scene's (a half would clamp a scene scaled by 10^4 and flush one scaled by 10^-6), while the
// spread is an angle's tangent, the same at every scale. Decode once per ray per use, not per
// node: a decode is a square root and a division.
struct Ray {
  Vec3 org;
  float tmax = 0;                 // a distance along dir()
  float coneWidth = 0;            // footprint width at the origin
  uint32_t ignoreLeaf = kNoLeaf;  // a leaf this ray must not hit (a shadow ray's light)
  // The leaf the ray leaves from (originLeaf(); kNoLeaf for camera rays) and the level it was hit
  // at: the ray sees that leaf at exactly that level, the same micro-grid it left, so a coarser
  // footprint cannot make it hit its own patch again. With the kind, one word: 4 bytes of the
  // record's padding saved (bench/history/2026-11.md, "Compact ray slots").
  uint32_t originLeafBits : kRayLeafBits = kMaxRayLeaves;  // kMaxRayLeaves: none
  uint32_t originLevel : 4 = 0;
  RayKind kind : 2 = RayKind::Inactive;
  OctahedralCode48 dirCode;       // the unit direction ((0, 0): +z)
  uint16_t coneSpreadCode = 0;    // half: footprint growth per unit t (2 tan(half angle))
  uint32_t originLeaf() const { return originLeafBits == kMaxRayLeaves ? kNoLeaf : uint32_t(originLeafBits); }
  void setOrigin(uint32_t leaf, uint8_t level) {
    originLeafBits = leaf == kNoLeaf ? kMaxRayLeaves : leaf;
    originLevel = level;
  }
  Vec3 dir() const { return decodeOctahedral48(dirCode); }  // unit
  float coneSpread() const { return decodeHalf(coneSpreadCode); }
  // The direction a ray aimed along d traces (dir() after aim(d, ...)); zero for a d that traces
  // nothing. A producer that checks a direction before it writes the ray (which side of the
  // surface, the origin's offset) checks this one, the one the engines will trace.
  static Vec3 traced(Vec3 d) { return aimedLength(d) > 0 ? decodeOctahedral48(encodeOctahedral48(d)) : Vec3{}; }
  // Aims the ray along d, which need not be unit: t1 and spread are per unit of |d| and are
  // stored per unit of distance (tmax times |d|, the spread over |d|, in double so that |d| from
  // 1e-20 to 1e20 stays finite; a spread beyond the half's range clamps). A zero or non-finite d
  // traces nothing (tmax 0, dir() +z).
  void aim(Vec3 d, float t1, float width, float spread) {
    const double len = aimedLength(d);
    const bool usable = len > 0;
    dirCode = usable ? encodeOctahedral48(d) : OctahedralCode48{};
    tmax = usable ? float(double(t1) * len) : 0.0f;
    coneWidth = width;
    coneSpreadCode = encodeHalf(usable ? float(double(spread) / len) : spread);
  }

 private:
  // |d| in double (finite for every finite float d), or 0 for a d that traces nothing: zero,
  // infinite or NaN.
  static double aimedLength(Vec3 d) {
    const double len = std::sqrt(double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z);
    return len > 0 && std::isfinite(len) ? len : 0.0;
  }
};
static_assert(sizeof(Ray) == 36);

// The surface's partial derivatives at a hit, world space per unit of the patch parameters: what
// turns the ray's footprint into one in (u, v) for texture filtering (shading/footprint.h). The
// engines take them from the micro-quad hit (the bilinear quad's partials times 2^level), so
// they are the diced surface's, at the level the ray saw. Finite; zero where the quad collapses.
struct HitDerivatives {
  Vec3 dpdu, dpdv;
};

struct RayBatch {
  std::vector<Ray> ray;
  // Shutter time in [0, 1], per ray only when `timed`: a scene where nothing moves sees the same
  // geometry at every time, so its batches leave the array empty and every ray is at time 0.
  std::vector<float> time;
  bool timed = true;                  // set before resize()
  // What was found: hit[hitIndex(i)] for a slot that keeps a full hit (keepsFullHit), else the
  // leaf that occludes shadow ray i in occluder[i / 2] (kNoLeaf: none). A shadow ray's result is
  // its occluding leaf alone, so in a batch of shadow pairs (set before resize()) an odd slot,
  // which may hold only shadow rays, keeps those 4 bytes instead of a 28-byte RayHit
  // (bench/history/2026-11.md, "Compact ray slots"). Read slots through hitOf / occluded /
  // occluderOf: they hold for both layouts.
  std::vector<RayHit> hit;
  std::vector<uint32_t> occluder;
  bool shadowPairs = false;
  // dP/du and dP/dv at each closest hit, only when `derivatives` (a scene with a textured
  // material; set before resize()): a scene without one pays neither the bytes nor the work.
  // Indexed like `hit`; meaningful only where the slot's hit is a closest hit; shadow rays get none.
  std::vector<HitDerivatives> dpd;
  bool derivatives = false;
  // Dicings charged to each ray (`--cost-layers`, app/pixel_cost.h), only when `chargeDicings`
  // (set before resize()): fixed point, kDicingShareOne per dicing. The engine splits each
  // dicing among the rays that caused it (the rays of its leaf's run) into integer shares that
  // sum to exactly kDicingShareOne, so per-pixel sums are exact and their order does not
  // matter; the engine only adds (atomically: a ray is in several leaves' runs at once), the
  // render takes and clears them after each trace. A render without the layers pays nothing.
  static constexpr uint64_t kDicingShareOne = uint64_t(1) << 32;
  std::vector<uint64_t> dicingShare;
  bool chargeDicings = false;
  // Queries the engine runs per leaf during trace(), besides the rays (core/leaf_queries.h):
  // the poster's (not owned), or none.
  LeafQueries* queries = nullptr;
  // The tracking the engine runs at brick leaves (core/medium_leaves.h): the poster's (not
  // owned), or none (a scene without media).
  MediumLeafTracker* media = nullptr;
  // The memory the engine's candidate sort uses while it traces this batch and the
  // integrator's shading sort while it shades it: never both at once (core/sort_scratch.h).
  SortScratch sortScratch;

  size_t size() const { return ray.size(); }
  void resize(size_t n) {
    ray.resize(n);
    time.resize(timed ? n : 0);
    hit.resize(shadowPairs ? (n + 1) / 2 : n);
    occluder.resize(shadowPairs ? n / 2 : 0, kNoLeaf);  // no occluder yet, also in slots a resize adds
    dpd.resize(derivatives ? hit.size() : 0);
    dicingShare.resize(chargeDicings ? n : 0);
  }
  // Whether slot i keeps a full RayHit (every slot, or the even slots of shadow pairs); an odd
  // slot of shadow pairs keeps an occluding leaf only and may hold only a shadow ray.
  bool keepsFullHit(size_t i) const { return !shadowPairs || (i & 1) == 0; }
  size_t hitIndex(size_t i) const { return shadowPairs ? i >> 1 : i; }
  // Slot i's hit; i must keep a full hit.
  RayHit& hitOf(size_t i) { return hit[hitIndex(i)]; }
  const RayHit& hitOf(size_t i) const { return hit[hitIndex(i)]; }
  // The leaf word of slot i's result: the hit's leaf, or an odd pair slot's occluder (engines
  // read and write it atomically while a trace runs).
  uint32_t& occluderOf(size_t i) { return keepsFullHit(i) ? hitOf(i).leaf : occluder[i >> 1]; }
  const uint32_t& occluderOf(size_t i) const { return keepsFullHit(i) ? hitOf(i).leaf : occluder[i >> 1]; }
  // Shadow ray i found an occluder (a closest slot: it found a hit).
  bool occluded(size_t i) const { return occluderOf(i) != kNoLeaf; }
  // Slot i's result reset to "nothing found".
  void clearHit(size_t i) {
    if (keepsFullHit(i)) {
      hitOf(i) = RayHit{};
      if (derivatives) dpd[hitIndex(i)] = HitDerivatives{};
    } else {
      occluder[i >> 1] = kNoLeaf;
    }
  }
  // Slot i's result cleared as a trace starts (engines call it for each slot they trace); a
  // closest ray in a slot that keeps only an occluder is a layout error of the caller.
  void clearForTrace(size_t i) {
    if (!keepsFullHit(i) && ray[i].kind != RayKind::Shadow)
      throw std::logic_error("RayBatch: a closest ray in a slot of shadow pairs that keeps no hit");
    clearHit(i);
  }
  // Adds `share` to ray i's dicings (thread-safe for distinct or equal i).
  void chargeDicing(size_t i, uint64_t share) {
    std::atomic_ref<uint64_t>(dicingShare[i]).fetch_add(share, std::memory_order_relaxed);
  }
  // The derivatives at ray i's hit (i keeps a full hit), or null when the batch keeps none.
  const HitDerivatives* derivativesOf(size_t i) const { return derivatives ? &dpd[hitIndex(i)] : nullptr; }
  HitDerivatives* derivativesOf(size_t i) { return derivatives ? &dpd[hitIndex(i)] : nullptr; }
  float timeOf(size_t i) const { return timed ? time[i] : 0.0f; }
  // Every argument explicit: a defaulted shutter time or origin leaf let a stale call compile
  // and trace at time 0, or re-hit the surface it leaves.
  void set(size_t i, RayKind k, Vec3 o, Vec3 d, float t1, float width, float spread,
           uint32_t ignore, uint32_t fromLeaf, uint8_t fromLevel, float shutterTime) {
    Ray& r = ray[i];
    r.org = o;
    r.aim(d, t1, width, spread);
    r.ignoreLeaf = ignore;
    r.setOrigin(fromLeaf, fromLevel);
    r.kind = k;
    if (timed) time[i] = shutterTime;
    clearHit(i);
  }
  // A ray that leaves no surface and ignores no leaf, at shutter time 0 (tests, benchmarks).
  void setFromNowhere(size_t i, RayKind k, Vec3 o, Vec3 d, float t1, float width, float spread) {
    set(i, k, o, d, t1, width, spread, kNoLeaf, kNoLeaf, 0, 0.0f);
  }
  // Per ray slot; with shadow pairs, per slot of a pair (half of the pair's, which is even).
  static constexpr size_t bytesPerRay(bool timed, bool derivatives = false, bool shadowPairs = false) {
    const size_t closest = sizeof(RayHit) + (derivatives ? sizeof(HitDerivatives) : 0);
    return sizeof(Ray) + (timed ? sizeof(float) : 0) + (shadowPairs ? (closest + sizeof(uint32_t)) / 2 : closest);
  }
  static_assert((sizeof(RayHit) + sizeof(uint32_t)) % 2 == 0 && sizeof(HitDerivatives) % 2 == 0);
};

}  // namespace rayes
