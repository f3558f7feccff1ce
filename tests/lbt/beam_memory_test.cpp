// What --beam-memory bounds in real allocations (lbt/beam_budget.h; issue 30: lbt's resident
// set was 8 % over its budget): a store's allocations stay within what it takes from the
// account, and the account returns freed pages to the system after every releaseStep() bytes
// given back. Every operator new of this test program is counted (its usable size, so the
// count is what the heap really holds), so the first test can compare the store's live bytes at
// their peak with the account's.
#include <gtest/gtest.h>
#include <atomic>
#include <cstdlib>
#include <new>
#include <vector>
#include <unistd.h>
#include <tbb/global_control.h>
#include "lbt/beam_budget.h"
#include "lbt/beam_store.h"
#include "toplevel/toplevel_bvh.h"
#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace {
std::atomic<size_t> liveBytes{0}, peakLiveBytes{0};
size_t usable(void* p) {
#if defined(__GLIBC__)
  return p ? malloc_usable_size(p) : 0;
#else
  (void)p;
  return 0;
#endif
}
}  // namespace

// The replaceable allocation functions the others (nothrow, arrays, sized delete) call.
void* operator new(size_t n) {
  void* p = std::malloc(n ? n : 1);
  if (!p) throw std::bad_alloc();
  const size_t live = liveBytes.fetch_add(usable(p)) + usable(p);
  size_t peak = peakLiveBytes.load();
  while (live > peak && !peakLiveBytes.compare_exchange_weak(peak, live)) {}
  return p;
}
void operator delete(void* p) noexcept {
  liveBytes.fetch_sub(usable(p));
  std::free(p);
}
void operator delete(void* p, size_t) noexcept { operator delete(p); }

namespace rayes {
namespace {

// n×n cells of a mirror at z = 0 sending beams up to a ceiling at z = 2 made of m×m leaves.
std::vector<BeamSegment> risingBeams(int n, float sigma) {
  std::vector<BeamSegment> out;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      for (int half = 0; half < 2; ++half) {
        BeamSegment s;
        const float x = -1 + 2.0f * float(i) / float(n), y = -1 + 2.0f * float(j) / float(n), h = 2.0f / float(n);
        const Vec3 c[3] = {{x, y, 0}, half ? Vec3{x + h, y + h, 0} : Vec3{x + h, y, 0}, half ? Vec3{x, y + h, 0} : Vec3{x + h, y + h, 0}};
        for (int k = 0; k < 3; ++k) {
          s.o[k] = c[k];
          s.d[k] = normalize(c[k] - Vec3{0, 0, -1});
          s.t[k] = 2 / s.d[k].z;
        }
        s.power = Rgb{1, 1, 1};
        s.sigma = sigma;
        out.push_back(s);
      }
  return out;
}

TEST(BeamMemory, AStoresAllocationsStayWithinWhatItTakesFromTheAccount) {
#if !defined(__GLIBC__)
  GTEST_SKIP() << "counts usable sizes with glibc's malloc_usable_size";
#endif
  // One thread: the binning's per-thread scratch (not on the account) is then one set.
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  constexpr int kLeavesPerSide = 16;
  std::vector<Box3> boxes;
  for (int j = 0; j < kLeavesPerSide; ++j)
    for (int i = 0; i < kLeavesPerSide; ++i) {
      const float x0 = -4 + 8.0f * float(i) / kLeavesPerSide, y0 = -4 + 8.0f * float(j) / kLeavesPerSide;
      boxes.push_back({{x0, y0, 2}, {x0 + 8.0f / kLeavesPerSide, y0 + 8.0f / kLeavesPerSide, 2}});
    }
  TopLevelBvh top;
  top.build(boxes);
  for (const float sigma : {0.0f, 0.05f}) {
    SCOPED_TRACE(sigma);
    std::vector<BeamSegment> segments = risingBeams(24, sigma);
    const size_t n = segments.size();
    BeamBudget account(size_t(1) << 30);
    const size_t before = liveBytes.load();
    peakLiveBytes.store(before);
    size_t entries = 0, held = 0, transient = 0;
    {
      const BeamStore store(std::move(segments), top, top.leafBoxes(), account.limit(), {}, 1 << 30, &account);
      ASSERT_TRUE(store.fits());
      entries = store.binEntries();
      // The segments came in with the store (allocated before, not on this account).
      held = liveBytes.load() - before;
      transient = peakLiveBytes.load() - before;
      EXPECT_EQ(account.used() + n * sizeof(BeamSegment), store.bytes()) << "the store's bytes besides the segments stay on the account";
    }
    // What the account does not hold: the per-thread scratch of one thread -- the top level's
    // traversal heap (at most one 8-byte item per leaf), a segment's leaves and cells (at most
    // every leaf and every entry), each in a vector grown by doubling (2x) -- and the
    // allocator's rounding of each block: a page for the blocks it maps (the store's arrays and
    // the binning's lists: nine), 24 bytes for the others (the scratch vectors' reallocations:
    // at most 64 each).
    const size_t scratch = 2 * (boxes.size() * (8 + sizeof(uint32_t)) + entries * sizeof(uint64_t));
    const size_t rounding = 9 * size_t(sysconf(_SC_PAGESIZE)) + 3 * 64 * 24;
    EXPECT_LE(held, account.peak() + rounding) << "the arrays the store keeps are on the account";
    EXPECT_LE(transient, account.peak() + scratch + rounding)
        << "the binning's lists and counts are on the account before they are made";
    EXPECT_GT(entries, n) << "beams reach more than one cell each: the binning's lists matter";
  }
}

TEST(BeamMemory, FreedPagesAreReturnedAfterEveryReleaseStepGivenBack) {
  BeamBudget account(size_t(256) << 20);
  EXPECT_EQ(account.releaseStep(), (size_t(256) << 20) / 64) << "1/64 of the budget";
  EXPECT_EQ(BeamBudget(size_t(16) << 20).releaseStep(), size_t(1) << 20) << "at least 1 MiB";
  const size_t step = account.releaseStep();
  account.take(3 * step, "test");
  account.give(step - 1);
  account.take(1, "test");
  EXPECT_EQ(account.releases(), 0u) << "less than a step given back: nothing returned";
  account.give(1);
  EXPECT_EQ(account.releases(), 0u) << "returned by the next take, not by the give";
  account.take(1, "test");
  EXPECT_EQ(account.releases(), 1u);
  // Kept grids the account frees count as given back too.
  account.keep(step);
  account.keep(0);
  account.take(1, "test");
  EXPECT_EQ(account.releases(), 2u);
  account.take(1, "test");
  EXPECT_EQ(account.releases(), 2u) << "nothing given since";
}

}  // namespace
}  // namespace rayes
