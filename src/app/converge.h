// `rayes converge`: error against run time. A scene is rendered afresh at doubling effort
// until the time budget would be exceeded, and every render is compared with a reference:
// RMSE and relative MSE over the image (or over the pixels of an error mask), and the mean
// signed error (bias) inside a region (a pixel box, or the non-zero pixels of a mask EXR;
// docs/design.md, "Caustic paths"). One CSV row per render, and an SVG chart of RMSE against
// seconds (log-log).
// The effort schedule (ConvergeSchedule): spp doubles at every step for every method; photon
// counts are per sample, so the photon methods double their photons with it; the beam method
// also refines its beams, the light grid's resolution growing by `beamGrowth` per step (sqrt 2:
// twice the beams), since more samples alone leave the beam discretisation, and so its bias,
// where it was. The columns of a method's own work read its statistics (Integrator::
// methodStats, ShadeStats), so this file names no method.
#pragma once
#include <string>
#include <vector>
#include "app/image_error.h"
#include "app/renderer.h"

namespace rayes {

struct ConvergeRow {
  double seconds;   // wall clock of this render alone (setup and render, not loading)
  double cpuSeconds;  // the process's CPU time over the same span (all threads; steadier under load)
  int spp;
  uint64_t photons; // photons traced (0 for a method without photons)
  int beamResolution;       // cells per side of each light's grid of beams (0 for a method without beams)
  uint64_t beamSegments;    // beam segments built (0 for a method without beams)
  double rmse, relMse, regionBias;
};

struct ConvergeSchedule {
  double beamGrowth = 1.4142135623730951;  // beams: resolution factor per doubling of spp (1: fixed)
  int maxBeamResolution = 4096;            // the resolution stops growing here
  // The beam resolution at step k (spp = 2^k), from `first`.
  int beamResolution(int first, int step) const;
};

// Renders until the next doubling is not expected to fit in `budgetSeconds` (at least once).
// RMSE and relMSE count the pixels of `errorPixels`, the bias those of `region` among them.
// `row` is called after every render (progress).
std::vector<ConvergeRow> converge(const Scene& scene, const RenderOptions& options, const std::vector<float>& reference,
                                  const PixelRegion& errorPixels, const PixelRegion& region, double budgetSeconds,
                                  const ConvergeSchedule& schedule = {},
                                  const std::function<void(const ConvergeRow&)>& row = {});

std::string convergeCsv(const std::vector<ConvergeRow>& rows);
std::string convergeSvg(const std::vector<ConvergeRow>& rows, const std::string& title);

}  // namespace rayes
