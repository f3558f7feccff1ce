#include "rays/candidate_sort.h"
#include <algorithm>
#include <bit>
#include <stdexcept>
#include <tbb/parallel_for.h>

namespace rayes {
namespace {
constexpr int kMaxDigitBits = 11;  // 2048 counters per block stay in L1
}

void CandidateSort::sort(const std::vector<uint32_t>& leafOf, std::span<uint32_t> scratch) {
  const size_t n = order.size();
  if (scratch.size() < n) throw std::logic_error("CandidateSort: less scratch than slots");
  std::span<uint32_t> from(order.data(), n), to = scratch.first(n);
  uint32_t maxLeaf = 0;
  for (size_t i = 0; i < n; ++i) maxLeaf = std::max(maxLeaf, leafOf[from[i]]);
  const int bits = std::max(1, 32 - std::countl_zero(maxLeaf));
  const int passes = (bits + kMaxDigitBits - 1) / kMaxDigitBits;
  const int digitBits = (bits + passes - 1) / passes;
  const size_t radix = size_t(1) << digitBits;
  const size_t blocks = std::clamp<size_t>(n / 65536, 1, 64);
  offsets.resize(blocks * radix);
  auto blockRange = [&](size_t b) { return std::pair{n * b / blocks, n * (b + 1) / blocks}; };
  for (int pass = 0; pass < passes; ++pass) {
    const int shift = pass * digitBits;
    const uint32_t mask = uint32_t(radix - 1);
    tbb::parallel_for(size_t(0), blocks, [&](size_t b) {
      uint32_t* count = &offsets[b * radix];
      std::fill(count, count + radix, 0u);
      const auto [lo, hi] = blockRange(b);
      for (size_t i = lo; i < hi; ++i) ++count[(leafOf[from[i]] >> shift) & mask];
    });
    uint32_t sum = 0;  // digit-major exclusive scan: block b's digit d follows blocks < b (stable)
    for (size_t d = 0; d < radix; ++d)
      for (size_t b = 0; b < blocks; ++b) {
        const uint32_t c = offsets[b * radix + d];
        offsets[b * radix + d] = sum;
        sum += c;
      }
    tbb::parallel_for(size_t(0), blocks, [&](size_t b) {
      uint32_t* next = &offsets[b * radix];
      const auto [lo, hi] = blockRange(b);
      for (size_t i = lo; i < hi; ++i) to[next[(leafOf[from[i]] >> shift) & mask]++] = from[i];
    });
    std::swap(from, to);
  }
  sorted = from;
  spare = to;
  runs.clear();
  for (size_t i = 0; i < n; ++i)
    if (i == 0 || leafOf[from[i]] != leafOf[from[i - 1]]) runs.push_back(static_cast<uint32_t>(i));
  runs.push_back(static_cast<uint32_t>(n));
}

}  // namespace rayes
