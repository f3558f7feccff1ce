// Process memory readings for the stats (peak resident set size) and the machine's size.
#pragma once
#include <cstdint>

namespace rayes {
// Peak resident set size of this process in bytes (VmHWM), 0 where it cannot be read.
uint64_t peakRssBytes();
// Physical memory of the machine in bytes, 0 where it cannot be read.
uint64_t physicalMemoryBytes();
}  // namespace rayes
