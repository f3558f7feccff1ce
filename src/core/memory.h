// Process memory readings, and the memory limit that applies to this process.
//
// A farm task runs under a limit that is not the machine's RAM: its cgroup's (Slurm, systemd,
// a container: cgroup v2 memory.max or v1 memory.limit_in_bytes, of the process's cgroup or of
// any ancestor), or an address-space cap (ulimit -v, prlimit --as: RLIMIT_AS). readMemoryLimit()
// takes the smallest of those and of physical memory, with what already counts against each, so
// that budgets and defaults are sized from it and large allocations are checked against it
// before they are made (checkMemoryFits: ResourceError, exit code 3, naming the option).
// Every function here reads files or the kernel afresh and is thread-safe; processMemoryLimit()
// is read once per process.
#pragma once
#include <cstdint>
#include <string>

namespace rayes {
// Peak resident set size of this process in bytes (VmHWM), 0 where it cannot be read.
uint64_t peakRssBytes();
// Current resident set size of this process in bytes (/proc/self/statm), 0 where it cannot be read.
uint64_t currentRssBytes();
// Physical memory of the machine in bytes, 0 where it cannot be read.
uint64_t physicalMemoryBytes();
// Gives the pages of freed heap blocks back to the system (glibc: malloc_trim). glibc keeps
// blocks below its mmap threshold in its arenas after they are freed, resident, and reuses them
// only for later blocks that fit: a budget that frees and allocates in turn (lbt's beams) would
// otherwise see the resident set grow past what it holds. Walks the arenas' free lists: call
// it after a budget has freed megabytes, not per block. Thread-safe; a no-op elsewhere.
void releaseFreedMemory();
// "123 MiB" from 1 MiB up, else "456 bytes": for messages.
std::string readableBytes(uint64_t bytes);

// Where the limits are read from. The defaults are this process's; tests point procCgroup and
// mountInfo at files of their own, and mountPrefix at a folder that holds a fake cgroup tree
// (prepended to the mount points that mountInfo names).
struct MemoryLimitSources {
  std::string procCgroup = "/proc/self/cgroup";
  std::string mountInfo = "/proc/self/mountinfo";
  std::string mountPrefix;
  bool addressSpace = true;  // RLIMIT_AS, against this process's virtual size
  bool physical = true;      // physical memory, against this process's resident size
};

struct MemoryLimit {
  uint64_t bytes = 0;      // the smallest limit that applies (0: none could be read)
  uint64_t available = 0;  // the least any limit has left after what already counts against it
  std::string source;      // the limit that leaves the least, e.g. "RLIMIT_AS (ulimit -v)"
  uint64_t sourceBytes = 0, sourceUsed = 0;  // that limit and what counts against it
  // "5.8 GiB available of a limit of 6 GiB (RLIMIT_AS (ulimit -v))": for messages.
  std::string describe() const;
};

// The limits that apply, smallest first: the cgroup's (every level of the process's memory
// cgroup that exists under its mount, up to the mount's root, which in a container is the
// container's own cgroup; usage there without inactive file pages), RLIMIT_AS (against VmSize),
// physical memory (against this process's RSS; other processes' use is not counted).
MemoryLimit readMemoryLimit(const MemoryLimitSources& sources = {});

// The limit read once, at the first call: what defaults are sized from (fixed for the run).
const MemoryLimit& processMemoryLimit();

// Throws ResourceError(option, ...) unless `bytes` fit what the limit has available now:
// "<what> needs about X, more than the Y available ...; <advice>".
void checkMemoryFits(uint64_t bytes, const std::string& option, const std::string& what, const std::string& advice);
}  // namespace rayes
