// The (ray, leaf) candidate buffer of one iteration (thesis Fig. 6.5): the leaf id per slot.
// Active ray a owns slots [a*N, a*N + count[a]), filled by the top-level traversal in
// (entry distance, leaf) order. Hits are not stored per slot: the bottom level offers each one
// straight to its ray (SortedEngine::offerHit), so a slot costs 4 bytes. Capacity is fixed at
// construction (the candidate part of --ray-memory).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace rayes {

struct CandidateBuffer {
  std::vector<uint32_t> leaf;  // kNoLeaf: the ray's ignored leaf, not intersected

  explicit CandidateBuffer(size_t capacity) : leaf(capacity) {}
  size_t capacity() const { return leaf.size(); }
  static constexpr size_t bytesPerSlot() { return sizeof(uint32_t); }
};

}  // namespace rayes
