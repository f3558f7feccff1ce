#include "app/output_set.h"
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <unistd.h>
#include "core/error.h"

namespace rayes {
namespace fs = std::filesystem;
namespace {

// The temporaries of live sets, for a run stopped by SIGINT, SIGTERM or SIGHUP: the handler
// may only call async-signal-safe functions (unlink, signal, raise), so the paths are kept in
// plain arrays. A path too long for a slot, or a slot table full, is only not removed on a signal.
constexpr int kSlots = 16;
char pendingPath[kSlots][4096];
volatile std::sig_atomic_t pendingUsed[kSlots];

extern "C" void removePendingAndReraise(int sig) {
  for (int k = 0; k < kSlots; ++k)
    if (pendingUsed[k]) ::unlink(pendingPath[k]);
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

int registerPending(const std::string& path) {
  static const bool installed = [] {
    for (int sig : {SIGINT, SIGTERM, SIGHUP})  // an ignored signal (nohup) stays ignored
      if (std::signal(sig, removePendingAndReraise) == SIG_IGN) std::signal(sig, SIG_IGN);
    return true;
  }();
  (void)installed;
  if (path.size() >= sizeof pendingPath[0]) return -1;
  for (int k = 0; k < kSlots; ++k)
    if (!pendingUsed[k]) {
      std::memcpy(pendingPath[k], path.c_str(), path.size() + 1);
      pendingUsed[k] = 1;
      return k;
    }
  return -1;
}

void unregisterPending(int slot) {
  if (slot >= 0) pendingUsed[slot] = 0;
}

}  // namespace

OutputSet::~OutputSet() {
  if (!committed_) removeTemporaries();
}

void OutputSet::removeTemporaries() {
  std::error_code ec;
  for (const Entry& e : entries_) {
    fs::remove(e.temporary, ec);
    unregisterPending(e.signalSlot);
  }
  // Folders this set created, deepest first; fs::remove leaves a folder that is not empty.
  for (auto it = createdFolders_.rbegin(); it != createdFolders_.rend(); ++it) fs::remove(*it, ec);
}

void OutputSet::add(const std::string& target, const std::string& what) {
  for (const Entry& e : entries_)
    if (fs::path(e.target).lexically_normal() == fs::path(target).lexically_normal())
      throw InputError(target, "", "given as the " + e.what + " and as the " + what);
  std::error_code ec;
  for (const std::string& input : inputs_)
    if (fs::equivalent(target, input, ec))
      throw InputError(target, "", "the " + what + " would overwrite an input of this run");
  if (fs::is_directory(target, ec)) throw InputError(target, "", "cannot write the " + what + ": is a directory");
  // Renaming onto a device or a pipe would replace it, not write into it.
  if (fs::exists(target, ec) && !fs::is_regular_file(target, ec))
    throw InputError(target, "", "cannot write the " + what + ": not a regular file");
  const fs::path dir = fs::path(target).parent_path();
  if (!dir.empty()) {
    std::vector<fs::path> missing;
    for (fs::path p = dir; !p.empty() && !fs::exists(p, ec); p = p.parent_path()) missing.push_back(p);
    createdFolders_.insert(createdFolders_.end(), missing.rbegin(), missing.rend());
    fs::create_directories(dir, ec);
    if (ec) throw InputError(target, "", "cannot create the folder for the " + what + ": " + ec.message());
  }
  const std::string temporary =
      (dir / ("." + fs::path(target).filename().string() + ".tmp-" + std::to_string(::getpid()))).string();
  FILE* f = std::fopen(temporary.c_str(), "wb");
  if (!f) {
    const int err = errno;
    throw InputError(target, "", "cannot write the " + what + ": " + std::strerror(err));
  }
  std::fclose(f);
  entries_.push_back({target, temporary, what, registerPending(temporary)});
}

const OutputSet::Entry& OutputSet::entry(const std::string& target) const {
  for (const Entry& e : entries_)
    if (e.target == target) return e;
  throw std::logic_error("OutputSet: '" + target + "' was not added");
}

void OutputSet::write(const std::string& target, const std::function<void(const std::string&)>& write) {
  const Entry& e = entry(target);
  try {
    write(e.temporary);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& ex) {
    throw InputError(target, "", "cannot write the " + e.what + ": " + ex.what());
  }
}

void OutputSet::writeText(const std::string& target, const std::string& text) {
  write(target, [&](const std::string& temporary) {
    FILE* f = std::fopen(temporary.c_str(), "wb");
    int err = f ? 0 : errno;
    if (f && std::fwrite(text.data(), 1, text.size(), f) != text.size()) err = errno;
    if (f && std::fclose(f) != 0 && err == 0) err = errno;
    if (err) throw std::runtime_error(std::strerror(err));
  });
}

void OutputSet::commit() {
  for (size_t k = 0; k < entries_.size(); ++k) {
    std::error_code ec;
    fs::rename(entries_[k].temporary, entries_[k].target, ec);
    if (!ec) continue;
    const std::string reason = ec.message();  // before the cleanup below reuses ec
    for (size_t done = 0; done < k; ++done) fs::remove(entries_[done].target, ec);
    removeTemporaries();
    committed_ = true;
    throw InputError(entries_[k].target, "", "cannot write the " + entries_[k].what + ": " + reason);
  }
  for (const Entry& e : entries_) unregisterPending(e.signalSlot);
  committed_ = true;
}

}  // namespace rayes
