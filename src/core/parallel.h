// Parallel helpers over oneTBB. Every parallel loop in the project goes through oneTBB;
// ThreadLimit fixes the worker count for a render (tbb::global_control), and thread-local
// scratch (dice buffers) lives in tbb::enumerable_thread_specific owned by the stage using it.
#pragma once
#include <memory>
#include <tbb/global_control.h>
#include <tbb/info.h>

namespace rayes {

class ThreadLimit {
 public:
  // threads <= 0 means "all cores".
  explicit ThreadLimit(int threads) {
    if (threads > 0)
      control_ = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                       static_cast<size_t>(threads));
  }
  static int active() {
    return static_cast<int>(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
  }
 private:
  std::unique_ptr<tbb::global_control> control_;
};

}  // namespace rayes
