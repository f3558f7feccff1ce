// The border regions of a dicing (see dice_buffer.h): the boxes of the true border curve over
// border segments, a moving dicing's border trees, and the regions' radii about their chords.
#include <algorithm>
#include <atomic>
#include <cmath>
#include "dicing/dice_buffer.h"
#include "dicing/micro_quad.h"

namespace rayes {

void DiceBuffer::chordEnds(int e, int i, uint32_t j, int m, size_t& v0, size_t& v1) {
  const size_t res = (size_t(1) << m) + 1;
  const size_t stride = size_t(1) << (m - i);
  switch (e) {
    case 0: v0 = j * stride; v1 = v0 + stride; break;
    case 1: v0 = j * stride * res + (res - 1); v1 = v0 + stride * res; break;
    case 2: v0 = (res - 1) * res + j * stride; v1 = v0 + stride; break;
    default: v0 = j * stride * res; v1 = v0 + stride * res; break;
  }
}

namespace {

// Largest squared distance of a box's corners from the line through a along axis (|axis|^2 =
// len2 > 0): the distance to a line is convex, so over the box it is largest at a corner.
double farthestCorner2(const Box3& box, Vec3 a, const double axis[3], double len2) {
  double worst = 0;
  for (int c = 0; c < 8; ++c) {
    const double p[3] = {double((c & 1) ? box.hi.x : box.lo.x) - a.x, double((c & 2) ? box.hi.y : box.lo.y) - a.y,
                         double((c & 4) ? box.hi.z : box.lo.z) - a.z};
    // |p x axis|^2 / |axis|^2
    const double x = p[1] * axis[2] - p[2] * axis[1], y = p[2] * axis[0] - p[0] * axis[2],
                 z = p[0] * axis[1] - p[1] * axis[0];
    worst = std::max(worst, (x * x + y * y + z * z) / len2);
  }
  return worst;
}

// Relative slack for the rounding of farthestCorner2 and the square root (double, on float inputs).
double radiusFrom(double worst2) { return std::sqrt(worst2) * (1.0 + 1e-9); }

// The parameter rectangle of segment j of border e at level i (a line: one side is a point).
struct SegmentRect {
  float u0, u1, v0, v1;
};
SegmentRect segmentRect(int e, int i, uint32_t j) {
  const float inv = 1.0f / float(1u << i);  // a power of two: j * inv is exact
  const float t0 = float(j) * inv, t1 = float(j + 1) * inv;
  switch (e) {
    case 0: return {t0, t1, 0.0f, 0.0f};
    case 1: return {1.0f, 1.0f, t0, t1};
    case 2: return {t0, t1, 1.0f, 1.0f};
    default: return {0.0f, 0.0f, t0, t1};
  }
}

// A box kept in six atomic floats of a BorderSegment (lo, then hi).
Box3 loadBox(const std::atomic<float>* six) {
  Box3 b;
  for (int a = 0; a < 3; ++a) {
    b.lo[a] = six[a].load(std::memory_order_relaxed);
    b.hi[a] = six[3 + a].load(std::memory_order_relaxed);
  }
  return b;
}
void storeBox(std::atomic<float>* six, const Box3& b) {
  for (int a = 0; a < 3; ++a) {
    six[a].store(b.lo[a], std::memory_order_relaxed);
    six[3 + a].store(b.hi[a], std::memory_order_relaxed);
  }
}

}  // namespace

Box3 DiceBuffer::curveBox(int e, int i, uint32_t j, int sample) const {
  BorderSegment* seg = !moving_ && i <= maxLevel_ ? &segments_[borderOffset(e, i, j) / 6] : nullptr;
  if (seg && seg->boxStamp.load(std::memory_order_acquire) == stamp_) return loadBox(seg->box);
  const BorderBoundCache::Key key{shared_.leaf, BorderBoundCache::Kind::CurveBox, e, i, j};
  const bool share = seg && shared_.cache;
  Box3 b;
  if (!share || !shared_.cache->find(key, b)) {
    const SegmentRect r = segmentRect(e, i, j);
    b = patch_->boundsOverAt(sample, r.u0, r.u1, r.v0, r.v1);
    if (share) shared_.cache->insert(key, b);
  }
  if (seg) {
    storeBox(seg->box, b);
    seg->boxStamp.store(stamp_, std::memory_order_release);
  }
  return b;
}

bool DiceBuffer::mayEnterCoarseBox(int e, int i, uint32_t j, const RayBoxQuery& q, const Vec3& pad, float tmin,
                                   float tmax) const {
  BorderSegment& seg = segments_[borderOffset(e, i, j) / 6];
  Box3 c;
  if (seg.coarseStamp.load(std::memory_order_acquire) == stamp_) {
    c = loadBox(seg.coarse);
  } else {
    // Kept across dicings in the shared table: then the box costs a look-up, not a bound.
    if (shared_.cache && shared_.cache->find({shared_.leaf, BorderBoundCache::Kind::CurveBox, e, i, j}, c)) {
      storeBox(seg.box, c);
      seg.boxStamp.store(stamp_, std::memory_order_release);
      return true;
    }
    const SegmentRect r = segmentRect(e, i, j);  // curveBox's rectangle
    if (!patch_->coarseBoundsOverAt(0, r.u0, r.u1, r.v0, r.v1, c)) return true;
    size_t v0, v1;
    chordEnds(e, i, j, level_, v0, v1);
    c.extend(a_.positions[v0]);
    c.extend(a_.positions[v1]);
    storeBox(seg.coarse, c);
    seg.coarseStamp.store(stamp_, std::memory_order_release);
  }
  // Each coordinate of c lies as far out as the region box's or farther, and intersectBox's
  // slab distances are monotone in the bounds (float rounding is monotone; a NaN leaves a slab
  // unused either way), so its entry is no later and its exit no earlier: a miss here is a miss
  // there, and the walk takes the same path as with every box computed.
  float t0, t1;
  return intersectBox(q, c.lo - pad, c.hi + pad, tmin, tmax, t0, t1);
}

Box3 DiceBuffer::regionBox(int e, int i, uint32_t j) const {
  Box3 b = curveBox(e, i, j, 0);
  size_t v0, v1;
  chordEnds(e, i, j, level_, v0, v1);
  b.extend(a_.positions[v0]);
  b.extend(a_.positions[v1]);
  return b;
}

// Border trees of a moving dicing: for each border e and level i, box (e, i, j) is the box of
// the true border curve over segment j and of the segment's chord (its two grid vertices),
// united with its two children's boxes so that a node contains every finer level's box below
// it (the traversal prunes with it). Built finest level first. Levels above level_ are never
// read.
void DiceBuffer::buildBorders(int sample, const Sample& s, GridArray<float>& out) const {
  const int m = level_;
  for (int e = 0; e < 4; ++e) {
    for (int i = m; i >= 0; --i) {
      for (uint32_t j = 0; j < (1u << i); ++j) {
        Box3 b = curveBox(e, i, j, sample);
        size_t v0, v1;
        chordEnds(e, i, j, m, v0, v1);
        b.extend(s.positions[v0]);
        b.extend(s.positions[v1]);
        float* box = out.data() + borderOffset(e, i, j);
        if (i < m) {
          const float* c = out.data() + borderOffset(e, i + 1, 2 * j);  // the two children are adjacent
          for (int a = 0; a < 3; ++a) {
            b.lo[a] = std::min(b.lo[a], std::min(c[a], c[6 + a]));
            b.hi[a] = std::max(b.hi[a], std::max(c[3 + a], c[9 + a]));
          }
        }
        for (int a = 0; a < 3; ++a) {
          box[a] = b.lo[a];
          box[3 + a] = b.hi[a];
        }
      }
    }
  }
}

// The radius about the line through the chord (a, b) of segment j of border e at level k that
// holds the true border curve: the curve lies in the boxes of its pieces (with `blend`, the
// blend of both samples' boxes at time weights w0, w1, which holds the blended curve), and its
// distance from the line is at most their farthest corner's. The radius exceeds the curve's
// true distance by about a piece's size, so a static dicing's region takes pieces of level
// k + radiusSplit(k) = max(k + 3, 6) (at most 64): coarse segments, which secondary rays
// with wide footprints use, would otherwise make curved objects visibly fatter for them (a
// moving dicing, computed per query: k + 3). Level 6, not 7: a level-0 radius of a displaced
// forest leaf from 128 pieces cost about twice a level-5 dicing of it (estimated), and such
// radii were about a quarter of a forest render's profile; 64 pieces fatten a level-0 region by
// 1/64 of the patch instead of 1/128 (bench/history/2026-11.md, "Border radii from pieces of level
// 6"). The pieces come from the patch in one call (Patch::borderPieceBoundsAt: a Bézier border is
// restricted once and halved, not restricted from the whole patch per piece, which was a third of a
// forest render's time); they are not the region boxes (curveBox), whose bits differ. (Tried:
// branch and bound, splitting only the piece that reaches farthest; on displaced borders every
// piece's box reaches about as far, so it split nearly all and made up to twice the boundsOver
// calls.)
double DiceBuffer::borderRadius(int e, int k, uint32_t j, Vec3 a, Vec3 b, int split, bool blend, float w0,
                                float w1) const {
  const double ax[3] = {double(b.x) - a.x, double(b.y) - a.y, double(b.z) - a.z};
  const double len2 = ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2];
  if (!(len2 > 0)) return 0.0;  // rayCylinder ignores the radius of a degenerate chord
  // Box3 arrays are initialised: a coarse radius's 8 pieces should not pay for 128.
  auto farthest = [&](auto& boxes, auto& other) {
    patch_->borderPieceBoundsAt(sampleA_, e, k, j, split, boxes);
    if (blend) patch_->borderPieceBoundsAt(sampleA_ + 1, e, k, j, split, other);
    double worst = 0;
    for (uint32_t i = 0; i < (1u << split); ++i) {
      Box3 box = boxes[i];
      if (blend) {
        box.lo = lerpPoint(box.lo, other[i].lo, w0, w1);
        box.hi = lerpPoint(box.hi, other[i].hi, w0, w1);
      }
      worst = std::max(worst, farthestCorner2(box, a, ax, len2));
    }
    return worst;
  };
  if (split <= 3) {
    Box3 boxes[8], other[8];
    return radiusFrom(farthest(boxes, other));
  }
  Box3 boxes[1u << Patch::kMaxPieceSplit], other[1u << Patch::kMaxPieceSplit];
  return radiusFrom(farthest(boxes, other));
}

double DiceBuffer::cachedRadius(int e, int k, uint32_t j, Vec3 a, Vec3 b, bool coarse) const {
  BorderSegment& seg = segments_[borderOffset(e, k, j) / 6];
  const int which = coarse ? 0 : 1;
  if (seg.radiusStamp[which].load(std::memory_order_acquire) == stamp_)
    return seg.radius[which].load(std::memory_order_relaxed);
  const BorderBoundCache::Key key{shared_.leaf,
                                  coarse ? BorderBoundCache::Kind::CoarseRadius : BorderBoundCache::Kind::FineRadius,
                                  e, k, j};
  double r;
  if (!shared_.cache || !shared_.cache->find(key, r)) {
    r = borderRadius(e, k, j, a, b, coarse ? 3 : radiusSplit(k), false, 1.0f, 0.0f);
    if (shared_.cache) shared_.cache->insert(key, r);
  }
  seg.radius[which].store(r, std::memory_order_relaxed);
  seg.radiusStamp[which].store(stamp_, std::memory_order_release);
  return r;
}

}  // namespace rayes
