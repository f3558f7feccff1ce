// How one leaf's run of ray slots is processed (SortedEngine::intersectRun, trackBrickRun): a
// short run by the calling thread at once, a long one in chunks of kRunChunk slots that other
// threads may take, isolated so a thread waiting on the chunks does not pick up another leaf's
// work (and its per-thread dice buffer) meanwhile. `range(k0, k1)` processes slots [k0, k1).
#pragma once
#include <cstddef>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace rayes {

inline constexpr size_t kRunChunk = 1024;

template <class Range>
void forRunChunks(size_t count, Range&& range) {
  if (count <= 2 * kRunChunk) {
    range(size_t(0), count);
    return;
  }
  tbb::this_task_arena::isolate([&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, kRunChunk),
                      [&](const tbb::blocked_range<size_t>& c) { range(c.begin(), c.end()); });
  });
}

}  // namespace rayes
