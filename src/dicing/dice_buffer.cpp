// DiceBuffer storage and the bottom-up build of the implicit quad-tree (thesis §6.1.1).
#include "dicing/dice_buffer.h"
#include <stdexcept>
#include "dicing/morton.h"
#include "dicing/patch_math.h"

namespace rayes {

using detail::levelOffset;
using detail::morton;

DiceBuffer::DiceBuffer(int maxLevel) : maxLevel_(maxLevel) {
  if (maxLevel < 0 || maxLevel > 12) throw std::invalid_argument("DiceBuffer: maxLevel not in 0..12");
  const size_t res = (size_t(1) << maxLevel) + 1;
  positions_.resize(res * res);
  normals_.resize(res * res);
  nodes_.resize(levelOffset(maxLevel + 1));
}

void DiceBuffer::dice(const Patch& patch, int level) {
  if (level < 0 || level > maxLevel_) throw std::invalid_argument("DiceBuffer::dice: level > maxLevel");
  level_ = level;
  patchBounds_ = patch.bounds();
  patch.dice(level, positions_.data(), normals_.data());
  const size_t count = size_t(resolution()) * resolution();
  for (size_t k = 0; k < count; ++k) normals_[k] = detail::unitOrZero(normals_[k]);
  buildTree();
}

// Level m: the box of each micro-quad's 4 corners (the two flat triangles lie in their convex
// hull). Level i < m: the union of the 4 children, which Z-order keeps consecutive. One linear
// pass per level, no sorting: O(4^m) in total.
void DiceBuffer::buildTree() {
  const uint32_t n = 1u << level_;
  const size_t res = n + 1;
  Box3* leaves = &nodes_[levelOffset(level_)];
  for (uint32_t y = 0; y < n; ++y) {
    const Vec3* row = &positions_[y * res];
    for (uint32_t x = 0; x < n; ++x) {
      const Vec3 p00 = row[x], p10 = row[x + 1], p01 = row[res + x], p11 = row[res + x + 1];
      Box3& b = leaves[morton(x, y)];
      b.lo = vmin(vmin(p00, p10), vmin(p01, p11));
      b.hi = vmax(vmax(p00, p10), vmax(p01, p11));
    }
  }
  for (int i = level_ - 1; i >= 0; --i) {
    Box3* parents = &nodes_[levelOffset(i)];
    const Box3* children = &nodes_[levelOffset(i + 1)];
    const size_t count = size_t(1) << (2 * i);
    for (size_t c = 0; c < count; ++c) {
      const Box3* ch = children + 4 * c;
      parents[c].lo = vmin(vmin(ch[0].lo, ch[1].lo), vmin(ch[2].lo, ch[3].lo));
      parents[c].hi = vmax(vmax(ch[0].hi, ch[1].hi), vmax(ch[2].hi, ch[3].hi));
    }
  }
}

Vec3 DiceBuffer::position(int i, int j) const { return positions_[size_t(j) * resolution() + i]; }
Vec3 DiceBuffer::normal(int i, int j) const { return normals_[size_t(j) * resolution() + i]; }

const Box3& DiceBuffer::node(int treeLevel, int x, int y) const {
  return nodes_[levelOffset(treeLevel) + morton(uint32_t(x), uint32_t(y))];
}

size_t DiceBuffer::nodeCount() const { return levelOffset(level_ + 1); }

size_t DiceBuffer::bytesAllocated() const {
  return positions_.capacity() * sizeof(Vec3) + normals_.capacity() * sizeof(Vec3) +
         nodes_.capacity() * sizeof(Box3);
}

}  // namespace rayes
