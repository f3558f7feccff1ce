#include "core/memory.h"
#include <cstdio>
#include <cstring>
#include <unistd.h>

namespace rayes {
namespace {
uint64_t readStatusKb(const char* key) {
  FILE* f = std::fopen("/proc/self/status", "r");
  if (!f) return 0;
  char line[256];
  uint64_t kb = 0;
  const size_t n = std::strlen(key);
  while (std::fgets(line, sizeof line, f)) {
    if (std::strncmp(line, key, n) == 0) {
      std::sscanf(line + n, " %lu", reinterpret_cast<unsigned long*>(&kb));
      break;
    }
  }
  std::fclose(f);
  return kb * 1024;
}
}  // namespace
uint64_t peakRssBytes() { return readStatusKb("VmHWM:"); }
uint64_t physicalMemoryBytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGESIZE);
  return pages > 0 && size > 0 ? uint64_t(pages) * uint64_t(size) : 0;
}
std::string readableBytes(uint64_t bytes) {
  return bytes >= (uint64_t(1) << 20) ? std::to_string(bytes >> 20) + " MiB" : std::to_string(bytes) + " bytes";
}

}  // namespace rayes
