// The beams' memory account (docs/design.md, "Light beam tracing", Memory and batches): every
// allocation the light phase makes -- the probe's segments, seed chunks, area-light points, the
// tracer's per-generation arrays, split children, segments, the store's bins and the partial
// gathers of batches -- is taken from one budget of --beam-memory bytes *before* it is made,
// and given back when it is freed. take() throws BeamBudgetExceeded when the bytes are not
// there; the caller processes less at once (a smaller chunk of seed triangles, a smaller range
// of beams) or, when even one seed triangle does not fit, refuses with ResourceError naming
// --beam-memory. The diced grids the engine keeps between the corner rays' traces are on the
// account too (keep(): they use what the beams leave free and are freed first when a take()
// needs room). peak() is the most the account ever held: the beams' own high-water mark, what
// the stats report and the tests check against the budget (deterministic, unlike the RSS).
// Freed is not yet returned: the arrays below the allocator's mmap threshold (1 MiB,
// app/allocator_settings.h) -- a generation's corner rays, a chunk's seeds, runs of segments,
// grids of a level up to 7 -- stay in glibc's arenas, resident, once freed; over the batches of
// forest-1 at --beam-resolution 64 they held 19 MB of a 64 MiB budget beside it (bench/
// history/2026-11.md, "lbt's resident set against --beam-memory"). So a take() that follows
// releaseStep() bytes given back first returns the freed pages (releaseFreedMemory): the
// resident set stays within the account plus about one step.
// Not thread-safe: only the serial parts of the light phase take and give.
#pragma once
#include <algorithm>
#include <cstddef>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include "core/memory.h"

namespace rayes {

// What did not fit: `needed` bytes asked for `what` with `available` left.
class BeamBudgetExceeded : public std::runtime_error {
 public:
  BeamBudgetExceeded(size_t needed, size_t available, const std::string& what)
      : std::runtime_error(what + " needs " + std::to_string(needed) + " bytes, " + std::to_string(available) +
                           " left of --beam-memory"),
        needed_(needed), available_(available) {}
  size_t needed() const { return needed_; }
  size_t available() const { return available_; }

 private:
  size_t needed_, available_;
};

class BeamBudget {
 public:
  explicit BeamBudget(size_t limit) : limit_(limit), releaseStep_(std::max<size_t>(size_t(1) << 20, limit / 64)) {}
  size_t limit() const { return limit_; }
  size_t used() const { return used_; }
  size_t left() const { return limit_ - used_; }
  size_t peak() const { return peak_; }
  bool fits(size_t bytes) const { return bytes <= left(); }
  void take(size_t bytes, const char* what) {
    if (given_ >= releaseStep_) {
      releaseFreedMemory();
      given_ = 0;
      ++releases_;
    }
    if (!fits(bytes) && shrinkKept_) keep(shrinkKept_(kept_ - std::min(kept_, bytes - left())));
    if (!fits(bytes)) throw BeamBudgetExceeded(bytes, left(), what);
    used_ += bytes;
    peak_ = std::max(peak_, used_);
  }
  void give(size_t bytes) {
    given_ += std::min(bytes, used_);
    used_ -= std::min(bytes, used_);
  }

  // Kept grids: what the ray engine holds between the corner rays' traces (diced grids), which
  // may use whatever the beams leave free and give it back when the beams need it. keep(n)
  // charges the n bytes held now (at most kept() + left(): the bound the engine was given);
  // `shrink` (target bytes -> bytes held after shrinking) is how take() gets room from them.
  size_t kept() const { return kept_; }
  void keep(size_t bytes) {
    given_ += kept_ - std::min(kept_, bytes);
    used_ = used_ - kept_ + bytes;
    kept_ = bytes;
    peak_ = std::max(peak_, used_);
  }
  void shrinkKeptWith(std::function<size_t(size_t)> shrink) { shrinkKept_ = std::move(shrink); }
  // Bytes given back (kept grids freed included) after which the next take() returns the freed
  // pages to the system: 1/64 of the budget, at least 1 MiB; and how often it did.
  size_t releaseStep() const { return releaseStep_; }
  uint64_t releases() const { return releases_; }

 private:
  size_t limit_, used_ = 0, peak_ = 0, kept_ = 0;
  size_t releaseStep_, given_ = 0;
  uint64_t releases_ = 0;
  std::function<size_t(size_t)> shrinkKept_;
};

// Bytes taken from a budget (none: unaccounted) for as long as it lives; given back at its end.
class BeamCharge {
 public:
  BeamCharge() = default;
  BeamCharge(BeamBudget* budget, size_t bytes, const char* what) : budget_(budget) { add(bytes, what); }
  BeamCharge(BeamCharge&& o) noexcept : budget_(std::exchange(o.budget_, nullptr)), bytes_(std::exchange(o.bytes_, 0)) {}
  BeamCharge& operator=(BeamCharge&& o) noexcept {
    if (this != &o) {
      release();
      budget_ = std::exchange(o.budget_, nullptr);
      bytes_ = std::exchange(o.bytes_, 0);
    }
    return *this;
  }
  BeamCharge(const BeamCharge&) = delete;
  BeamCharge& operator=(const BeamCharge&) = delete;
  ~BeamCharge() { release(); }
  // More bytes on the same account (taken first: throws when they do not fit).
  void add(size_t bytes, const char* what) {
    if (budget_) budget_->take(bytes, what);
    bytes_ += bytes;
  }
  // Fewer bytes (a smaller allocation replaced a larger one).
  void sub(size_t bytes) {
    bytes = std::min(bytes, bytes_);
    if (budget_) budget_->give(bytes);
    bytes_ -= bytes;
  }
  void release() {
    if (budget_) budget_->give(bytes_);
    bytes_ = 0;
  }
  size_t bytes() const { return bytes_; }

 private:
  BeamBudget* budget_ = nullptr;
  size_t bytes_ = 0;
};

}  // namespace rayes
