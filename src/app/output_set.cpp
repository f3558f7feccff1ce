#include "app/output_set.h"
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <unistd.h>
#include "app/interrupt.h"
#include "core/error.h"

namespace rayes {
namespace fs = std::filesystem;

OutputSet::~OutputSet() {
  if (!committed_) removeTemporaries();
}

void OutputSet::removeTemporaries() {
  std::error_code ec;
  for (const Entry& e : entries_) {
    fs::remove(e.temporary, ec);
    unregisterCleanup(e.signalSlot);
  }
  // Folders this set created, deepest first; fs::remove leaves a folder that is not empty.
  for (auto it = createdFolders_.rbegin(); it != createdFolders_.rend(); ++it) fs::remove(*it, ec);
  for (int slot : folderSlots_) unregisterCleanup(slot);
  folderSlots_.clear();
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
    // A run stopped by a signal removes them too (outermost registered first).
    for (auto it = missing.rbegin(); it != missing.rend(); ++it) folderSlots_.push_back(registerCleanupFolder(it->string()));
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
  entries_.push_back({target, temporary, what, registerCleanupFile(temporary)});
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
  for (const Entry& e : entries_) unregisterCleanup(e.signalSlot);
  for (int slot : folderSlots_) unregisterCleanup(slot);
  folderSlots_.clear();
  committed_ = true;
}

}  // namespace rayes
