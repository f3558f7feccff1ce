// Runs the built `rayes` program (RAYES_BINARY_DIR/bin/rayes) in a child process, for what an
// in-process run cannot show: a memory limit on the process (RLIMIT_AS, a cgroup), standard
// input from a pipe, stderr that is not a terminal. Returns the exit code (or the signal) and
// what the child printed.
#pragma once
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace rayes::testing {

inline std::string rayesBinary() { return std::string(RAYES_BINARY_DIR) + "/bin/rayes"; }

struct ChildSetup {
  uint64_t addressSpace = 0;    // RLIMIT_AS of the child (0: inherited)
  std::string cgroupProcs;      // a cgroup.procs file the parent puts the child in before it runs
  bool feedStdin = false;       // give the child stdinText through a pipe (else /dev/null)
  std::string stdinText;
  std::string cwd;              // the child's working directory ("": the test's)
  std::vector<std::string> env; // "NAME=value" set in the child's environment over the test's
};

struct ChildResult {
  int code = -1;    // exit code, -1 when killed by a signal
  int signal = 0;   // the signal that ended it, if any
  std::string out, err;
};

namespace detail {
inline std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string s((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::remove(path.c_str());
  return s;
}
}  // namespace detail

inline ChildResult runRayesProcess(const std::vector<std::string>& args, const ChildSetup& setup = {}) {
  static int runs = 0;
  const std::string base = "/tmp/rayes-child-" + std::to_string(::getpid()) + "-" + std::to_string(runs++);
  const std::string outPath = base + ".out", errPath = base + ".err";
  std::vector<std::string> argv = {rayesBinary()};
  argv.insert(argv.end(), args.begin(), args.end());
  std::vector<char*> cargv;
  for (auto& a : argv) cargv.push_back(a.data());
  cargv.push_back(nullptr);
  // The child's environment, made before the fork: the test's, each of setup.env replacing a
  // variable of its name.
  std::vector<std::string> envText(setup.env);
  for (char** e = environ; *e; ++e) {
    const std::string entry = *e;
    const std::string name = entry.substr(0, entry.find('=') + 1);
    if (std::none_of(setup.env.begin(), setup.env.end(), [&](const std::string& s) { return s.rfind(name, 0) == 0; }))
      envText.push_back(entry);
  }
  std::vector<char*> cenv;
  for (auto& e : envText) cenv.push_back(e.data());
  cenv.push_back(nullptr);
  int go[2], in[2];
  if (::pipe(go) != 0 || ::pipe(in) != 0) return {};
  const pid_t pid = ::fork();
  if (pid < 0) return {};
  if (pid == 0) {
    // Only async-signal-safe calls until exec: wait for the parent's go (it may first move this
    // process into a cgroup), then the limit, the files, exec.
    ::close(go[1]);
    ::close(in[1]);
    char c;
    if (::read(go[0], &c, 1) != 1) ::_exit(120);
    if (!setup.cwd.empty() && ::chdir(setup.cwd.c_str()) != 0) ::_exit(124);
    if (setup.addressSpace) {
      const rlimit r{setup.addressSpace, setup.addressSpace};
      if (::setrlimit(RLIMIT_AS, &r) != 0) ::_exit(121);
    }
    const int o = ::open(outPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int e = ::open(errPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int i = setup.feedStdin ? in[0] : ::open("/dev/null", O_RDONLY);
    if (o < 0 || e < 0 || i < 0) ::_exit(122);
    ::dup2(o, 1);
    ::dup2(e, 2);
    ::dup2(i, 0);
    ::execve(cargv[0], cargv.data(), cenv.data());
    ::_exit(123);
  }
  ::close(go[0]);
  ::close(in[0]);
  if (!setup.cgroupProcs.empty()) std::ofstream(setup.cgroupProcs) << pid << "\n";
  const char c = 'g';
  ChildResult r;
  if (::write(go[1], &c, 1) != 1) r.err = "could not start the child";
  ::close(go[1]);
  if (setup.feedStdin) {
    // A child that stops reading must not kill the test with SIGPIPE.
    struct sigaction ignore {}, old{};
    ignore.sa_handler = SIG_IGN;
    ::sigaction(SIGPIPE, &ignore, &old);
    size_t done = 0;
    while (done < setup.stdinText.size()) {
      const ssize_t n = ::write(in[1], setup.stdinText.data() + done, setup.stdinText.size() - done);
      if (n <= 0) break;
      done += size_t(n);
    }
    ::sigaction(SIGPIPE, &old, nullptr);
  }
  ::close(in[1]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFEXITED(status)) r.code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) r.signal = WTERMSIG(status);
  r.out = detail::slurp(outPath);
  r.err += detail::slurp(errPath);
  return r;
}

}  // namespace rayes::testing
