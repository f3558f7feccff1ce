// Z-order (Morton) indices for the nodes of one level of the implicit quad-tree. With them the
// four children of node c on level i are the four consecutive nodes 4c..4c+3 on level i+1, so
// the bottom-up build is a linear sweep and a traversal step reads one contiguous run.
#pragma once
#include <cstdint>

namespace rayes::detail {

// Spreads the low 16 bits of x to the even bit positions.
constexpr uint32_t spreadBits(uint32_t x) {
  x &= 0x0000ffffu;
  x = (x | (x << 8)) & 0x00ff00ffu;
  x = (x | (x << 4)) & 0x0f0f0f0fu;
  x = (x | (x << 2)) & 0x33333333u;
  x = (x | (x << 1)) & 0x55555555u;
  return x;
}

// Inverse of spreadBits on the even bit positions.
constexpr uint32_t compactBits(uint32_t x) {
  x &= 0x55555555u;
  x = (x | (x >> 1)) & 0x33333333u;
  x = (x | (x >> 2)) & 0x0f0f0f0fu;
  x = (x | (x >> 4)) & 0x00ff00ffu;
  x = (x | (x >> 8)) & 0x0000ffffu;
  return x;
}

constexpr uint32_t morton(uint32_t x, uint32_t y) { return spreadBits(x) | (spreadBits(y) << 1); }
constexpr uint32_t mortonX(uint32_t c) { return compactBits(c); }
constexpr uint32_t mortonY(uint32_t c) { return compactBits(c >> 1); }

// Offset of tree level i in the node array: sum_{l<i} 4^l.
constexpr size_t levelOffset(int i) { return ((size_t(1) << (2 * i)) - 1) / 3; }

}  // namespace rayes::detail
