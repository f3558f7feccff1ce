// releaseFreedMemory (core/memory.h): the pages of heap blocks that were freed but that glibc
// keeps in its arena (it returns only the top of a heap) leave the resident set. What lbt's beam
// account relies on to keep the resident set within --beam-memory (lbt/beam_budget.h).
#include <gtest/gtest.h>
#include <unistd.h>
#include <cstdlib>
#include <cstring>
#include <vector>
#include "core/memory.h"

namespace rayes {
namespace {

TEST(ReleaseFreedMemory, FreedBlocksInsideTheHeapLeaveTheResidentSet) {
#if !defined(__GLIBC__)
  GTEST_SKIP() << "glibc's arenas only";
#elif defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer has its own allocator";
#else
  // 1024 blocks of 60 KiB (below glibc's mmap threshold, 128 KiB at least: from the heap), each
  // written; then 15 of every 16 freed. The 16th ones stay and pin the heap, so free() alone
  // gives nothing back: each run of 15 coalesces into one free chunk inside it.
  constexpr size_t kBlock = 60 << 10, kBlocks = 1024, kRun = 16;
  std::vector<char*> blocks(kBlocks);
  for (char*& b : blocks) {
    b = static_cast<char*>(std::malloc(kBlock));
    ASSERT_NE(b, nullptr);
    std::memset(b, 1, kBlock);
  }
  for (size_t i = 0; i < kBlocks; ++i)
    if (i % kRun != kRun - 1) {
      std::free(blocks[i]);
      blocks[i] = nullptr;
    }
  const uint64_t before = currentRssBytes();
  ASSERT_GT(before, 0u) << "no /proc/self/statm";
  releaseFreedMemory();
  const uint64_t after = currentRssBytes();
  // Every whole page of each free chunk goes: at most the two pages at its ends (partly the
  // neighbours' and the chunk's own header) stay per run.
  const uint64_t page = uint64_t(sysconf(_SC_PAGESIZE));
  const uint64_t runs = kBlocks / kRun, freed = (kBlocks - runs) * kBlock;
  EXPECT_GE(before - std::min(before, after), freed - runs * 2 * page)
      << "before " << before << ", after " << after;
  for (char* b : blocks) std::free(b);
#endif
}

}  // namespace
}  // namespace rayes
