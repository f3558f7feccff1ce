// `rayes render`: one scene to an image, with its statistics and report; every output all or
// nothing (OutputSet).
#include <cstdio>
#include <filesystem>
#include "app/commands.h"
#include "app/html_report.h"
#include "app/image_io.h"
#include "app/output_set.h"
#include "app/progress.h"
#include "app/renderer.h"
#include "app/stats_json.h"
#include "core/error.h"
#include "core/parallel.h"
#include "core/timer.h"

namespace rayes {
namespace {

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}
bool endsWithPng(const std::string& path) { return lowerExtension(path) == ".png"; }

// -o takes the names of what can be written, and nothing else: a.jpg must not become an EXR.
void checkOutputName(const std::string& out) {
  const std::string ext = lowerExtension(out);
  if (ext != ".exr" && ext != ".png" && ext != ".film")
    throw InputError("-o", "", "'" + out + "': " + (ext.empty() ? std::string("no extension") : "unknown extension '" + ext + "'") +
                                   "; an output is .exr (the image, a PNG preview beside it), .png (the preview "
                                   "alone) or .film (the film's state, for rayes merge)");
}

}  // namespace

int runRender(const RenderArgs& a) {
  const auto wall0 = Clock::now();
  if (!a.out.empty()) checkOutputName(a.out);
  RenderOptions options = checkedOptions(a);
  ThreadLimit limit(a.threads);
  ProgressReporter progress(a.quiet ? ProgressMode::None : progressModeFromName(a.progress));
  ProgressState& live = liveProgress();
  live.setPhase(Phase::LoadingScene);
  Scene scene = preparedScene(a);
  const double loadSeconds = secondsSince(wall0);
  // Not silenced by --quiet, like the precision warning below: the render would not show why.
  for (const std::string& w : scene.warnings) std::fprintf(stderr, "rayes: warning: %s\n", w.c_str());
  if (!a.reference.empty()) {
    options.reference = imageOfSceneSize(a.reference, scene, "reference");
    options.progressive = true;  // the error curve has one point per pass
  }
  // -o NAME.png asks for the preview alone; any other name gets the EXR and the preview beside it.
  const std::string stem = a.scene == kStdinScene ? "stdin" : std::filesystem::path(a.scene).stem().string();
  const std::string out = a.out.empty() ? "out/" + stem + ".exr" : a.out;
  const bool pngOnly = endsWithPng(out);
  const std::string exr = pngOnly ? "" : out;
  const std::string png = pngOnly ? out : std::filesystem::path(out).replace_extension(".png").string();
  OutputSet outputs;
  if (a.scene != kStdinScene) outputs.addInput(a.scene);
  outputs.addInput(a.reference);
  if (!exr.empty()) outputs.add(exr, "image");
  outputs.add(png, "preview");
  if (!a.stats.empty()) outputs.add(a.stats, "stats");
  if (!a.report.empty()) outputs.add(a.report, "report");

  live.setPhase(Phase::BuildingTopLevel);
  Renderer renderer(scene, options);
  // Not silenced by --quiet: a scene far from the origin for its size is the one case where
  // the image can differ from the same scene near the origin with no other sign.
  if (const SceneFeatures& f = renderer.stats().features; f.lowPrecisionLeaves > 0)
    std::fprintf(stderr,
                 "rayes: warning: %s: %llu of %zu leaves lie far from the origin for their size (float spacing up to "
                 "%.3g of a leaf, above 2^-16): the image may differ from the same scene near the origin by more "
                 "than rounding (docs/design.md, \"Precision\"); move the scene nearer the origin\n",
                 a.scene.c_str(), (unsigned long long)f.lowPrecisionLeaves, scene.leaves.size(), f.coarsestRelativeSpacing);
  live.samplesTotal.store(scene.samplesPerPixel);
  live.pathsTotal.store(uint64_t(scene.width) * uint64_t(scene.height) * uint64_t(scene.samplesPerPixel));
  const Film film = renderer.render([&](uint64_t d, uint64_t t, int s) { progress.update(d, t, s); });
  live.setPhase(Phase::Writing);

  if (!exr.empty()) outputs.write(exr, [&](const std::string& tmp) { writeExr(tmp, film); });
  outputs.write(png, [&](const std::string& tmp) { writePngPreview(tmp, film); });
  if (!a.stats.empty() || !a.report.empty()) {
    const RunInfo run{a.scene, ThreadLimit::active(), scene.width, scene.height, scene.samplesPerPixel, loadSeconds,
                      secondsSince(wall0)};
    const auto stats = statsToJson(scene, options, renderer.stats(), run);
    if (!a.stats.empty()) outputs.writeText(a.stats, stats.dump(2) + "\n");
    if (!a.report.empty()) {
      const auto reportDir = std::filesystem::path(a.report).parent_path();
      const auto rel = std::filesystem::proximate(png, reportDir.empty() ? std::filesystem::path(".") : reportDir);
      outputs.writeText(a.report, htmlReport(stats, rel.string()));
    }
  }
  outputs.commit();
  progress.finish();
  if (!a.quiet) {
    const std::string what = exr.empty() ? png : exr + " and " + png;
    std::fprintf(stderr, "rayes: wrote %s (%.2fs)\n", what.c_str(), secondsSince(wall0));
  }
  return 0;
}

}  // namespace rayes
