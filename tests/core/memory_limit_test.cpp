// readMemoryLimit (core/memory.h): the limit a farm node's task runs under is the smallest of its
// cgroup's (v1 memory.limit_in_bytes or v2 memory.max, at any level from the process's cgroup
// up to the mount's root), RLIMIT_AS and physical memory, each less what already counts
// against it. The cgroup cases read fake trees: a mountinfo and a /proc/self/cgroup of the
// test's own, whose mount points lie under a temporary folder.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <gtest/gtest.h>
#include "core/error.h"
#include "core/memory.h"
#include "support/temp_folder.h"

namespace rayes {
namespace {

constexpr uint64_t kGiB = uint64_t(1) << 30;
constexpr const char* kV1Unlimited = "9223372036854771712";

// A fake cgroup v1 memory hierarchy mounted at <folder>/sys/fs/cgroup/memory (root `mountRoot`
// inside the hierarchy), and the process's line in /proc/self/cgroup.
struct FakeCgroups {
  testing::TempFolder folder;
  MemoryLimitSources sources() const {
    MemoryLimitSources s;
    s.procCgroup = folder.path("proc-cgroup");
    s.mountInfo = folder.path("mountinfo");
    s.mountPrefix = folder.dir().string();
    s.addressSpace = false;
    s.physical = false;
    return s;
  }
  void v1(const std::string& processPath, const std::string& mountRoot = "/") {
    folder.write("proc-cgroup", "12:pids:/x\n4:memory:" + processPath + "\n1:name=systemd:/\n0::/\n");
    folder.write("mountinfo", "31 23 0:28 / /sys/fs/cgroup rw,relatime - tmpfs tmpfs rw,mode=755\n"
                              "35 31 0:32 " + mountRoot + " /sys/fs/cgroup/memory rw,relatime - cgroup cgroup rw,memory\n"
                              "41 31 0:38 / /sys/fs/cgroup/unified rw,relatime - cgroup2 cgroup2 rw\n");
  }
  void v2(const std::string& processPath) {
    folder.write("proc-cgroup", "0::" + processPath + "\n");
    folder.write("mountinfo", "31 23 0:28 / /sys/fs/cgroup rw,nosuid shared:4 - cgroup2 cgroup2 rw,nsdelegate\n");
  }
  // Files of the cgroup at `dir` (relative to the mount point).
  void v1Level(const std::string& dir, const std::string& limit, uint64_t usage = 0, uint64_t inactive = 0) {
    const std::string d = "sys/fs/cgroup/memory/" + dir + "/";
    folder.write(d + "memory.limit_in_bytes", limit + "\n");
    folder.write(d + "memory.usage_in_bytes", std::to_string(usage) + "\n");
    folder.write(d + "memory.stat", "cache 5\ntotal_inactive_file " + std::to_string(inactive) + "\n");
  }
  void v2Level(const std::string& dir, const std::string& max, uint64_t current = 0, uint64_t inactive = 0) {
    const std::string d = "sys/fs/cgroup/" + dir + "/";
    folder.write(d + "memory.max", max + "\n");
    folder.write(d + "memory.current", std::to_string(current) + "\n");
    folder.write(d + "memory.stat", "anon 1\ninactive_file " + std::to_string(inactive) + "\n");
  }
};

TEST(MemoryLimit, CgroupV1TheSmallestLimitOfTheProcessCgroupAndItsAncestors) {
  FakeCgroups f;
  f.v1("/slurm/job7/step0");
  f.v1Level("", kV1Unlimited);
  f.v1Level("slurm", kV1Unlimited);
  f.v1Level("slurm/job7", std::to_string(4 * kGiB), kGiB / 2);
  f.v1Level("slurm/job7/step0", std::to_string(8 * kGiB));
  const MemoryLimit m = readMemoryLimit(f.sources());
  EXPECT_EQ(m.bytes, 4 * kGiB);
  EXPECT_EQ(m.available, 4 * kGiB - kGiB / 2);
  EXPECT_NE(m.source.find("memory.limit_in_bytes"), std::string::npos) << m.source;
  EXPECT_NE(m.source.find("slurm/job7"), std::string::npos) << m.source;
}

TEST(MemoryLimit, CgroupV1UsageLessInactiveFilePagesCountsAsUsed) {
  FakeCgroups f;
  f.v1("/job");
  f.v1Level("", kV1Unlimited);
  f.v1Level("job", std::to_string(4 * kGiB), 3 * kGiB, kGiB);  // 1 GiB of it is reclaimable page cache
  const MemoryLimit m = readMemoryLimit(f.sources());
  EXPECT_EQ(m.bytes, 4 * kGiB);
  EXPECT_EQ(m.available, 2 * kGiB);
  EXPECT_EQ(m.sourceUsed, 2 * kGiB);
}

TEST(MemoryLimit, CgroupV1UnlimitedEverywhereIsNoLimit) {
  FakeCgroups f;
  f.v1("/a");
  f.v1Level("", kV1Unlimited);
  f.v1Level("a", kV1Unlimited);
  const MemoryLimit m = readMemoryLimit(f.sources());
  EXPECT_EQ(m.bytes, 0u);
  EXPECT_EQ(m.sourceBytes, 0u);
}

// In a container /proc/self/cgroup may name a path of the host's hierarchy that does not exist
// under the container's mount: the levels that exist (up to the mount's root, the container's
// own cgroup) are read.
TEST(MemoryLimit, CgroupV1PathMissingUnderTheMountReadsTheLevelsThatExist) {
  FakeCgroups f;
  f.v1("/docker/0123abcd/inner");
  f.v1Level("", std::to_string(2 * kGiB));
  const MemoryLimit m = readMemoryLimit(f.sources());
  EXPECT_EQ(m.bytes, 2 * kGiB);
}

// A mount of a sub-hierarchy (mountinfo's root field /docker/0123abcd): the process's path is
// made relative to it.
TEST(MemoryLimit, CgroupV1MountOfASubHierarchy) {
  FakeCgroups f;
  f.v1("/docker/0123abcd/task", "/docker/0123abcd");
  f.v1Level("", std::to_string(3 * kGiB));
  f.v1Level("task", std::to_string(5 * kGiB / 2));
  EXPECT_EQ(readMemoryLimit(f.sources()).bytes, 5 * kGiB / 2);
}

TEST(MemoryLimit, CgroupV2MemoryMaxOfAnAncestorWhenTheOwnIsMax) {
  FakeCgroups f;
  f.v2("/system.slice/slurmstepd.scope/job_3/step_0");
  f.v2Level("system.slice/slurmstepd.scope/job_3", std::to_string(6 * kGiB), 2 * kGiB, kGiB / 2);
  f.v2Level("system.slice/slurmstepd.scope/job_3/step_0", "max");
  const MemoryLimit m = readMemoryLimit(f.sources());
  EXPECT_EQ(m.bytes, 6 * kGiB);
  EXPECT_EQ(m.available, 6 * kGiB - (2 * kGiB - kGiB / 2));
  EXPECT_NE(m.source.find("memory.max"), std::string::npos) << m.source;
}

TEST(MemoryLimit, NoCgroupFilesAndNothingElseIsNoLimit) {
  FakeCgroups f;
  f.v2("/");
  EXPECT_EQ(readMemoryLimit(f.sources()).bytes, 0u);
}

TEST(MemoryLimit, PhysicalMemoryIsTheLimitWhenNothingElseApplies) {
  FakeCgroups f;
  f.v2("/");
  MemoryLimitSources s = f.sources();
  s.physical = true;
  const MemoryLimit m = readMemoryLimit(s);
  ASSERT_GT(physicalMemoryBytes(), 0u) << "cannot read this machine's memory";
  EXPECT_EQ(m.bytes, physicalMemoryBytes());
  EXPECT_EQ(m.source, "physical memory");
  EXPECT_LT(m.available, m.bytes);  // this process's resident pages count
  EXPECT_GT(currentRssBytes(), 0u);
}

// RLIMIT_AS (ulimit -v, prlimit --as), set in a child process: the limit less the child's
// address space, and the smallest of it and a larger cgroup limit.
TEST(MemoryLimit, AddressSpaceLimitAgainstTheVirtualSize) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer reserves terabytes of address space: RLIMIT_AS cannot be set under it";
#else
  FakeCgroups f;
  f.v1("/job");
  f.v1Level("", kV1Unlimited);
  f.v1Level("job", std::to_string(16 * kGiB));
  MemoryLimitSources s = f.sources();
  s.addressSpace = true;
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    const rlimit r{6 * kGiB, 6 * kGiB};
    if (setrlimit(RLIMIT_AS, &r) != 0) _exit(10);
    const MemoryLimit m = readMemoryLimit(s);
    if (m.bytes != 6 * kGiB) _exit(11);
    if (m.source != "RLIMIT_AS (ulimit -v)") _exit(12);
    if (!(m.available < m.bytes && m.available > 0)) _exit(13);
    _exit(0);
  }
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "10: setrlimit failed, 11: wrong limit, 12: wrong source, 13: nothing counted";
#endif
}

TEST(MemoryLimit, CheckMemoryFitsRefusesWithAResourceErrorNamingTheOption) {
  try {
    checkMemoryFits(uint64_t(1) << 62, "--res", "the film", "lower --res");
    FAIL() << "2^62 bytes fit";
  } catch (const ResourceError& e) {
    EXPECT_EQ(e.file(), "--res");
    EXPECT_NE(std::string(e.what()).find("the film needs about"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("lower --res"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(checkMemoryFits(1 << 20, "--res", "a small film", "lower --res"));
}

}  // namespace
}  // namespace rayes
