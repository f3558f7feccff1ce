// DiceBuffer storage and the bottom-up build of the implicit quad-tree (thesis §6.1.1).
#include "dicing/dice_buffer.h"
#include <xmmintrin.h>
#include <algorithm>
#include <stdexcept>
#include "dicing/morton.h"
#include "geometry/patch_math.h"
#include "geometry/sub_patch.h"

namespace rayes {

using detail::levelOffset;
using detail::morton;

DiceBuffer::DiceBuffer(int maxLevel) : maxLevel_(maxLevel) {
  if (maxLevel < 0 || maxLevel > 12) throw std::invalid_argument("DiceBuffer: maxLevel not in 0..12");
  allocate(a_);
  segments_ = std::make_unique<BorderSegment[]>(borderOffset(4, 0, 0) / 6);
}

void DiceBuffer::allocate(Sample& s) const {
  const size_t res = (size_t(1) << maxLevel_) + 1;
  s.positions.resize(res * res);
  s.normals.resize(res * res);
  s.nodes.resize(levelOffset(maxLevel_ + 1) * 6);  // 6 floats per box
}

void DiceBuffer::diceSample(const Patch& patch, int sample, int level, Sample& out) {
  patch.diceAt(sample, level, out.positions.data(), out.normals.data());
  const size_t count = size_t(resolution()) * resolution();
  for (size_t k = 0; k < count; ++k) out.normals[k] = detail::unitOrZero(out.normals[k]);
  buildTree(out.positions, out.nodes);
  if (borders_ && moving_) {  // a static dicing computes its border segments on demand
    if (out.borders.empty()) out.borders.resize(borderOffset(4, 0, 0));  // 4 x (2^(maxLevel+1) - 1) boxes
    buildBorders(sample, out, out.borders);
  }
}

// A new serial number makes every border segment entry stale; on wrap-around (after 2^16
// dicings, at most a clear per 65,535 dicings) the entries are cleared so that no old stamp can match.
void DiceBuffer::newStamp() {
  if (++stamp_ == 0) {
    for (size_t i = 0, n = borderOffset(4, 0, 0) / 6; i < n; ++i) {
      segments_[i].boxStamp.store(0, std::memory_order_relaxed);
      for (auto& r : segments_[i].radiusStamp) r.store(0, std::memory_order_relaxed);
      segments_[i].coarseStamp.store(0, std::memory_order_relaxed);
    }
    stamp_ = 1;
  }
}

void DiceBuffer::setPlace(const Patch& patch) {
  const auto* sub = dynamic_cast<const SubPatch*>(&patch);
  subX_ = sub ? sub->x() : 0;
  subY_ = sub ? sub->y() : 0;
  subDepth_ = sub ? sub->depth() : 0;
  // The whole leaf's box sets a sub-leaf's margins and watertight error (it holds the sub-leaf's
  // box, so they stay conservative): the border regions are then the whole leaf's to the bit.
  if (sub) patchBounds_ = sub->parent().bounds();
}

void DiceBuffer::dice(const Patch& patch, int level, SharedBorderBounds shared) {
  if (level < 0 || level > maxLevel_) throw std::invalid_argument("DiceBuffer::dice: level > maxLevel");
  level_ = level;
  moving_ = false;
  patch_ = &patch;
  sampleA_ = 0;
  shared_ = shared;
  borders_ = patch.needsBorderClosure();
  patchBounds_ = patch.bounds();
  setPlace(patch);
  newStamp();
  diceSample(patch, 0, level, a_);
  if (borders_) buildThinBounds();
}

void DiceBuffer::buildThinBounds() {
  for (int e = 0; e < 4; ++e)
    for (int k = 0; k <= std::min(level_, BottomQuery::kMaxThinLevel); ++k) {
      Box3 b;
      for (uint32_t j = 0; j < (1u << k); ++j) {
        size_t v0, v1;
        chordEnds(e, k, j, level_, v0, v1);
        b.extend(a_.positions[v0]);
        b.extend(a_.positions[v1]);
      }
      thinBounds_[e][k] = b;
    }
}

void DiceBuffer::diceInterval(const Patch& patch, int interval, int level, SharedBorderBounds shared) {
  if (patch.timeSamples() < 2) return dice(patch, level, shared);
  if (level < 0 || level > maxLevel_) throw std::invalid_argument("DiceBuffer::dice: level > maxLevel");
  if (interval < 0 || interval + 1 >= patch.timeSamples())
    throw std::invalid_argument("DiceBuffer::diceInterval: no such time interval");
  level_ = level;
  moving_ = true;
  patch_ = &patch;
  sampleA_ = interval;
  shared_ = {};
  borders_ = patch.needsBorderClosure();
  patchBounds_ = patch.bounds();  // the union over all samples: the margin is per patch, not per interval
  setPlace(patch);
  newStamp();
  if (b_.positions.empty()) allocate(b_);
  diceSample(patch, interval, level, a_);
  diceSample(patch, interval + 1, level, b_);
}

// Level m: the box of each micro-quad's 4 corners (the two flat triangles lie in their convex
// hull). Level i < m: the union of the 4 children, which Z-order keeps in one group. One linear
// pass per level in Z-order, no sorting: O(4^m) in total. Reductions use the same vmin/vmax
// order as a Box3 union, so every box is bit-identical to the array-of-boxes layout it replaces.
namespace {

constexpr int kLo = 0, kHi = 4;  // lane offsets within an axis's 8 floats

// Lane-wise std::min(std::min(a, b), std::min(c, d)) (resp. max), exactly: std::min(x, y) is
// (y < x) ? y : x, which is _mm_min_ps(y, x); likewise std::max(x, y) is _mm_max_ps(y, x).
inline __m128 min4(__m128 a, __m128 b, __m128 c, __m128 d) {
  return _mm_min_ps(_mm_min_ps(d, c), _mm_min_ps(b, a));
}
inline __m128 max4(__m128 a, __m128 b, __m128 c, __m128 d) {
  return _mm_max_ps(_mm_max_ps(d, c), _mm_max_ps(b, a));
}

// Union of the 4 boxes of a group.
void groupBounds(const float* group, Vec3& lo, Vec3& hi) {
  for (int a = 0; a < 3; ++a) {
    const float* l = group + 8 * a + kLo;
    const float* h = group + 8 * a + kHi;
    lo[a] = std::min(std::min(l[0], l[1]), std::min(l[2], l[3]));
    hi[a] = std::max(std::max(h[0], h[1]), std::max(h[2], h[3]));
  }
}

}  // namespace

void DiceBuffer::buildTree(const GridArray<Vec3>& positions_, GridArray<float>& nodes) const {
  auto nodeGroup = [&](int level, uint32_t g) { return nodes.data() + groupOffset(level, g); };
  const size_t res = (size_t(1) << level_) + 1;
  auto quadBox = [&](uint32_t x, uint32_t y, Vec3& lo, Vec3& hi) {
    const Vec3* p = &positions_[y * res + x];
    const Vec3 p00 = p[0], p10 = p[1], p01 = p[res], p11 = p[res + 1];
    lo = vmin(vmin(p00, p10), vmin(p01, p11));
    hi = vmax(vmax(p00, p10), vmax(p01, p11));
  };
  float* root = nodes.data() + groupOffset(maxLevel_, 0);
  Vec3 lo, hi;
  if (level_ == 0) {
    quadBox(0, 0, lo, hi);
  } else {
    const int m = level_;
    // Leaves, one group (a 2x2 block of micro-quads, 3x3 vertices) at a time, 4 lanes wide.
    float* leaves = nodeGroup(m - 1, 0);
    const uint32_t groups = 1u << (2 * (m - 1));
    for (uint32_t g = 0; g < groups; ++g) {
      const size_t x0 = 2 * size_t(detail::mortonX(g)), y0 = 2 * size_t(detail::mortonY(g));
      const Vec3* r0 = &positions_[y0 * res + x0];
      const Vec3* r1 = r0 + res;
      const Vec3* r2 = r1 + res;
      float* group = leaves + kNodeGroupFloats * g;
      for (int a = 0; a < 3; ++a) {
        const __m128 v0 = _mm_setr_ps(r0[0][a], r0[1][a], r0[2][a], 0.0f);
        const __m128 v1 = _mm_setr_ps(r1[0][a], r1[1][a], r1[2][a], 0.0f);
        const __m128 v2 = _mm_setr_ps(r2[0][a], r2[1][a], r2[2][a], 0.0f);
        // Lane l = (dx, dy) = (l & 1, l >> 1): its corners p00, p10, p01, p11.
        const __m128 p00 = _mm_shuffle_ps(v0, v1, _MM_SHUFFLE(1, 0, 1, 0));
        const __m128 p10 = _mm_shuffle_ps(v0, v1, _MM_SHUFFLE(2, 1, 2, 1));
        const __m128 p01 = _mm_shuffle_ps(v1, v2, _MM_SHUFFLE(1, 0, 1, 0));
        const __m128 p11 = _mm_shuffle_ps(v1, v2, _MM_SHUFFLE(2, 1, 2, 1));
        _mm_storeu_ps(group + 8 * a + kLo, min4(p00, p10, p01, p11));
        _mm_storeu_ps(group + 8 * a + kHi, max4(p00, p10, p01, p11));
      }
    }
    // Node n of level i (1 <= i < m) is the union of its children group (level i, n) and is
    // stored in lane n % 4 of group (level i-1, n / 4): each parent group is the lane-wise
    // reduction of the transposes of its 4 nodes' children groups.
    for (int i = m - 1; i >= 1; --i) {
      const float* children = nodeGroup(i, 0);
      float* parents = nodeGroup(i - 1, 0);
      const uint32_t count = 1u << (2 * (i - 1));
      for (uint32_t pg = 0; pg < count; ++pg) {
        const float* c = children + kNodeGroupFloats * 4 * size_t(pg);
        float* out = parents + kNodeGroupFloats * size_t(pg);
        for (int plane = 0; plane < 6; ++plane) {
          __m128 t0 = _mm_loadu_ps(c + 4 * plane), t1 = _mm_loadu_ps(c + kNodeGroupFloats + 4 * plane),
                 t2 = _mm_loadu_ps(c + 2 * kNodeGroupFloats + 4 * plane),
                 t3 = _mm_loadu_ps(c + 3 * kNodeGroupFloats + 4 * plane);
          _MM_TRANSPOSE4_PS(t0, t1, t2, t3);  // t_j = lane j of the 4 children groups
          _mm_storeu_ps(out + 4 * plane, plane % 2 == 0 ? min4(t0, t1, t2, t3) : max4(t0, t1, t2, t3));
        }
      }
    }
    groupBounds(nodeGroup(0, 0), lo, hi);
  }
  for (int a = 0; a < 3; ++a) {
    root[a] = lo[a];
    root[3 + a] = hi[a];
  }
}

Box3 DiceBuffer::borderNode(int e, int treeLevel, int j) const {
  Box3 b;
  if (!borders_) return b;
  if (!moving_) return regionBox(e, treeLevel, uint32_t(j));
  const float* r = a_.borders.data() + borderOffset(e, treeLevel, uint32_t(j));
  b.lo = {r[0], r[1], r[2]};
  b.hi = {r[3], r[4], r[5]};
  return b;
}

Vec3 DiceBuffer::position(int i, int j) const { return a_.positions[size_t(j) * resolution() + i]; }
Vec3 DiceBuffer::normal(int i, int j) const { return a_.normals[size_t(j) * resolution() + i]; }

Box3 DiceBuffer::node(int treeLevel, int x, int y) const {
  Box3 b;
  if (treeLevel == 0) {
    const float* r = rootBox();
    b.lo = {r[0], r[1], r[2]};
    b.hi = {r[3], r[4], r[5]};
    return b;
  }
  const uint32_t n = morton(uint32_t(x), uint32_t(y));
  const float* g = nodeGroup(treeLevel - 1, n >> 2);
  const uint32_t lane = n & 3;
  b.lo = {g[lane], g[8 + lane], g[16 + lane]};
  b.hi = {g[4 + lane], g[12 + lane], g[20 + lane]};
  return b;
}

size_t DiceBuffer::nodeCount() const { return levelOffset(level_ + 1); }

size_t DiceBuffer::bytesFor(int maxLevel) {
  const size_t res = (size_t(1) << maxLevel) + 1;
  return res * res * 2 * sizeof(Vec3) + levelOffset(maxLevel + 1) * 6 * sizeof(float) +
         4 * ((size_t(2) << maxLevel) - 1) * sizeof(BorderSegment);  // segments_: borderOffset(4, 0, 0) / 6
}

size_t DiceBuffer::bytesAllocated() const {
  size_t b = 0;
  for (const Sample* s : {&a_, &b_})
    b += s->positions.capacity() * sizeof(Vec3) + s->normals.capacity() * sizeof(Vec3) +
         s->nodes.capacity() * sizeof(float) + s->borders.capacity() * sizeof(float);
  return b + borderOffset(4, 0, 0) / 6 * sizeof(BorderSegment);  // segments_
}

}  // namespace rayes
