// Scratch memory that the sorts of one RayBatch share (RayBatch::sortScratch). Two sorts work on
// a batch and are never live at once: the engine's candidate sort while trace() runs (its radix
// passes' second buffer, then each sorted slot's box entry until trace() returns;
// rays/candidate_sort.h) and the integrator's shading sort while shade() runs (the paths' sort
// items, shading/path_tracer.h). Each takes the memory when it starts and owns it until its
// stage returns; nothing in it outlives the stage that took it. So one buffer serves both, and
// the ray budget counts the larger need once (Renderer: the engine's sortScratchBytesPerRay
// against the integrator's sortScratchBytesPerPath; bench/history/2026-11.md, "session 9").
//
// Ownership: the batch owns the storage; take() grows it to the largest request so far and
// never shrinks it, so a warmed-up render allocates nothing. Not thread-safe: one stage takes
// it, then that stage's threads use the span it got. take() is O(1) unless it grows, which
// allocates without touching the pages. Copying a batch copies no scratch: a new copy has none,
// an assigned-to batch keeps its own (nothing in it outlives the stage that took it).
#pragma once
#include <cstddef>
#include <memory>
#include <new>
#include <span>
#include <type_traits>

namespace rayes {

class SortScratch {
 public:
  SortScratch() = default;
  SortScratch(const SortScratch&) {}
  SortScratch& operator=(const SortScratch&) { return *this; }
  SortScratch(SortScratch&&) noexcept = default;
  SortScratch& operator=(SortScratch&&) noexcept = default;

  // n objects of T over the scratch, their values unspecified; what an earlier take() handed
  // out is dead from now on.
  template <class T>
  std::span<T> take(size_t n) {
    static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T> &&
                  alignof(T) <= __STDCPP_DEFAULT_NEW_ALIGNMENT__);
    if (n == 0) return {};
    if (n * sizeof(T) > bytes_) {
      storage_.reset();
      storage_ = std::unique_ptr<std::byte[]>(new std::byte[n * sizeof(T)]);  // uninitialised
      bytes_ = n * sizeof(T);
    }
    // Starts the lifetime of n T's in the storage (no initialisation, no code for trivial T).
    return {::new (static_cast<void*>(storage_.get())) T[n], n};
  }
  size_t bytes() const { return bytes_; }

 private:
  std::unique_ptr<std::byte[]> storage_;
  size_t bytes_ = 0;
};

}  // namespace rayes
