#include "app/progress.h"
#include <cstdio>
#include <unistd.h>

namespace rayes {

ProgressReporter::ProgressReporter(bool enabled, int totalSpp)
    : enabled_(enabled), terminal_(::isatty(2) != 0), totalSpp_(totalSpp), start_(Clock::now()) {}

void ProgressReporter::update(uint64_t done, uint64_t total, int samplesFinished) {
  if (!enabled_) return;
  const double t = secondsSince(start_);
  const double f = total ? double(done) / double(total) : 1.0;
  if (terminal_) {
    if (t - lastDraw_ < 0.1 && done < total) return;
    lastDraw_ = t;
    const int width = 40, filled = int(f * width);
    char bar[width + 1];
    for (int i = 0; i < width; ++i) bar[i] = i < filled ? '#' : '.';
    bar[width] = 0;
    const double eta = f > 0 ? t * (1 - f) / f : 0;
    std::fprintf(stderr, "\r[%s] %5.1f%%  %d/%d spp  %.1fs  ETA %.1fs ", bar, 100 * f, samplesFinished, totalSpp_,
                 t, eta);
    std::fflush(stderr);
  } else if (samplesFinished != lastSpp_ && samplesFinished > 0) {
    lastSpp_ = samplesFinished;
    std::fprintf(stderr, "rayes: %d/%d spp, %.0f%% of paths, %.2fs\n", samplesFinished, totalSpp_, 100 * f, t);
  }
}

void ProgressReporter::finish() {
  if (enabled_ && terminal_) std::fprintf(stderr, "\n");
}

}  // namespace rayes
