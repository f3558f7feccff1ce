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

}  // namespace

int runConverge(const RenderArgs& a) {
  RenderOptions options = checkedOptions(a);
  if (!(a.budget > 0) || !std::isfinite(a.budget)) throw InputError("--budget", "", "must be a positive number of seconds");
  if (!a.region.empty() && !a.mask.empty()) throw InputError("--mask", "", "give --region or --mask, not both");
  if (!(a.beamGrowth >= 1 && a.beamGrowth <= 4))
    throw InputError("--beam-growth", "", "must lie in [1, 4] (the beam resolution's factor per doubling of spp)");
  ThreadLimit limit(a.threads);
  const Scene scene = preparedScene(a);
  // Several references are summed: e.g. the image without caustic paths plus those paths alone,
  // each by the method that renders it best.
  std::vector<float> reference;
  for (const std::string& file : a.references) {
    const std::vector<float> part = imageOfSceneSize(file, scene, "reference");
    if (reference.empty()) reference.assign(part.size(), 0.0f);
    for (size_t i = 0; i < part.size(); ++i) reference[i] += part[i];
  }
  const PixelRegion wholeImage{0, 0, scene.width, scene.height, {}};
  PixelRegion region = wholeImage, errorPixels = wholeImage;
  if (!a.mask.empty()) region.mask = imageOfSceneSize(a.mask, scene, "mask");
  else if (!a.region.empty()) region = parseRegion(a.region, scene);
  if (!a.errorMask.empty()) errorPixels.mask = imageOfSceneSize(a.errorMask, scene, "error mask");
  const std::string stem = std::filesystem::path(a.scene).stem().string() + "-" + a.method;
  const std::string csv = a.out.empty() ? "out/" + stem + "-converge.csv" : a.out;
  const std::string svg = a.svg.empty() ? std::filesystem::path(csv).replace_extension(".svg").string() : a.svg;
  OutputSet outputs;
  for (const std::string& input : {a.scene, a.mask, a.errorMask}) outputs.addInput(input);
  for (const std::string& input : a.references) outputs.addInput(input);
  outputs.add(csv, "error curve");
  outputs.add(svg, "chart");
  ConvergeSchedule schedule;
  schedule.beamGrowth = a.beamGrowth;
  const auto rows = converge(scene, options, reference, errorPixels, region, a.budget, schedule, [&](const ConvergeRow& r) {
    if (!a.quiet)
      std::fprintf(stderr, "rayes converge: %d spp, %.2fs, RMSE %.5g, relMSE %.5g, region bias %.5g\n", r.spp, r.seconds,
                   r.rmse, r.relMse, r.regionBias);
  });
  outputs.writeText(csv, convergeCsv(rows));
  outputs.writeText(svg, convergeSvg(rows, std::filesystem::path(a.scene).filename().string() + ", --method " + a.method));
  outputs.commit();
  if (!a.quiet) std::fprintf(stderr, "rayes: wrote %s and %s\n", csv.c_str(), svg.c_str());
  return 0;
}

}  // namespace rayes
