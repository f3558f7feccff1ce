// Progress of a render, drawn by a timer thread from the live state (app/progress_state.h), so
// that it moves during a batch and names the set-up phases while they run; the render thread
// only stores atomics and never waits on it. Modes (--progress):
//   human: on a terminal (stderr), one line redrawn four times a second: the phase, or during
//          the render a bar, paths finished, the generation, spp, elapsed time and ETA. When
//          stderr is not a terminal (a farm job's log): a plain line per finished pass, as
//          before, and one every 30 s while a pass runs.
//   json:  one JSON object per line on standard output, once a second and a last one with
//          phase "done": elapsed_s, phase, samples_done, samples_total,
//          paths_done, paths_total, generation, eta_s (null while unknown), rss_bytes (resident
//          memory now). Standard output carries nothing else (images go to files, messages to
//          stderr), so a scheduler or dashboard reads it alone. elapsed_s, samples_done and
//          paths_done never decrease.
//   none:  nothing (-q).
#pragma once
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <string>
#include <thread>
#include "app/progress_state.h"
#include "core/timer.h"

namespace rayes {

enum class ProgressMode { Human, Json, None };
ProgressMode progressModeFromName(const std::string& name);  // "human", "json", "none"

class ProgressReporter {
 public:
  // Starts the timer thread (none for ProgressMode::None); the state is liveProgress(), reset.
  explicit ProgressReporter(ProgressMode mode);
  ~ProgressReporter();  // without finish(): stops, draws no last line (the run failed)
  ProgressReporter(const ProgressReporter&) = delete;
  ProgressReporter& operator=(const ProgressReporter&) = delete;
  // The Renderer's per-batch callback: done paths of total, samples per pixel finished.
  void update(uint64_t done, uint64_t total, int samplesFinished);
  // Stops the thread and draws the last state (phase "done").
  void finish();

 private:
  void run();
  void stopThread();
  void draw(bool last);

  ProgressMode mode_;
  bool terminal_;
  ProgressState& state_;
  Clock::time_point start_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false, finished_ = false;
  std::thread thread_;
  // Drawn by the thread only (and by finish() after it ended).
  int lastPhase_ = -1, lastPassLine_ = -1;
  uint64_t lastPaths_ = 0;
  int lastSamples_ = 0;
  double lastElapsed_ = 0, lastPlainLine_ = 0;
  size_t lastWidth_ = 0;
};

}  // namespace rayes
