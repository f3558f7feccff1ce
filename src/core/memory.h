// Process memory readings for the stats (peak resident set size) and the machine's size.
#pragma once
#include <cstdint>
#include <string>

namespace rayes {
// Peak resident set size of this process in bytes (VmHWM), 0 where it cannot be read.
uint64_t peakRssBytes();
// Physical memory of the machine in bytes, 0 where it cannot be read.
uint64_t physicalMemoryBytes();
// "123 MiB" from 1 MiB up, else "456 bytes": for messages.
std::string readableBytes(uint64_t bytes);
}  // namespace rayes
