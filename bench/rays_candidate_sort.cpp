// Candidate sort throughput: the production rayes::CandidateSort (src/rays/candidate_sort.h, a
// stable parallel LSD radix sort of the slots on their leaf id, read where it lies) against
// tbb::parallel_sort of 64-bit (leaf << 32 | slot) keys, which gives the same order.
// Input: the filled slots 0..n-1 in increasing order (as the SortedEngine hands them over), leaf ids
// random in [0, 100000). Both sides include their own packing/unpacking: CandidateSort copies
// its input in (it consumes it), reads each slot's leaf in every pass and writes `order` and
// `runs`; the 64-bit side packs the keys, sorts, and unpacks the slot order (runs are not
// computed for it, which favours it slightly). Run: bench_rays_candidate_sort ; figures in
// bench/history/RESULTS-toplevel.md (candidate sort section).
#include <benchmark/benchmark.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/rng.h"
#include "rays/candidate_sort.h"

namespace {

using namespace rayes;
constexpr uint32_t kLeaves = 100000;

struct Input {
  std::vector<uint32_t> slots, leafOf;
};

Input randomCandidates(size_t n) {
  Input in;
  in.slots.resize(n);
  in.leafOf.resize(n);
  for (size_t i = 0; i < n; ++i) {
    in.slots[i] = uint32_t(i);
    in.leafOf[i] = uint32_t(mix64(i * 0x9e3779b97f4a7c15ull + 11) % kLeaves);
  }
  return in;
}

void setPairRate(benchmark::State& state, size_t n) {
  state.counters["Mpairs/s"] =
      benchmark::Counter(double(n) * double(state.iterations()) * 1e-6, benchmark::Counter::kIsRate);
}

void BM_TbbParallelSort64(benchmark::State& state) {
  const Input in = randomCandidates(size_t(state.range(0)));
  const size_t n = in.slots.size();
  std::vector<uint64_t> keys(n);
  std::vector<uint32_t> order(n);
  for (auto _ : state) {
    for (size_t i = 0; i < n; ++i) keys[i] = uint64_t(in.leafOf[in.slots[i]]) << 32 | in.slots[i];
    tbb::parallel_sort(keys.begin(), keys.end());
    for (size_t i = 0; i < n; ++i) order[i] = uint32_t(keys[i]);
    benchmark::DoNotOptimize(order.data());
  }
  setPairRate(state, n);
}
BENCHMARK(BM_TbbParallelSort64)->Arg(1 << 20)->Arg(1 << 23)->UseRealTime()->Unit(benchmark::kMillisecond);

void BM_CandidateSort(benchmark::State& state) {
  const Input in = randomCandidates(size_t(state.range(0)));
  const size_t n = in.slots.size();
  CandidateSort sort;
  std::vector<uint32_t> scratch(n);  // the engine lends the batch's (RayBatch::sortScratch)
  {  // the result must equal the 64-bit key sort, and runs must delimit the leaves
    sort.order = in.slots;
    sort.sort(in.leafOf, scratch);
    std::vector<uint64_t> keys(n);
    for (size_t i = 0; i < n; ++i) keys[i] = uint64_t(in.leafOf[i]) << 32 | in.slots[i];
    std::sort(keys.begin(), keys.end());
    bool ok = sort.sorted.size() == n && !sort.runs.empty() && sort.runs.front() == 0 && sort.runs.back() == n;
    for (size_t i = 0; ok && i < n; ++i) ok = uint32_t(keys[i]) == sort.sorted[i];
    size_t leaves = 0;
    for (size_t i = 0; i < n; ++i) leaves += i == 0 || (keys[i] >> 32) != (keys[i - 1] >> 32);
    ok = ok && sort.runs.size() == leaves + 1;
    if (!ok) {
      state.SkipWithError("CandidateSort result differs from the 64-bit key sort");
      return;
    }
    state.counters["leaves"] = double(leaves);
  }
  for (auto _ : state) {
    sort.order.assign(in.slots.begin(), in.slots.end());  // the sort consumes its input
    sort.sort(in.leafOf, scratch);
    benchmark::DoNotOptimize(sort.sorted.data());
  }
  setPairRate(state, n);
}
BENCHMARK(BM_CandidateSort)->Arg(1 << 20)->Arg(1 << 23)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
