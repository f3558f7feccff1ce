#include "app/checkpoint.h"
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <unistd.h>
#include "app/interrupt.h"
#include "core/error.h"

namespace rayes {
namespace fs = std::filesystem;
namespace {

std::string temporaryOf(const std::string& path) {
  const fs::path p(path);
  return (p.parent_path() / ("." + p.filename().string() + ".tmp-" + std::to_string(::getpid()))).string();
}

void syncFolder(const std::string& path) {
  const fs::path dir = fs::path(path).parent_path();
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd < 0) return;
  ::fsync(fd);  // the rename reaches the disk; a failure here leaves the old or the new file
  ::close(fd);
}

}  // namespace

std::string defaultCheckpointPath(const std::string& firstOutput) {
  return fs::path(firstOutput).replace_extension(".checkpoint.film").string();
}

Checkpointer::Checkpointer(std::string path, double everySeconds)
    : path_(std::move(path)), every_(everySeconds), last_(Clock::now()) {
  std::error_code ec;
  if (fs::is_directory(path_, ec)) throw InputError(path_, "", "cannot write the checkpoint: is a directory");
  if (fs::exists(path_, ec) && !fs::is_regular_file(path_, ec))
    throw InputError(path_, "", "cannot write the checkpoint: not a regular file");
  const fs::path dir = fs::path(path_).parent_path();
  if (!dir.empty()) {
    std::vector<fs::path> missing;
    for (fs::path p = dir; !p.empty() && !fs::exists(p, ec); p = p.parent_path()) missing.push_back(p);
    for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
      createdFolders_.push_back(it->string());
      folderSlots_.push_back(registerCleanupFolder(it->string()));
    }
    fs::create_directories(dir, ec);
    if (ec) throw InputError(path_, "", "cannot create the folder for the checkpoint: " + ec.message());
  }
  // Writable: the temporary can be made (and is removed at once).
  const std::string tmp = temporaryOf(path_);
  FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) {
    const int err = errno;
    throw InputError(path_, "", std::string("cannot write the checkpoint: ") + std::strerror(err));
  }
  std::fclose(f);
  ::unlink(tmp.c_str());
}

Checkpointer::~Checkpointer() {
  // Folders made for a checkpoint never written go (a folder that holds anything stays).
  std::error_code ec;
  if (!valid_)
    for (auto it = createdFolders_.rbegin(); it != createdFolders_.rend(); ++it) fs::remove(*it, ec);
  for (int slot : folderSlots_) unregisterCleanup(slot);
}

void Checkpointer::batchDone(const Film& film, const Renderer::Position& next) {
  if (secondsSince(last_) < every_) return;
  const std::string failure = writeNow(film, next);
  if (!failure.empty() && failure != lastFailure_)
    std::fprintf(stderr, "rayes: warning: %s: cannot write the checkpoint: %s; %s, the render goes on\n", path_.c_str(),
                 failure.c_str(), valid_ ? "the previous checkpoint is kept" : "there is none yet");
  lastFailure_ = failure;
}

std::string Checkpointer::writeNow(const Film& film, const Renderer::Position& next) {
  const auto t0 = Clock::now();
  struct Timed {
    const Clock::time_point& t0;
    double& seconds;
    ~Timed() { seconds += secondsSince(t0); }
  } timed{t0, seconds_};
  last_ = t0;
  header_.pass = next.pass;
  header_.next = next.next;
  header_.blockPixels = next.blockPixels;
  header_.firstHitsEnd = next.firstHitsEnd;
  const std::string tmp = temporaryOf(path_);
  const int slot = registerCleanupFile(tmp);
  std::string failure;
  try {
    writeFilmFile(tmp, header_, film, true);
    if (std::rename(tmp.c_str(), path_.c_str()) != 0) failure = std::strerror(errno);
  } catch (const FilmWriteError& e) {
    failure = e.what();
    if (e.error == ENOSPC || e.error == EDQUOT || e.error == EFBIG) failure += " (the disk or the file size limit is full)";
  }
  if (!failure.empty()) ::unlink(tmp.c_str());
  unregisterCleanup(slot);
  if (!failure.empty()) return failure;
  syncFolder(path_);
  valid_ = true;
  ++written_;
  return "";
}

void Checkpointer::removeFile() {
  std::error_code ec;
  fs::remove(path_, ec);
  valid_ = false;
}

}  // namespace rayes
