// Checkpoints of a render (--checkpoint FILE, --checkpoint-every SECONDS, --time-limit): the
// film and the position of the next batch, as a .film file (app/film_file.h) written
// atomically: a temporary in the same folder, fsync, rename, fsync of the folder. A checkpoint
// that cannot be written (a full disk) leaves the previous one as it was, valid.
//
// The Renderer calls batchDone at every batch boundary; a checkpoint is written there when
// the period has passed since the last one. writeNow writes one at once (a stop: a signal, the
// time limit). Owned by the command's thread; not thread-safe.
#pragma once
#include <string>
#include "app/film_file.h"
#include "app/renderer.h"
#include "core/timer.h"

namespace rayes {

class Checkpointer {
 public:
  // Claims `path`: it must not be a folder, a device or a pipe, and its folder must be
  // writable (created if missing); throws InputError naming it (exit code 2) otherwise, before
  // any rendering.
  Checkpointer(std::string path, double everySeconds);
  // What the checkpoints are of (batch_job.h: filmHeader); before the first is written.
  void describe(FilmFileHeader header) {
    header_ = std::move(header);
    header_.kind = "checkpoint";
    header_.complete = false;
  }
  ~Checkpointer();
  Checkpointer(const Checkpointer&) = delete;
  Checkpointer& operator=(const Checkpointer&) = delete;

  const std::string& path() const { return path_; }
  // The render resumed from the checkpoint at path(): it is valid already.
  void resumed() { valid_ = true; }
  // At a batch boundary: writes a checkpoint if the period has passed. A failure is reported
  // on stderr once per reason and the render goes on (the previous checkpoint stays).
  void batchDone(const Film& film, const Renderer::Position& next);
  // Writes a checkpoint now; returns "" or the reason it could not (the previous one, if any,
  // is then still there: valid()).
  std::string writeNow(const Film& film, const Renderer::Position& next);
  // Whether path() holds a checkpoint of this render (written by it, or resumed from).
  bool valid() const { return valid_; }
  // The render is complete and its outputs written: the checkpoint is removed.
  void removeFile();
  int written() const { return written_; }
  // Wall seconds spent writing checkpoints (the cost of --checkpoint; the stats' checkpoints.time_s).
  double seconds() const { return seconds_; }

 private:
  std::string path_;
  double every_;
  FilmFileHeader header_;
  Clock::time_point last_;
  bool valid_ = false;
  int written_ = 0;
  double seconds_ = 0;
  std::string lastFailure_;
  std::vector<int> folderSlots_;  // folders created for the checkpoint, in the signal cleanup table
  std::vector<std::string> createdFolders_;
};

// Where --time-limit keeps its checkpoint without --checkpoint: beside the first output,
// "<name without its extension>.checkpoint.film".
std::string defaultCheckpointPath(const std::string& firstOutput);

}  // namespace rayes
