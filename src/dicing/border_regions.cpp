// The border regions of a dicing (see dice_buffer.h): the boxes of the true border curve over
// border segments, a moving dicing's border trees, and the regions' radii about their chords.
#include <algorithm>
#include <cmath>
#include "dicing/dice_buffer.h"
#include "dicing/micro_quad.h"

namespace rayes {

namespace {

// Grid indices of the two ends of segment j of border e at level i of a level-m grid.
void chordEnds(int e, int i, uint32_t j, int m, size_t& v0, size_t& v1) {
  const size_t res = (size_t(1) << m) + 1;
  const size_t stride = size_t(1) << (m - i);
  switch (e) {
    case 0: v0 = j * stride; v1 = v0 + stride; break;
    case 1: v0 = j * stride * res + (res - 1); v1 = v0 + stride * res; break;
    case 2: v0 = (res - 1) * res + j * stride; v1 = v0 + stride; break;
    default: v0 = j * stride * res; v1 = v0 + stride * res; break;
  }
}

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

// The pieces of a radius are those of level k + split: the radius exceeds the curve's true
// distance by about a piece's size, so coarse segments, which secondary rays with wide
// footprints use, take pieces of level 7 (128 per segment at level 0): curved objects would
// otherwise get visibly fatter for them.
int radiusSplit(int k) { return std::max(3, 7 - k); }

}  // namespace

Box3 DiceBuffer::curveBox(int e, int i, uint32_t j, int sample) const {
  BorderSegment* seg = !moving_ && i <= maxLevel_ ? &segments_[borderOffset(e, i, j) / 6] : nullptr;
  if (seg && seg->boxStamp.load(std::memory_order_acquire) == stamp_) {
    Box3 b;
    for (int a = 0; a < 3; ++a) {
      b.lo[a] = seg->box[a].load(std::memory_order_relaxed);
      b.hi[a] = seg->box[3 + a].load(std::memory_order_relaxed);
    }
    return b;
  }
  const float inv = 1.0f / float(1u << i);  // a power of two: j * inv is exact
  const float t0 = float(j) * inv, t1 = float(j + 1) * inv;
  Box3 b;
  switch (e) {
    case 0: b = patch_->boundsOverAt(sample, t0, t1, 0.0f, 0.0f); break;
    case 1: b = patch_->boundsOverAt(sample, 1.0f, 1.0f, t0, t1); break;
    case 2: b = patch_->boundsOverAt(sample, t0, t1, 1.0f, 1.0f); break;
    default: b = patch_->boundsOverAt(sample, 0.0f, 0.0f, t0, t1); break;
  }
  if (seg) {
    for (int a = 0; a < 3; ++a) {
      seg->box[a].store(b.lo[a], std::memory_order_relaxed);
      seg->box[3 + a].store(b.hi[a], std::memory_order_relaxed);
    }
    seg->boxStamp.store(stamp_, std::memory_order_release);
  }
  return b;
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
void DiceBuffer::buildBorders(const Patch&, int sample, const Sample& s, std::vector<float>& out) const {
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
// holds the true border curve of a moving dicing: the curve lies in the boxes of its pieces
// (at time weights w0, w1 with `blend`, the blend of both samples' boxes, which holds the
// blended curve; computed per query, so with pieces of level k + 3 only), and its distance
// from the line is at most their farthest corner's.
double DiceBuffer::borderRadius(int e, int k, uint32_t j, Vec3 a, Vec3 b, float w0, float w1, bool blend) const {
  const int split = blend ? 3 : radiusSplit(k);
  const double ax[3] = {double(b.x) - a.x, double(b.y) - a.y, double(b.z) - a.z};
  const double len2 = ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2];
  if (!(len2 > 0)) return 0.0;  // rayCylinder ignores the radius of a degenerate chord
  const uint32_t pieces = 1u << split;
  double worst = 0;
  for (uint32_t i = 0; i < pieces; ++i) {
    Box3 box = curveBox(e, k + split, j * pieces + i, sampleA_);
    if (blend) {
      const Box3 other = curveBox(e, k + split, j * pieces + i, sampleA_ + 1);
      box.lo = lerpPoint(box.lo, other.lo, w0, w1);
      box.hi = lerpPoint(box.hi, other.hi, w0, w1);
    }
    worst = std::max(worst, farthestCorner2(box, a, ax, len2));
  }
  return radiusFrom(worst);
}

// A static dicing's radius: the same bound as borderRadius's over the pieces of level k +
// radiusSplit(k), found by branch and bound instead of from all of them. A cover of the
// segment by pieces (the segment itself first) is refined by splitting the piece whose box
// reaches farthest from the line, until that piece is of the finest level: its distance is
// then at least every other piece's, so it bounds the curve, and it is one of the pieces the
// exhaustive bound takes the largest of, so the radius is no larger. Pieces whose boxes stay
// closer to the chord than the answer are never split; their boxes (and the split ones') are
// the curveBox entries the traversal's walk shares. A pure function of (e, k, j): the order of
// splits depends only on the boxes.
double DiceBuffer::staticBorderRadius(int e, int k, uint32_t j, Vec3 a, Vec3 b) const {
  const double ax[3] = {double(b.x) - a.x, double(b.y) - a.y, double(b.z) - a.z};
  const double len2 = ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2];
  if (!(len2 > 0)) return 0.0;  // rayCylinder ignores the radius of a degenerate chord
  const int finest = k + radiusSplit(k);
  struct Piece {
    double d2;
    int level;
    uint32_t j;
  };
  // Farthest first; ties by (level, j), so the order of splits is fixed.
  auto nearer = [](const Piece& x, const Piece& y) {
    if (x.d2 != y.d2) return x.d2 < y.d2;
    if (x.level != y.level) return x.level > y.level;
    return x.j > y.j;
  };
  // Each split replaces one piece by two, and at most 2^split - 1 pieces are split.
  Piece heap[2 << 7];
  int size = 0;
  auto push = [&](int level, uint32_t s) {
    heap[size++] = {farthestCorner2(curveBox(e, level, s, 0), a, ax, len2), level, s};
    std::push_heap(heap, heap + size, nearer);
  };
  push(k, j);
  for (;;) {
    std::pop_heap(heap, heap + size, nearer);
    const Piece top = heap[--size];
    if (top.level >= finest) return radiusFrom(top.d2);
    push(top.level + 1, 2 * top.j);
    push(top.level + 1, 2 * top.j + 1);
  }
}

}  // namespace rayes
