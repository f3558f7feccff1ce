// Groups the candidate slots of one iteration by leaf, so that every leaf is diced once and
// all its rays are intersected while it is in one thread's dice buffer.
// The caller fills `order` with the filled slot indices in increasing order; sort() sorts them
// in place by (leaf, slot) and sets `runs` to the start of each leaf's run in `order` plus a
// final end sentinel. The slots are sorted as they are, reading each one's leaf where it lies:
// `order` and 4 bytes of scratch per slot are all it holds (no (leaf, slot) pairs, no separate
// input list: the radix passes ping-pong between the two). The order is fully determined by
// the input (the sort is stable and the slots come in increasing order), whatever the thread
// count.
//
// Hand-written because it was measured faster: a parallel LSD radix sort (oneTBB) on the leaf
// id alone, sorting only as many bits as the largest leaf id has, is 7.7-11.5x faster than
// tbb::parallel_sort of 64-bit (leaf, slot) keys on this machine (bench/RESULTS.md,
// bench/rays_candidate_sort.cpp).
// Complexity O(n * ceil(bits / 11)); scratch is kept across iterations, and between sorts it
// is free, as long as `order` (the SortedEngine keeps each sorted slot's box entry there).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace rayes {

struct CandidateSort {
  std::vector<uint32_t> scratch;
  std::vector<uint32_t> offsets;
  std::vector<uint32_t> order;
  std::vector<uint32_t> runs;
  // Bytes per sorted slot: `order` and `scratch`.
  static constexpr size_t bytesPerSlot() { return 2 * sizeof(uint32_t); }

  // Sorts `order` (filled slot indices in increasing order) by leaf; leafOf: leaf id per slot.
  void sort(const std::vector<uint32_t>& leafOf);
};

}  // namespace rayes
