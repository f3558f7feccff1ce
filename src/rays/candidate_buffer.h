// The (ray, leaf) candidate buffer of one iteration (thesis Fig. 6.5): the leaf id per slot,
// and the ray's level of detail on that leaf. Active ray a owns slots [a*N, a*N + count[a]),
// filled by the top-level traversal in (entry distance, leaf) order. Hits are not stored per
// slot: the bottom level offers each one straight to its ray (Tracer::offerHit), so a slot
// costs 5 bytes. Capacity is fixed at construction (the candidate part of --ray-memory).
//
// Why the level is kept: it is computed from the ray's record (Tracer::levelFor), which the
// top level reads in ray order, from cache; the per-leaf stages visit slots in leaf order, where
// every ray record is a cache miss, and the dicing level of a run (the largest of its slots')
// is needed before any of them is intersected. Reading those records there was a tenth of a
// forest render's time (bench/RESULTS.md).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace rayes {

struct CandidateBuffer {
  std::vector<uint32_t> leaf;  // kNoLeaf: the ray's ignored leaf, not intersected
  std::vector<uint8_t> level;  // the ray's level on that leaf (per-ray LOD rules only)

  explicit CandidateBuffer(size_t capacity) : leaf(capacity), level(capacity) {}
  size_t capacity() const { return leaf.size(); }
  static constexpr size_t bytesPerSlot() { return sizeof(uint32_t) + sizeof(uint8_t); }
};

}  // namespace rayes
