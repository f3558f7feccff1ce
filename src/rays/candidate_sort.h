// Groups the candidate slots of one iteration by leaf, so that every leaf is diced once and
// all its rays are intersected while it is in one thread's dice buffer.
// The caller fills `order` with the filled slot indices in increasing order and lends as many
// words of scratch; sort() sorts the slots by (leaf, slot) into `sorted` and sets `runs` to the
// start of each leaf's run in `sorted` plus a final end sentinel. The slots are sorted as they
// are, reading each one's leaf where it lies: `order` and the scratch are all it holds (no
// (leaf, slot) pairs, no separate input list): the radix passes ping-pong between the two, so
// `sorted` lies in whichever the last pass wrote and `spare` is the other, free for the caller
// until the next sort (the SortedEngine keeps each sorted slot's box entry there). The scratch
// is the caller's (the SortedEngine's is the batch's RayBatch::sortScratch, which the shading
// sort uses while the trace does not: core/sort_scratch.h). The order is fully determined by
// the input (the sort is stable and the slots come in increasing order), whatever the thread
// count.
//
// Hand-written because it was measured faster: a parallel LSD radix sort (oneTBB) on the leaf
// id alone, sorting only as many bits as the largest leaf id has, is 7.7-11.5x faster than
// tbb::parallel_sort of 64-bit (leaf, slot) keys on this machine (bench/RESULTS.md,
// bench/rays_candidate_sort.cpp).
// Complexity O(n * ceil(bits / 11)); `order`, `offsets` and `runs` are kept across sorts.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace rayes {

struct CandidateSort {
  std::vector<uint32_t> order;    // in: the filled slots, increasing
  std::vector<uint32_t> offsets;
  std::vector<uint32_t> runs;
  std::span<uint32_t> sorted;     // out: order's slots by (leaf, slot), in `order` or the scratch
  std::span<uint32_t> spare;      // out: the other of the two, as long as `sorted`
  // Bytes per sorted slot that the sort itself holds: its place in `order`. The scratch the
  // caller lends is as much again (scratchBytesPerSlot).
  static constexpr size_t bytesPerSlot() { return sizeof(uint32_t); }
  static constexpr size_t scratchBytesPerSlot() { return sizeof(uint32_t); }

  // Sorts `order` (filled slot indices in increasing order) by leaf; leafOf: leaf id per slot;
  // scratch: at least order.size() words, the caller's until it reuses them (`spare`, `sorted`).
  void sort(const std::vector<uint32_t>& leafOf, std::span<uint32_t> scratch);
};

}  // namespace rayes
