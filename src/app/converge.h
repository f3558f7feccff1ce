// `rayes converge`: error against run time. A scene is rendered afresh at doubling effort
// (spp 1, 2, 4, ...; photon counts are per sample, so pm and ppm double their photons too)
// until the time budget would be exceeded, and every render is compared with a reference:
// RMSE and relative MSE over the image, and the mean signed error (bias) inside a region
// (a pixel box, or the non-zero pixels of a mask EXR; docs/converge.md). One CSV row per
// render, and an SVG chart of RMSE against seconds (log-log).
#pragma once
#include <string>
#include <vector>
#include "app/renderer.h"

namespace rayes {

struct ConvergeRow {
  double seconds;   // wall clock of this render alone (setup and render, not loading)
  int spp;
  uint64_t photons; // photons traced (pm, ppm), else 0
  double rmse, relMse, regionBias;
};

// Pixels [x0, x1) x [y0, y1), or a mask (non-zero red) when `mask` is not empty.
struct ConvergeRegion {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  std::vector<float> mask;  // RGB per pixel
  bool contains(int x, int y, int width) const {
    if (!mask.empty()) return mask[3 * (size_t(y) * size_t(width) + size_t(x))] != 0;
    return x >= x0 && x < x1 && y >= y0 && y < y1;
  }
};

// Renders until the next doubling is not expected to fit in `budgetSeconds` (at least once).
// `row` is called after every render (progress).
std::vector<ConvergeRow> converge(const Scene& scene, const RenderOptions& options, const std::vector<float>& reference,
                                  const ConvergeRegion& region, double budgetSeconds,
                                  const std::function<void(const ConvergeRow&)>& row = {});

// The mean of (x - r)² / (r² + 0.01) over pixels and channels (the 0.01 keeps black pixels finite).
double relMseAgainst(const std::vector<float>& rgba, const std::vector<float>& referenceRgb);
std::string convergeCsv(const std::vector<ConvergeRow>& rows);
std::string convergeSvg(const std::vector<ConvergeRow>& rows, const std::string& title);

}  // namespace rayes
