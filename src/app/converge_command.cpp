// `rayes converge`: error against run time, renders at doubling effort against a reference
// (app/converge.h), written as a CSV and an SVG chart.
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include "app/commands.h"
#include "app/converge.h"
#include "app/output_set.h"
#include "core/error.h"
#include "core/parallel.h"
#include "core/timer.h"

namespace rayes {
namespace {

// "x0,y0,x1,y1": a pixel box inside the image, x0 < x1, y0 < y1.
PixelRegion parseRegion(const std::string& text, const Scene& scene) {
  PixelRegion r;
  int v[4];
  size_t at = 0;
  for (int k = 0; k < 4; ++k) {
    const size_t comma = k < 3 ? text.find(',', at) : text.size();
    const std::string part = comma == std::string::npos ? "" : text.substr(at, comma - at);
    const auto [p, ec] = std::from_chars(part.data(), part.data() + part.size(), v[k]);
    if (part.empty() || ec != std::errc() || p != part.data() + part.size())
      throw InputError("--region", "", "expected x0,y0,x1,y1 in whole pixels, got '" + text + "'");
    at = comma + 1;
  }
  r.x0 = v[0], r.y0 = v[1], r.x1 = v[2], r.y1 = v[3];
  if (r.x0 < 0 || r.y0 < 0 || r.x1 > scene.width || r.y1 > scene.height || r.x0 >= r.x1 || r.y0 >= r.y1)
    throw InputError("--region", "", "the box " + text + " is empty or leaves the " + std::to_string(scene.width) + "x" +
                                         std::to_string(scene.height) + " image");
  return r;
}

// How many pixels both sets count.
size_t pixelsInBoth(const PixelRegion& a, const PixelRegion& b, int width, int height) {
  size_t n = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) n += a.contains(x, y, width) && b.contains(x, y, width);
  return n;
}

// "(12, 7) 0.53 against 0.02, ..." for the warning: where, and which image is off.
std::string namedPixels(const LargestErrors& largest) {
  std::string s;
  char buf[160];
  for (const PixelError& e : largest.pixels) {
    std::snprintf(buf, sizeof buf, "%s(%d, %d): %.4g against %.4g in the reference, %.1f %%", s.empty() ? "" : "; ",
                  e.x, e.y, e.value, e.reference, 100 * e.squared / largest.total);
    s += buf;
  }
  return s;
}

}  // namespace

int runConverge(const RenderArgs& a) {
  // The budget covers the whole command: loading the scene and the references too.
  const auto t0 = Clock::now();
  RenderOptions options = checkedOptions(a);
  if (!(a.budget > 0) || !std::isfinite(a.budget)) throw InputError("--budget", "", "must be a positive number of seconds");
  if (!a.region.empty() && !a.mask.empty()) throw InputError("--mask", "", "give --region or --mask, not both");
  if (!(a.beamGrowth >= 1 && a.beamGrowth <= 4))
    throw InputError("--beam-growth", "", "must lie in [1, 4] (the beam resolution's factor per doubling of spp)");
  if (a.clampedRmse && !(*a.clampedRmse > 0 && *a.clampedRmse < 1))
    throw InputError("--clamped-rmse", "", "must lie in (0, 1): the quantile of the pixels' squared errors at which "
                                           "each is clamped, e.g. 0.999");
  ThreadLimit limit(a.threads);
  const Scene scene = preparedScene(a);
  ConvergeSettings settings;
  // Several references are summed: e.g. the image without caustic paths plus those paths alone,
  // each by the method that renders it best.
  for (const std::string& file : a.references) {
    const std::vector<float> part = imageOfSceneSize(file, scene, "reference image");
    if (settings.reference.empty()) settings.reference.assign(part.size(), 0.0f);
    for (size_t i = 0; i < part.size(); ++i) settings.reference[i] += part[i];
  }
  const PixelRegion wholeImage{0, 0, scene.width, scene.height, {}};
  settings.region = settings.errorPixels = wholeImage;
  if (!a.mask.empty()) settings.region.mask = imageOfSceneSize(a.mask, scene, "mask");
  else if (!a.region.empty()) settings.region = parseRegion(a.region, scene);
  if (!a.errorMask.empty()) settings.errorPixels.mask = imageOfSceneSize(a.errorMask, scene, "error mask");
  // A set of no pixels would give every row an RMSE (or a bias) of exactly 0, which reads as a
  // perfect render, not as no measurement: refused rather than warned about, since the whole
  // run, its budget and its CSV would then measure nothing.
  if (pixelsInBoth(settings.errorPixels, wholeImage, scene.width, scene.height) == 0)
    throw InputError(a.errorMask, "", "error mask has no pixel with non-zero red: no pixel would be counted and "
                                      "every RMSE would read 0");
  if (pixelsInBoth(settings.region, settings.errorPixels, scene.width, scene.height) == 0) {
    if (!a.mask.empty() && pixelsInBoth(settings.region, wholeImage, scene.width, scene.height) == 0)
      throw InputError(a.mask, "", "mask has no pixel with non-zero red: the region would be empty and its bias read 0");
    throw InputError(a.errorMask, "", "error mask counts no pixel of the region (" +
                                          (a.mask.empty() ? "--region " + a.region : a.mask) +
                                          "): its bias would read 0");
  }
  const std::string stem = std::filesystem::path(a.scene).stem().string() + "-" + a.method;
  const std::string csv = a.out.empty() ? "out/" + stem + "-converge.csv" : a.out;
  const std::string svg = a.svg.empty() ? std::filesystem::path(csv).replace_extension(".svg").string() : a.svg;
  OutputSet outputs;
  for (const std::string& input : {a.scene, a.mask, a.errorMask}) outputs.addInput(input);
  for (const std::string& input : a.references) outputs.addInput(input);
  outputs.add(csv, "error curve");
  outputs.add(svg, "chart");
  settings.schedule.beamGrowth = a.beamGrowth;
  settings.budget.seconds = a.budget;
  settings.clampQuantile = a.clampedRmse.value_or(0);
  settings.now = [t0] { return secondsSince(t0); };
  bool warned = false;
  const ConvergeRun run = converge(scene, options, settings, [&](const ConvergeRow& r) {
    if (!a.quiet) {
      std::fprintf(stderr, "rayes converge: %d spp, %.2fs, RMSE %.5g, relMSE %.5g, region bias %.5g", r.spp, r.seconds,
                   r.rmse, r.relMse, r.regionBias);
      if (a.clampedRmse) std::fprintf(stderr, ", clamped RMSE %.5g", r.clampedRmse);
      std::fprintf(stderr, "\n");
    }
    // Once per run, and not silenced by --quiet: the CSV alone would not show it.
    if (!warned && heldByFewPixels(r.largest)) {
      warned = true;
      std::fprintf(stderr,
                   "rayes: warning: at %d spp, %zu of %zu pixels hold %.1f %% of the squared error, so the RMSE "
                   "follows them: %s (mean over RGB); a firefly in the render or the reference (--clamped-rmse 0.999 "
                   "adds an RMSE with outliers clamped)\n",
                   r.spp, r.largest.pixels.size(), r.largest.counted, 100 * r.largest.share,
                   namedPixels(r.largest).c_str());
    }
  });
  if (run.stoppedSpp > 0 && !a.quiet)
    std::fprintf(stderr, "rayes converge: the %d spp render, started at %.2f s, reached the budget of %g s and was "
                 "stopped at %.2f s: no row for it\n", run.stoppedSpp, run.stoppedStart, a.budget,
                 run.stoppedStart + run.stoppedSeconds);
  outputs.writeText(csv, convergeCsv(run.rows, a.clampedRmse.has_value()));
  outputs.writeText(svg, convergeSvg(run.rows, std::filesystem::path(a.scene).filename().string() + ", --method " + a.method));
  outputs.commit();
  if (!a.quiet) std::fprintf(stderr, "rayes: wrote %s and %s\n", csv.c_str(), svg.c_str());
  return 0;
}

}  // namespace rayes
