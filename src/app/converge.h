// `rayes converge`: error against run time. A scene is rendered afresh at doubling effort
// while the budget allows, and every render is compared with a reference: RMSE and relative
// MSE over the image (or over the pixels of an error mask), optionally the RMSE with outliers
// clamped, and the mean signed error (bias) inside a region (a pixel box, or the non-zero
// pixels of a mask EXR; docs/design.md, "Caustic paths"). One CSV row per render, and an SVG
// chart of RMSE against seconds (log-log).
// The effort schedule (ConvergeSchedule): spp doubles at every step for every method; photon
// counts are per sample, so the photon methods double their photons with it; the beam method
// also refines its beams, the light grid's resolution growing by `beamGrowth` per step (sqrt 2:
// twice the beams), since more samples alone leave the beam discretisation, and so its bias,
// where it was. The columns of a method's own work read its statistics (Integrator::
// methodStats, ShadeStats), so this file names no method.
// The budget (ConvergeBudget) covers the whole run from the clock's zero: a render starts only
// when its predicted time fits what is left, and one that reaches the budget anyway is stopped
// at its next generation (Renderer::Control) and leaves no row. The first render always
// completes, so there is at least one row.
// Not thread-safe (one Renderer at a time, on the caller's thread and its ThreadLimit).
#pragma once
#include <functional>
#include <string>
#include <vector>
#include "app/image_error.h"
#include "app/renderer.h"

namespace rayes {

struct ConvergeSchedule {
  double beamGrowth = 1.4142135623730951;  // beams: resolution factor per doubling of spp (1: fixed)
  int maxBeamResolution = 4096;            // the resolution stops growing here
  // The beam resolution at step k (spp = 2^k), from `first`.
  int beamResolution(int first, int step) const;
};

// When the next render may start and when one in flight must stop: pure rules of the seconds
// elapsed since the run began and of the renders' seconds so far (oldest first).
struct ConvergeBudget {
  double seconds = 0;  // the whole run's budget
  // The next render's predicted seconds: the last render's times its growth over the one
  // before, at least 2. The effort doubles; a method whose cost per sample grows with the step
  // (lbt: twice the beams, each sample gathering over more segments) or with the samples (a
  // photon map's kd-tree: n log n) grows faster, and the last step's ratio carries that on.
  static double predictedNext(const std::vector<double>& renderSeconds);
  // The first render always starts; a later one when the elapsed time plus its prediction fits.
  bool mayStart(double elapsed, const std::vector<double>& renderSeconds) const {
    return renderSeconds.empty() || elapsed + predictedNext(renderSeconds) <= seconds;
  }
  bool mustStop(double elapsed) const { return elapsed >= seconds; }
};

// A few pixels holding most of the squared error (a firefly in the render or in the reference)
// make the RMSE follow them, not the image. The rule: the kOutlierPixels largest hold more
// than kOutlierShare of it, among at least kOutlierMinPixels counted pixels. Why these: with
// independent noise in N pixels the largest squared error is about 2 ln N times the mean
// (bench/reference_fireflies.py), so the 3 largest hold about 2 ln N / N of the sum: 9 % at
// N = 100, below 1 % from N = 2000, far from half; and a fixed few pixels can be named,
// where 0.1 % of a large image (2,000 pixels) could be a caustic's edge, the scene's hard part
// rather than an outlier.
inline constexpr size_t kOutlierPixels = 3;
inline constexpr double kOutlierShare = 0.5;
inline constexpr size_t kOutlierMinPixels = 100;
bool heldByFewPixels(const LargestErrors& largest);

struct ConvergeRow {
  double seconds;   // wall clock of this render alone (setup and render; not loading, not its error)
  double cpuSeconds;  // the process's CPU time over the same span (all threads; steadier under load)
  int spp;
  uint64_t photons; // photons traced (0 for a method without photons)
  int beamResolution;       // cells per side of each light's grid of beams (0 for a method without beams)
  uint64_t beamSegments;    // beam segments built (0 for a method without beams)
  double rmse, relMse, regionBias;
  double clampedRmse = 0;   // with ConvergeSettings::clampQuantile > 0 (image_error.h, clampedRmse)
  LargestErrors largest;    // the kOutlierPixels largest squared errors and their share
};

struct ConvergeSettings {
  std::vector<float> reference;  // RGB per pixel, of the scene's size, finite
  PixelRegion errorPixels;       // the pixels RMSE, relMSE, the clamped RMSE and the bias count
  PixelRegion region;            // the bias's pixels (among errorPixels)
  ConvergeBudget budget;
  ConvergeSchedule schedule;
  double clampQuantile = 0;      // in (0, 1): each row's clampedRmse at this quantile; 0: none
  // Seconds since the run began. Read once as each render starts (the budget decides there
  // whether it starts), once as it ends, and between the generations of every render but the
  // first (the stop check); nowhere else, so a test can script it.
  std::function<double()> now;
};

struct ConvergeRun {
  std::vector<ConvergeRow> rows;
  int stoppedSpp = 0;         // > 0: the render of this many spp reached the budget, stopped, no row
  double stoppedStart = 0;    // when it started (ConvergeSettings::now)
  double stoppedSeconds = 0;  // how long it had run
};

// `row` is called after every render (progress, warnings).
ConvergeRun converge(const Scene& scene, const RenderOptions& options, const ConvergeSettings& settings,
                     const std::function<void(const ConvergeRow&)>& row = {});

// The CSV: seconds, cpu_seconds, spp, photons, beam_resolution, beam_segments, rmse, rel_mse,
// region_bias, and clamped_rmse last when `clampedColumn` (readers by position keep working).
std::string convergeCsv(const std::vector<ConvergeRow>& rows, bool clampedColumn = false);
std::string convergeSvg(const std::vector<ConvergeRow>& rows, const std::string& title);

}  // namespace rayes
