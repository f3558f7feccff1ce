// Cheap RAII time accumulators (the MoonRay habit): a ScopedTimer adds its lifetime to a
// TimeAccumulator. Accumulators are atomic, so per-thread stages (dice, bottom) sum over
// threads while wall-clock stages are timed on the calling thread only.
#pragma once
#include <atomic>
#include <chrono>
#include <cstdint>

namespace rayes {

using Clock = std::chrono::steady_clock;

class TimeAccumulator {
 public:
  void add(Clock::duration d) { ns_.fetch_add(std::chrono::duration_cast<std::chrono::nanoseconds>(d).count(), std::memory_order_relaxed); }
  double seconds() const { return ns_.load(std::memory_order_relaxed) * 1e-9; }
  void reset() { ns_.store(0); }
 private:
  std::atomic<int64_t> ns_{0};
};

class ScopedTimer {
 public:
  explicit ScopedTimer(TimeAccumulator& acc) : acc_(acc), start_(Clock::now()) {}
  ~ScopedTimer() { acc_.add(Clock::now() - start_); }
  ScopedTimer(const ScopedTimer&) = delete;
  ScopedTimer& operator=(const ScopedTimer&) = delete;
 private:
  TimeAccumulator& acc_;
  Clock::time_point start_;
};

inline double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace rayes
