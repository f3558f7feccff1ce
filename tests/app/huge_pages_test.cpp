// restartWithHugePages (app/huge_pages.h): the process starts itself again once, with glibc's
// huge-page tunable added to whatever GLIBC_TUNABLES held, and not at all when the tunable is
// already named or RAYES_HUGE_PAGES=0. The exec is checked in a forked child that restarts this
// test binary into the Child test below, which writes the environment it got to a file.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>
#include <cstdlib>
#include <fstream>
#include <string>
#include "app/huge_pages.h"

namespace rayes {
namespace {

std::string env(const char* name) {
  const char* v = std::getenv(name);
  return v ? v : "(unset)";
}

// Run only as the restarted child: records GLIBC_TUNABLES for the parent.
TEST(HugePages, Child) {
  const char* out = std::getenv("RAYES_HUGE_PAGES_TEST_OUT");
  if (!out) GTEST_SKIP() << "only run by HugePages.RestartsOnceWithTheTunableAdded";
  std::ofstream(out) << env("GLIBC_TUNABLES");
}

TEST(HugePages, RestartsOnceWithTheTunableAdded) {
  const std::string out = testing::TempDir() + "huge_pages_child.txt";
  std::remove(out.c_str());
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    setenv("RAYES_HUGE_PAGES_TEST_OUT", out.c_str(), 1);
    setenv("GLIBC_TUNABLES", "glibc.malloc.check=0", 1);
    unsetenv("RAYES_HUGE_PAGES");
    std::string filter = "--gtest_filter=HugePages.Child";
    char name[] = "test_app";
    char* argv[] = {name, filter.data(), nullptr};
    restartWithHugePages(argv);
    _exit(3);  // reached only if it did not exec
  }
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  ASSERT_EQ(WEXITSTATUS(status), 0) << "the child did not restart into HugePages.Child (3: no exec)";
  std::ifstream in(out);
  std::string got;
  std::getline(in, got);
  EXPECT_EQ(got, "glibc.malloc.check=0:glibc.malloc.hugetlb=1");
}

TEST(HugePages, NoRestartWhenTheTunableIsNamedOrTurnedOff) {
  for (const char* off : {"tunable", "switch"}) {
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      if (std::string(off) == "tunable") {
        setenv("GLIBC_TUNABLES", "glibc.malloc.hugetlb=0", 1);  // the user's choice stands
        unsetenv("RAYES_HUGE_PAGES");
      } else {
        unsetenv("GLIBC_TUNABLES");
        setenv("RAYES_HUGE_PAGES", "0", 1);
      }
      std::string filter = "--gtest_filter=HugePages.Child";
      char name[] = "test_app";
      char* argv[] = {name, filter.data(), nullptr};
      restartWithHugePages(argv);
      // Returned without exec, and the environment is as it was.
      const bool same = std::string(off) == "tunable" ? env("GLIBC_TUNABLES") == "glibc.malloc.hugetlb=0"
                                                      : env("GLIBC_TUNABLES") == "(unset)";
      _exit(same ? 7 : 8);
    }
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 7) << off << ": 0 means it restarted, 8 that it changed the environment";
  }
}

}  // namespace
}  // namespace rayes
