#include "core/memory.h"
#include <sys/resource.h>
#include <cstdlib>  // defines __GLIBC__ on glibc
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <unistd.h>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>
#include "core/error.h"

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

// Field `k` (0: total program size, 1: resident) of /proc/self/statm, in bytes.
uint64_t statmBytes(int k) {
  std::ifstream in("/proc/self/statm");
  uint64_t v[2] = {0, 0};
  if (!(in >> v[0] >> v[1])) return 0;
  const long page = sysconf(_SC_PAGESIZE);
  return page > 0 ? v[k] * uint64_t(page) : 0;
}

// A whole file's first token as a number; false when absent or not a number ("max").
bool readNumber(const std::filesystem::path& p, uint64_t& out) {
  std::ifstream in(p);
  std::string s;
  if (!(in >> s) || s.empty() || s.find_first_not_of("0123456789") != std::string::npos) return false;
  try {
    out = std::stoull(s);
  } catch (const std::exception&) {
    return false;
  }
  return true;
}

// `key value` from a memory.stat; 0 when absent.
uint64_t statValue(const std::filesystem::path& p, const std::string& key) {
  std::ifstream in(p);
  std::string k;
  uint64_t v = 0;
  while (in >> k >> v)
    if (k == key) return v;
  return 0;
}

struct Mount {
  std::string root, point;
  bool found = false;
};

// The cgroup v1 mount holding the memory controller, and the cgroup2 mount (/proc/self/mountinfo:
// "id parent dev root point options [tags] - type source superoptions").
void findMounts(const MemoryLimitSources& s, Mount& v1, Mount& v2) {
  std::ifstream in(s.mountInfo);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::vector<std::string> f;
    for (std::string w; ls >> w;) f.push_back(w);
    size_t dash = 0;
    while (dash < f.size() && f[dash] != "-") ++dash;
    if (f.size() < 5 || dash + 1 >= f.size()) continue;
    const std::string& type = f[dash + 1];
    const std::string super = dash + 3 < f.size() ? "," + f[dash + 3] + "," : "";
    Mount m{f[3], s.mountPrefix + f[4], true};
    if (type == "cgroup2" && !v2.found) v2 = m;
    if (type == "cgroup" && super.find(",memory,") != std::string::npos && !v1.found) v1 = m;
  }
}

// The process's path in the v1 memory hierarchy and in the v2 hierarchy (/proc/self/cgroup:
// "id:controllers:path"; v2 is "0::path").
void findCgroupPaths(const MemoryLimitSources& s, std::string& v1, std::string& v2, bool& hasV1, bool& hasV2) {
  std::ifstream in(s.procCgroup);
  std::string line;
  while (std::getline(in, line)) {
    const size_t a = line.find(':'), b = a == std::string::npos ? a : line.find(':', a + 1);
    if (b == std::string::npos) continue;
    const std::string controllers = "," + line.substr(a + 1, b - a - 1) + ",", path = line.substr(b + 1);
    if (line.substr(0, a) == "0" && controllers == ",,") {
      v2 = path;
      hasV2 = true;
    } else if (controllers.find(",memory,") != std::string::npos) {
      v1 = path;
      hasV1 = true;
    }
  }
}

struct Limit {
  uint64_t bytes = 0, used = 0;
  std::string source;
  uint64_t left() const { return bytes > used ? bytes - used : 0; }
};

// Limits at or above 2^60 are "unlimited" (v1 writes 2^63 - 4096 for none).
constexpr uint64_t kUnlimited = uint64_t(1) << 60;

// The tightest limit of the cgroup levels from the process's own up to the mount's root. The
// process's path is made relative to the mount's root; where it does not lie under it (a
// container that sees its own cgroup as the root) the mount's root itself is the process's
// cgroup. Levels that do not exist (a path from outside a container) are skipped.
bool cgroupLimit(const Mount& mount, const std::string& path, bool v2, Limit& out) {
  namespace fs = std::filesystem;
  std::string rel;
  if (mount.root == "/") rel = path;
  else if (path == mount.root || path.rfind(mount.root + "/", 0) == 0) rel = path.substr(mount.root.size());
  const fs::path top = fs::path(mount.point);
  const fs::path below = fs::path(rel).relative_path();
  fs::path dir = below.empty() ? top : top / below;
  bool found = false;
  for (;;) {
    uint64_t limit = 0;
    const bool has = v2 ? readNumber(dir / "memory.max", limit) : readNumber(dir / "memory.limit_in_bytes", limit);
    if (has && limit < kUnlimited && (!found || limit < out.bytes)) {
      uint64_t usage = 0;
      readNumber(dir / (v2 ? "memory.current" : "memory.usage_in_bytes"), usage);
      const uint64_t inactive = statValue(dir / "memory.stat", v2 ? "inactive_file" : "total_inactive_file");
      out.bytes = limit;
      out.used = usage > inactive ? usage - inactive : 0;
      out.source = std::string(v2 ? "cgroup memory.max of " : "cgroup memory.limit_in_bytes of ") + dir.string();
      found = true;
    }
    if (dir == top || !dir.has_relative_path() || dir.string().size() <= top.string().size()) break;
    dir = dir.parent_path();
  }
  return found;
}

std::string gib(uint64_t bytes) {
  char s[64];
  if (bytes >= (uint64_t(1) << 30)) std::snprintf(s, sizeof s, "%.1f GiB", double(bytes) / double(uint64_t(1) << 30));
  else return readableBytes(bytes);
  return s;
}

}  // namespace

uint64_t peakRssBytes() { return readStatusKb("VmHWM:"); }
uint64_t currentRssBytes() { return statmBytes(1); }
void releaseFreedMemory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}
uint64_t physicalMemoryBytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGESIZE);
  return pages > 0 && size > 0 ? uint64_t(pages) * uint64_t(size) : 0;
}
std::string readableBytes(uint64_t bytes) {
  return bytes >= (uint64_t(1) << 20) ? std::to_string(bytes >> 20) + " MiB" : std::to_string(bytes) + " bytes";
}

MemoryLimit readMemoryLimit(const MemoryLimitSources& s) {
  std::vector<Limit> limits;
  Mount m1, m2;
  findMounts(s, m1, m2);
  std::string p1, p2;
  bool has1 = false, has2 = false;
  findCgroupPaths(s, p1, p2, has1, has2);
  Limit l;
  if (has1 && m1.found && cgroupLimit(m1, p1, false, l)) limits.push_back(l);
  l = {};
  if (has2 && m2.found && cgroupLimit(m2, p2, true, l)) limits.push_back(l);
  if (s.addressSpace) {
    rlimit r{};
    if (getrlimit(RLIMIT_AS, &r) == 0 && r.rlim_cur != RLIM_INFINITY && uint64_t(r.rlim_cur) < kUnlimited)
      limits.push_back({uint64_t(r.rlim_cur), statmBytes(0), "RLIMIT_AS (ulimit -v)"});
  }
  if (s.physical) {
    if (const uint64_t phys = physicalMemoryBytes()) limits.push_back({phys, currentRssBytes(), "physical memory"});
  }
  MemoryLimit out;
  for (size_t i = 0; i < limits.size(); ++i) {
    const Limit& x = limits[i];
    out.bytes = i == 0 ? x.bytes : std::min(out.bytes, x.bytes);
    if (i == 0 || x.left() < out.available) {
      out.available = x.left();
      out.source = x.source;
      out.sourceBytes = x.bytes;
      out.sourceUsed = x.used;
    }
  }
  return out;
}

const MemoryLimit& processMemoryLimit() {
  static const MemoryLimit limit = readMemoryLimit();
  return limit;
}

std::string MemoryLimit::describe() const {
  if (sourceBytes == 0) return "no memory limit could be read";
  return gib(available) + " available (" + source + ": " + gib(sourceBytes) + ", " + gib(sourceUsed) + " in use)";
}

void checkMemoryFits(uint64_t bytes, const std::string& option, const std::string& what, const std::string& advice) {
  const MemoryLimit limit = readMemoryLimit();
  if (limit.sourceBytes == 0 || bytes <= limit.available) return;
  throw ResourceError(option, what + " needs about " + gib(bytes) + ", more than the " + limit.describe() + "; " +
                                  advice);
}

}  // namespace rayes
