// OutputSet: the outputs of a run appear together or not at all, and a failure names the
// target with the system's reason.
#include <csignal>
#include <filesystem>
#include <sys/wait.h>
#include <unistd.h>
#include <fstream>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include "app/output_set.h"
#include "core/error.h"
#include "support/temp_folder.h"

namespace rayes {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

// Claims each name in `temp` (as the "stats") and fills it with its own name.
void claimAndFill(OutputSet& out, const testing::TempFolder& temp, std::initializer_list<const char*> names) {
  for (const char* n : names) out.add(temp.path(n), "stats");
  for (const char* n : names) out.writeText(temp.path(n), n);
}

TEST(OutputSet, NothingAppearsBeforeCommitAndEverythingAfter) {
  const testing::TempFolder temp;
  {
    OutputSet out;
    claimAndFill(out, temp, {"a.txt", "sub/b.txt"});
    EXPECT_FALSE(fs::exists(temp.path("a.txt")));
    EXPECT_FALSE(fs::exists(temp.path("sub/b.txt")));
    out.commit();
  }
  EXPECT_EQ(temp.read("a.txt"), "a.txt");
  EXPECT_EQ(temp.read("sub/b.txt"), "sub/b.txt");
  EXPECT_EQ(temp.entries(), (std::vector<std::string>{"a.txt", "sub", "sub/b.txt"}));  // no temporaries
}

TEST(OutputSet, AnUncommittedSetLeavesNothingNotEvenItsFolders) {
  const testing::TempFolder temp;
  {
    OutputSet out;
    claimAndFill(out, temp, {"x/y/a.txt"});
  }  // e.g. a later write threw
  EXPECT_TRUE(temp.entries().empty());
}

TEST(OutputSet, AFailedRenameRemovesTheOutputsAlreadyRenamed) {
  const testing::TempFolder temp;
  OutputSet out;
  claimAndFill(out, temp, {"a.txt", "b.txt"});
  fs::create_directories(temp.path("b.txt/inside"));  // appears after the check in add()
  try {
    out.commit();
    ADD_FAILURE() << "commit succeeded";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), temp.path("b.txt"));
    EXPECT_THAT(e.what(), HasSubstr("cannot write the stats: Is a directory"));  // errno kept, not "Success"
  }
  EXPECT_EQ(temp.entries(), (std::vector<std::string>{"b.txt", "b.txt/inside"}));
}

TEST(OutputSet, UnwritablePlacesFailAtAddWithTheReason) {
  const testing::TempFolder temp;
  temp.write("file", "x");
  fs::create_directories(temp.path("dir"));
  OutputSet out;
  EXPECT_THROW(
      try { out.add(temp.path("dir"), "image"); } catch (const InputError& e) {
        EXPECT_THAT(e.message(), HasSubstr("dir: cannot write the image: is a directory"));
        throw;
      },
      InputError);
  EXPECT_THROW(
      try { out.add(temp.path("file/o.exr"), "image"); } catch (const InputError& e) {
        EXPECT_THAT(e.message(), HasSubstr("cannot create the folder for the image: "));
        EXPECT_THAT(e.message(), ::testing::Not(HasSubstr("Success")));
        throw;
      },
      InputError);
  out.add(temp.path("o.exr"), "image");
  EXPECT_THROW(out.add(temp.path("./o.exr"), "stats"), InputError);  // the same file twice
}

// A run stopped by a signal between claiming and committing leaves no temporary (checked in a
// child process, which dies of the signal).
TEST(OutputSet, ASignalRemovesTheTemporaries) {
  const testing::TempFolder temp;
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    OutputSet out;
    out.add(temp.path("a.exr"), "image");
    out.add(temp.path("a.png"), "preview");
    std::raise(SIGTERM);
    ::_exit(0);  // not reached
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << status;
  EXPECT_TRUE(temp.entries().empty());
}

}  // namespace
}  // namespace rayes
