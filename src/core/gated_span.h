// Arrays read in place from memory that another owner keeps in blocks and may release: a
// compiled scene's mapping (geometry/compiled_file.h), whose blocks must be verified on their
// first touch and counted against --scene-memory before they are read. A GatedSpan<T> reads
// element i through its BlockGate: one relaxed byte load on the fast path (the block is
// verified, counted resident and marked used since the owner's clock last passed), a virtual
// call otherwise (BlockGate::admit). Without a gate it is a plain span (the JSON route's
// tables, which own their memory), at the cost of a predictable branch per read.
//
// What the gate does not promise: a block released by the owner between a reader's fast-path
// check and its load is mapped again by the kernel without being counted (there is no pin on
// this path). The data are read-only and never change, so only the count can be off, never the
// values read; the owner releases such a block again when its clock next passes it, and before
// it reports (geometry/compiled_file.cpp, kMaybeStray), so strays do not accumulate. (A
// re-check of the ready byte after the read, re-admitting the block, would close the window
// itself: not done yet.) Thread-safe: any thread may read any element.
#pragma once
#include <atomic>
#include <cstddef>
#include <cstdint>

namespace rayes {

class BlockGate {
 public:
  static constexpr unsigned kBlockShift = 16;  // 64 KiB blocks (compiled::kBlockBytes)

  // Makes byte `offset` of the gated range readable. Throws (InputError) when its block is
  // corrupt.
  void touch(uint64_t offset) const {
    const uint64_t block = offset >> kBlockShift;
    if (ready_[block].load(std::memory_order_relaxed) == 0) admit(block);
  }

 protected:
  explicit BlockGate(const std::atomic<uint8_t>* ready) : ready_(ready) {}
  ~BlockGate() = default;
  // The slow path: verify the block if it never was, count it resident (which may release
  // others), mark it used and set its ready byte.
  virtual void admit(uint64_t block) const = 0;

 private:
  const std::atomic<uint8_t>* ready_;  // per block of the range: nonzero when nothing is to do
};

template <class T>
class GatedSpan {
 public:
  GatedSpan() = default;
  // `offset`: where data[0] lies in the gate's range, in bytes.
  GatedSpan(const T* data, size_t size, const BlockGate* gate = nullptr, uint64_t offset = 0)
      : data_(data), size_(size), gate_(gate), offset_(offset) {}

  size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  bool gated() const { return gate_ != nullptr; }
  const T* data() const { return data_; }  // ungated: for prefetches, and what the owner stores

  // Element i by value (the block may be released once the read is done).
  T operator[](size_t i) const {
    touch(i);
    return data_[i];
  }
  // A reference valid until the owner releases the block: for hot loops that read several
  // fields of one element right after this call (the top level's nodes).
  const T& at(size_t i) const {
    touch(i);
    return data_[i];
  }

 private:
  void touch(size_t i) const {
    if (!gate_) return;
    const uint64_t first = offset_ + uint64_t(i) * sizeof(T);
    gate_->touch(first);
    // An element that does not divide the block may straddle two of them.
    if ((first >> BlockGate::kBlockShift) != ((first + sizeof(T) - 1) >> BlockGate::kBlockShift)) gate_->touch(first + sizeof(T) - 1);
  }

  const T* data_ = nullptr;
  size_t size_ = 0;
  const BlockGate* gate_ = nullptr;
  uint64_t offset_ = 0;
};

}  // namespace rayes
