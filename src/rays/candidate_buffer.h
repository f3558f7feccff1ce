// The (ray, leaf) candidate buffer of one iteration (thesis Fig. 6.5), structure of arrays.
// Active ray a owns slots [a*N, a*N + count[a]); each slot is written by exactly one task
// (the task of its leaf), so the bottom level needs no locks, and the per-ray reduction reads
// a ray's own slots in slot order, so the result does not depend on processing order.
// Capacity is fixed at construction (the candidate part of --ray-memory): 32 bytes per slot.
#pragma once
#include <cstdint>
#include <vector>

namespace rayes {

struct CandidateBuffer {
  // Written by the top-level traversal.
  std::vector<uint32_t> leaf;
  std::vector<float> entry;
  // Written by the leaf's bottom-level task.
  std::vector<float> t, u, v;        // t = +inf: no hit on this leaf
  std::vector<uint32_t> quadLevel;   // quad | level << 24
  std::vector<uint32_t> ng, ns;      // octahedral unit normals

  explicit CandidateBuffer(size_t capacity) { resize(capacity); }
  size_t capacity() const { return leaf.size(); }
  static constexpr size_t bytesPerSlot() { return 8 * sizeof(uint32_t); }

 private:
  void resize(size_t n) {
    leaf.resize(n); entry.resize(n); t.resize(n); u.resize(n); v.resize(n); quadLevel.resize(n);
    ng.resize(n); ns.resize(n);
  }
};

}  // namespace rayes
