// Queries that belong to top-level leaves and are answered in the ray engine's per-leaf stage,
// next to that leaf's rays (docs/architecture.md, "Data flow of one generation"): the caustic
// gathers of light beams, whose segments are binned per leaf, are the one kind today. Like
// RayBatch, the type lives in core so shading can post queries and src/rays can run them without
// knowing each other.
//
// Contract: slot q holds one query, on leaf[q] (kNoLeaf: empty). The poster gives each slot's
// meaning to its runner (the path tracer: slot k is path k's gather, one per path per
// generation, so the slots are bounded by the paths of a batch). During trace() the engine
// passes every filled slot exactly once to runner->run(leaf, ids), ids being slots of that leaf
// in increasing order, whether or not any ray visits that leaf: one call per leaf, or, for a
// leaf with many queries, consecutive chunks of its slots (so one large receiver does not
// serialise the stage on one thread). Calls may be concurrent, within a leaf too. A run writes
// only its own slots' results (held by the runner), so results do not depend on thread count,
// chunking or the order leaves are processed in.
// The engine never changes `leaf`: the poster reads the results after trace() and empties the
// slots.
#pragma once
#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>
#include "core/ray_batch.h"

namespace rayes {

class LeafQueryRunner {
 public:
  virtual ~LeafQueryRunner() = default;
  virtual void run(uint32_t leaf, std::span<const uint32_t> ids) = 0;
};

struct LeafQueries {
  std::vector<uint32_t> leaf;         // per slot: the leaf its query is on, or kNoLeaf
  LeafQueryRunner* runner = nullptr;  // not owned; null: no queries are run

  bool pending() const {
    return runner && std::any_of(leaf.begin(), leaf.end(), [](uint32_t l) { return l != kNoLeaf; });
  }
  // A slot and, when filled, what the engine spends on sorting it by leaf: its place in the
  // CandidateSort's order and its scratch (rays/leaf_query_runs.h).
  static constexpr size_t bytesPerSlot() { return 3 * sizeof(uint32_t); }
};

}  // namespace rayes
