// Progress on stderr: a bar with the elapsed time and an ETA when stderr is a terminal, plain
// lines (one per pass) otherwise, so logs of farm jobs stay readable.
#pragma once
#include <cstdint>
#include "core/timer.h"

namespace rayes {

class ProgressReporter {
 public:
  ProgressReporter(bool enabled, int totalSpp);
  void update(uint64_t done, uint64_t total, int samplesFinished);
  void finish();

 private:
  bool enabled_, terminal_;
  int totalSpp_, lastSpp_ = -1;
  Clock::time_point start_;
  double lastDraw_ = -1;
};

}  // namespace rayes
