// Process memory readings for the stats (peak and current resident set size).
#pragma once
#include <cstdint>

namespace rayes {
// Peak resident set size of this process in bytes (VmHWM), 0 where it cannot be read.
uint64_t peakRssBytes();
// Current resident set size in bytes (VmRSS), 0 where it cannot be read.
uint64_t currentRssBytes();
}  // namespace rayes
