#include "app/progress.h"
#include <unistd.h>
#include <algorithm>
#include <cmath>
#include "core/error.h"
#include "core/memory.h"

namespace rayes {

ProgressMode progressModeFromName(const std::string& name) {
  if (name == "human") return ProgressMode::Human;
  if (name == "json") return ProgressMode::Json;
  if (name == "none") return ProgressMode::None;
  throw InputError("--progress", "", "expected human, json or none, got '" + name + "'");
}

ProgressReporter::ProgressReporter(ProgressMode mode)
    : mode_(mode), terminal_(::isatty(2) != 0), state_(liveProgress()), start_(Clock::now()) {
  state_.reset();
  if (mode_ != ProgressMode::None) thread_ = std::thread([this] { run(); });
}

ProgressReporter::~ProgressReporter() {
  // Not finished: the run failed; stop without a last line (a redrawn one is ended, so that the
  // message that follows starts a line of its own).
  if (finished_) return;
  finished_ = true;
  stopThread();
  if (mode_ == ProgressMode::Human && terminal_) std::fprintf(stderr, "\n");
}

void ProgressReporter::stopThread() {
  if (!thread_.joinable()) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void ProgressReporter::update(uint64_t done, uint64_t total, int samplesFinished) {
  state_.batchDone(done, total, samplesFinished);
}

void ProgressReporter::run() {
  // Human on a terminal: 4 redraws a second; json: one line a second; plain lines: checked every second.
  const auto period = std::chrono::milliseconds(mode_ == ProgressMode::Human && terminal_ ? 250 : 1000);
  // The first draw after one period: a render shorter than that shows its last line only.
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    // Ask the render thread for the paths finished inside its batch, for the next draw.
    state_.countWanted.store(true, std::memory_order_relaxed);
    if (wake_.wait_for(lock, period, [this] { return stop_; })) break;
    lock.unlock();
    draw(false);
    lock.lock();
  }
}

void ProgressReporter::finish() {
  if (finished_) return;
  finished_ = true;
  stopThread();
  if (mode_ == ProgressMode::None) return;
  state_.setPhase(Phase::Done);
  draw(true);
}

void ProgressReporter::draw(bool last) {
  const double t = std::max(lastElapsed_, secondsSince(start_));
  lastElapsed_ = t;
  const Phase phase = state_.currentPhase();
  const uint64_t total = state_.pathsTotal.load(std::memory_order_relaxed);
  const uint64_t paths = lastPaths_ = std::max(lastPaths_, state_.paths());
  const int samplesTotal = state_.samplesTotal.load(std::memory_order_relaxed);
  const int samples = lastSamples_ = std::max(lastSamples_, state_.samplesDone.load(std::memory_order_relaxed));
  const int generation = state_.generation.load(std::memory_order_relaxed);
  const bool rendering = phase == Phase::Rendering || phase == Phase::TracingPhotons;
  // The ETA from the render's own rate: paths finished since it began.
  const double f = total ? double(paths) / double(total) : 0.0;
  const double eta = f > 0 && f < 1 ? t * (1 - f) / f : (f >= 1 ? 0.0 : -1.0);
  lastPhase_ = int(phase);

  if (mode_ == ProgressMode::Json) {
    char eta_s[32] = "null";
    if (eta >= 0) std::snprintf(eta_s, sizeof eta_s, "%.3f", eta);
    std::fprintf(stdout,
                 "{\"elapsed_s\": %.3f, \"phase\": \"%s\", \"samples_done\": %d, \"samples_total\": %d, "
                 "\"paths_done\": %llu, \"paths_total\": %llu, \"generation\": %d, \"eta_s\": %s, \"rss_bytes\": %llu}\n",
                 t, phaseName(phase), samples, samplesTotal, (unsigned long long)paths, (unsigned long long)total,
                 generation, eta_s, (unsigned long long)currentRssBytes());
    std::fflush(stdout);
    return;
  }
  if (!terminal_) {
    // Plain lines for logs: one per finished pass (as always), one every 30 s in between.
    if (samples != lastPassLine_ && samples > 0) {
      lastPassLine_ = samples;
      lastPlainLine_ = t;
      std::fprintf(stderr, "rayes: %d/%d spp, %.0f%% of paths, %.2fs\n", samples, samplesTotal, 100 * f, t);
    } else if (!last && t - lastPlainLine_ >= 30) {
      lastPlainLine_ = t;
      if (rendering)
        std::fprintf(stderr, "rayes: %s: %llu/%llu paths (%.0f%%), generation %d, %.0fs\n", phaseName(phase),
                     (unsigned long long)paths, (unsigned long long)total, 100 * f, generation, t);
      else std::fprintf(stderr, "rayes: %s, %.0fs\n", phaseName(phase), t);
    }
    return;
  }
  char line[256];
  if (last || !rendering) {
    if (last) std::snprintf(line, sizeof line, "rayes: %d/%d spp, %llu paths, %.1fs", samples, samplesTotal,
                            (unsigned long long)paths, t);
    else std::snprintf(line, sizeof line, "rayes: %s ... %.1fs", phaseName(phase), t);
  } else {
    const int width = 30, filled = std::clamp(int(f * width), 0, width);
    char bar[width + 1];
    for (int i = 0; i < width; ++i) bar[i] = i < filled ? '#' : '.';
    bar[width] = 0;
    char etaText[32] = "?";
    if (eta >= 0) std::snprintf(etaText, sizeof etaText, "%.1fs", eta);
    std::snprintf(line, sizeof line, "[%s] %5.1f%%  %llu/%llu paths  gen %d  %d/%d spp  %.1fs  ETA %s%s", bar,
                  100 * f, (unsigned long long)paths, (unsigned long long)total, std::max(generation, 0), samples,
                  samplesTotal, t, etaText, phase == Phase::TracingPhotons ? "  (photons)" : "");
  }
  // \r and erase to the end of the line: a shorter line leaves nothing of the longer one.
  std::fprintf(stderr, "\r%s\033[K%s", line, last ? "\n" : "");
  std::fflush(stderr);
}

}  // namespace rayes
