// Interrupted renders, run as separate processes of the built `rayes` (skipped when it has not
// been built): a render killed with SIGKILL at seeded random moments and resumed each time from
// its checkpoint gives the uninterrupted render's pixels; SIGTERM stops a render that has a
// checkpoint with exit code 4 and it resumes to the same image, while one without a checkpoint
// dies of the signal and leaves no file or folder it made; a checkpoint that cannot be written
// (the file size limit, or a full tmpfs where one can be mounted) leaves the previous one valid.
// The kill moments are in time, so where each lands varies with the machine's load; what is
// checked holds wherever they land.
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <thread>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include "support/exr_image.h"
#include "support/temp_folder.h"

namespace rayes::testing {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

const std::string kRayes = std::string(RAYES_BINARY_DIR) + "/bin/rayes";
const std::string kTeapot = std::string(RAYES_SOURCE_DIR) + "/scenes/teapot.json";

struct Spawned {
  pid_t pid = -1;
  // Waits; the exit code, or 128 + the signal it died of.
  int wait() {
    int status = 0;
    if (::waitpid(pid, &status, 0) != pid) return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : WIFSIGNALED(status) ? 128 + WTERMSIG(status) : -1;
  }
};

// Starts rayes with `args`, its stderr into `errFile`; with fsizeLimit > 0, under that
// RLIMIT_FSIZE and with SIGXFSZ ignored (so a write past it fails with EFBIG).
Spawned spawnRayes(const std::vector<std::string>& args, const std::string& errFile, rlim_t fsizeLimit = 0) {
  std::vector<std::string> all = {kRayes};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int fd = ::open(errFile.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) ::dup2(fd, 2);
    if (fsizeLimit > 0) {
      std::signal(SIGXFSZ, SIG_IGN);
      const rlimit lim{fsizeLimit, fsizeLimit};
      ::setrlimit(RLIMIT_FSIZE, &lim);
    }
    ::execv(kRayes.c_str(), argv.data());
    ::_exit(127);
  }
  return {pid};
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

class Interrupted : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(kRayes)) GTEST_SKIP() << kRayes << " is not built";
  }
  std::string path(const std::string& name) const { return temp_.path(name); }
  // The render every test interrupts: long enough (a second or more) to be stopped in the middle.
  std::vector<std::string> renderArgs(std::vector<std::string> more) const {
    std::vector<std::string> args = {"render", kTeapot, "-q", "--res", "96x72", "--spp", "32", "--threads", "2"};
    args.insert(args.end(), more.begin(), more.end());
    return args;
  }
  int run(std::vector<std::string> more, rlim_t fsizeLimit = 0) {
    return spawnRayes(renderArgs(std::move(more)), path("err.txt"), fsizeLimit).wait();
  }
  std::string err() const { return readFile(path("err.txt")); }
  // Waits (at most 60 s) until `p` exists.
  static bool waitFor(const std::string& p) {
    for (int i = 0; i < 6000 && !fs::exists(p); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    return fs::exists(p);
  }
  // The inode of `p` (0: none): a checkpoint replaced by a rename gets a new one.
  static ino_t inodeOf(const std::string& p) {
    struct stat st;
    return ::stat(p.c_str(), &st) == 0 ? st.st_ino : 0;
  }
  // Waits (at most 60 s) until `p` is a new file (another inode than `before`) or `pid` ended;
  // returns whether it is.
  static bool waitForNew(const std::string& p, ino_t before, pid_t pid) {
    for (int i = 0; i < 6000; ++i) {
      const ino_t now = inodeOf(p);
      if (now != 0 && now != before) return true;
      siginfo_t info{};
      if (::waitid(P_PID, id_t(pid), &info, WEXITED | WNOHANG | WNOWAIT) == 0 && info.si_pid == pid) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return false;
  }
  TempFolder temp_;
};

TEST_F(Interrupted, KilledAtRandomMomentsAndResumedIsTheUninterruptedRender) {
  ASSERT_EQ(run({"-o", path("ref.exr")}), 0) << err();
  std::mt19937 random(31);
  const std::vector<std::string> resumable = {"-o", path("out.exr"), "--checkpoint", path("cp.film"),
                                              "--checkpoint-every", "0.05", "--resume"};
  int kills = 0;
  for (int attempt = 0; attempt < 5; ++attempt) {
    // Killed a random moment after the run wrote a checkpoint of its own (so each run moves on).
    const ino_t before = inodeOf(path("cp.film"));
    Spawned p = spawnRayes(renderArgs(resumable), path("err.txt"));
    waitForNew(path("cp.film"), before, p.pid);
    std::this_thread::sleep_for(std::chrono::milliseconds(random() % 120));
    ::kill(p.pid, SIGKILL);
    const int code = p.wait();
    if (code == 0) break;  // it finished first
    ASSERT_EQ(code, 128 + SIGKILL) << err();
    ++kills;
  }
  ASSERT_EQ(run(resumable), 0) << err();
  std::printf("  resumed after %d kills\n", kills);  // how many landed depends on the machine's load
  EXPECT_TRUE(readExrImage(path("ref.exr")).sameBits(readExrImage(path("out.exr")))) << kills << " kills";
  EXPECT_FALSE(fs::exists(path("cp.film"))) << "removed once the render is done";
}

TEST_F(Interrupted, SigtermWithACheckpointExitsWith4AndResumes) {
  ASSERT_EQ(run({"-o", path("ref.exr")}), 0) << err();
  const std::vector<std::string> args = {"-o", path("new/sub/img.exr"), "--checkpoint", path("new/cp.film"),
                                         "--checkpoint-every", "0.05"};
  Spawned p = spawnRayes(renderArgs(args), path("err.txt"));
  waitForNew(path("new/cp.film"), 0, p.pid);  // in the middle of the render
  ::kill(p.pid, SIGTERM);
  const int code = p.wait();
  if (code == 0) GTEST_SKIP() << "the render finished before the signal";
  ASSERT_EQ(code, 4) << err();
  EXPECT_THAT(err(), HasSubstr("stopped by SIGTERM"));
  // The checkpoint stays, the outputs and the folder made only for them go.
  EXPECT_EQ(temp_.entries(), (std::vector<std::string>{"err.txt", "new", "new/cp.film", "ref.exr", "ref.png"}));
  std::vector<std::string> again = args;
  again.push_back("--resume");
  ASSERT_EQ(run(again), 0) << err();
  EXPECT_TRUE(readExrImage(path("ref.exr")).sameBits(readExrImage(path("new/sub/img.exr"))));
}

TEST_F(Interrupted, ASignalWithoutACheckpointLeavesNoFolderItMade) {
  for (int sig : {SIGTERM, SIGINT}) {
    Spawned p = spawnRayes(renderArgs({"-o", path("new/sub/img.exr"), "--stats", path("s/t/stats.json")}), path("err.txt"));
    ASSERT_TRUE(waitFor(path("new/sub")));
    ASSERT_TRUE(waitFor(path("s/t")));
    ::kill(p.pid, sig);
    const int code = p.wait();
    if (code == 0) GTEST_SKIP() << "the render finished before the signal";
    EXPECT_EQ(code, 128 + sig) << err();
    EXPECT_EQ(temp_.entries(), std::vector<std::string>{"err.txt"}) << "signal " << sig;
  }
}

// A checkpoint past the file size limit fails to write: the previous one stays, unchanged and
// valid, no temporary is left, and the render stops with exit code 4 (it can resume from it).
TEST_F(Interrupted, ACheckpointThatCannotBeWrittenLeavesThePreviousOne) {
  ASSERT_EQ(run({"-o", path("ref.exr")}), 0) << err();
  const std::vector<std::string> args = {"-o", path("out.exr"), "--checkpoint", path("cp.film"), "--time-limit", "1e-9"};
  ASSERT_EQ(run(args), 4) << err();
  const std::string before = readFile(path("cp.film"));
  std::vector<std::string> resume = args;
  resume.push_back("--resume");
  ASSERT_EQ(run(resume, before.size() / 2), 4) << err();
  EXPECT_THAT(err(), HasSubstr("cannot write a newer checkpoint"));
  EXPECT_THAT(err(), HasSubstr("the previous one is kept"));
  EXPECT_EQ(readFile(path("cp.film")), before);
  EXPECT_EQ(temp_.entries(), (std::vector<std::string>{"cp.film", "err.txt", "ref.exr", "ref.png"}));
  resume[5] = "1000";  // the time limit
  ASSERT_EQ(run(resume), 0) << err();
  EXPECT_TRUE(readExrImage(path("ref.exr")).sameBits(readExrImage(path("out.exr"))));
}

// The same on a disk that fills: a tmpfs too small for two checkpoints, mounted in a user and
// mount namespace (skipped where unshare cannot make one).
TEST_F(Interrupted, ADiskThatFillsLeavesThePreviousCheckpoint) {
  if (::system("unshare --user --map-root-user --mount true 2>/dev/null") != 0)
    GTEST_SKIP() << "unshare cannot make a mount namespace here";
  const std::string disk = path("disk");
  fs::create_directories(disk);
  std::string command;
  for (const std::string& a : renderArgs({"-o", disk + "/out.exr", "--checkpoint", disk + "/cp.film", "--time-limit", "1e-9"}))
    command += " '" + a + "'";
  // First a checkpoint that fits (96 x 72 pixels of 156 bytes, and a header), then a second one,
  // whose temporary must live beside the first on a disk that holds one and a half.
  const size_t one = 96 * 72 * 156;
  const std::string script = "mount -t tmpfs -o size=" + std::to_string(one * 3 / 2) + " tmpfs '" + disk +
                             "' || exit 90\n" + "'" + kRayes + "'" +
                             command + " 2>'" + path("err1.txt") + "'; echo $? > '" + path("code1") + "'\n" +
                             "cp '" + disk + "/cp.film' '" + path("first.film") + "'\n" +
                             "'" + kRayes + "'" + command +
                             " --resume 2>'" + path("err2.txt") + "'; echo $? > '" + path("code2") + "'\n" +
                             "cmp -s '" + disk + "/cp.film' '" + path("first.film") + "'; echo $? > '" + path("same") + "'\n" +
                             "ls -A '" + disk + "' > '" + path("left") + "'\n";
  temp_.write("script.sh", script);
  const int rc = ::system(("unshare --user --map-root-user --mount sh '" + path("script.sh") + "'").c_str());
  if (WEXITSTATUS(rc) == 90) GTEST_SKIP() << "cannot mount a tmpfs here";
  EXPECT_EQ(readFile(path("code1")), "4\n") << readFile(path("err1.txt"));
  EXPECT_EQ(readFile(path("code2")), "4\n") << readFile(path("err2.txt"));
  EXPECT_THAT(readFile(path("err2.txt")), HasSubstr("No space left on device"));
  EXPECT_EQ(readFile(path("same")), "0\n") << "the previous checkpoint is unchanged";
  EXPECT_EQ(readFile(path("left")), "cp.film\n") << "no temporary is left";
}

}  // namespace
}  // namespace rayes::testing
