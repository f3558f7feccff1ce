// The queries of a LeafQueries batch (core/leaf_queries.h) grouped by leaf, with the candidates'
// sort (CandidateSort: stable, so each leaf's ids stay in increasing order): what every engine
// needs to call the runner once per leaf. The SortedEngine interleaves these runs with its own
// per-leaf tasks (rays/sorted_engine.cpp, diceAndIntersectRuns); the engines without a per-leaf
// stage, and the SortedEngine when it has no rays or traces them one at a time, run them in a
// plain oneTBB loop (runAll). Scratch is kept across calls.
#pragma once
#include <cstdint>
#include <span>
#include <vector>
#include "core/leaf_queries.h"
#include "core/timer.h"
#include "rays/candidate_sort.h"

namespace rayes {

class LeafQueryRuns {
 public:
  // Groups the filled slots of `queries` by leaf (none when it has no runner). Returns the
  // number of runs.
  size_t group(const LeafQueries& queries);
  size_t runs() const { return sort_.runs.empty() ? 0 : sort_.runs.size() - 1; }
  uint32_t leafOf(size_t run) const { return leaf_[sort_.sorted[sort_.runs[run]]]; }
  std::span<const uint32_t> ids(size_t run) const {
    return sort_.sorted.subspan(sort_.runs[run], size_t(sort_.runs[run + 1] - sort_.runs[run]));
  }
  // Calls the runner for run `run` (timed into `time`, summed over threads): a run of more than
  // 2 kChunk queries in chunks of kChunk that other threads may take, isolated so this thread
  // does not pick up another leaf's task meanwhile (as SortedEngine::intersectRun does for rays).
  void run(size_t run, TimeAccumulator& time) const;
  static constexpr size_t kChunk = 256;
  // Every run, in parallel; then forgets them.
  void runAll(TimeAccumulator& time);
  void clear();

 private:
  std::span<const uint32_t> leaf_;
  LeafQueryRunner* runner_ = nullptr;
  CandidateSort sort_;
  // The sort's scratch, its own: the candidate sort's (the batch's RayBatch::sortScratch) is
  // live beside it while the first iteration runs both kinds of runs.
  std::vector<uint32_t> scratch_;
};

}  // namespace rayes
