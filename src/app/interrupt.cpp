#include "app/interrupt.h"
#include <csignal>
#include <cstring>
#include <unistd.h>

namespace rayes {
namespace {

constexpr int kSlots = 32;
char cleanupPath[kSlots][4096];
// 0: free, 1: a file, 2: a folder.
volatile std::sig_atomic_t cleanupKind[kSlots];
volatile std::sig_atomic_t stopOnSignal = 0;
volatile std::sig_atomic_t stopSignalSeen = 0;

void cleanUp() {
  for (int k = 0; k < kSlots; ++k)
    if (cleanupKind[k] == 1) ::unlink(cleanupPath[k]);
  // Folders deepest first; slots may have been reused out of order, so sweep until none goes.
  for (int pass = 0; pass < kSlots; ++pass) {
    bool removed = false;
    for (int k = kSlots - 1; k >= 0; --k)
      if (cleanupKind[k] == 2 && ::rmdir(cleanupPath[k]) == 0) {
        cleanupKind[k] = 0;
        removed = true;
      }
    if (!removed) break;
  }
}

extern "C" void onSignal(int sig) {
  if (stopOnSignal && !stopSignalSeen) {
    stopSignalSeen = sig;
    return;
  }
  cleanUp();
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

int registerPath(const std::string& path, int kind) {
  installSignalHandlers();
  if (path.size() >= sizeof cleanupPath[0]) return -1;
  for (int k = 0; k < kSlots; ++k)
    if (!cleanupKind[k]) {
      std::memcpy(cleanupPath[k], path.c_str(), path.size() + 1);
      cleanupKind[k] = kind;
      return k;
    }
  return -1;
}

}  // namespace

void installSignalHandlers() {
  static const bool installed = [] {
    for (int sig : {SIGINT, SIGTERM, SIGHUP})  // an ignored signal (nohup) stays ignored
      if (std::signal(sig, onSignal) == SIG_IGN) std::signal(sig, SIG_IGN);
    return true;
  }();
  (void)installed;
}

int registerCleanupFile(const std::string& path) { return registerPath(path, 1); }
int registerCleanupFolder(const std::string& path) { return registerPath(path, 2); }

void unregisterCleanup(int slot) {
  if (slot >= 0 && slot < kSlots) cleanupKind[slot] = 0;
}

void setStopOnSignal(bool stop) {
  installSignalHandlers();
  stopOnSignal = stop ? 1 : 0;
}

bool stopRequested() { return stopSignalSeen != 0; }
int stopSignal() { return stopSignalSeen; }

}  // namespace rayes
