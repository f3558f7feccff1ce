// `rayes render`: one scene to an image, with its statistics and report; every output all or
// nothing (OutputSet). Batch jobs (docs/batch-and-farm.md): --crop and --part choose the
// pixels or the share of the work, -o NAME.film writes the film's sums for `rayes merge`,
// --checkpoint / --time-limit make the render resumable (exit code 4 when it stopped with a
// checkpoint written), --resume continues one.
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include "app/batch_job.h"
#include "app/checkpoint.h"
#include "app/commands.h"
#include "app/film_file.h"
#include "app/image_io.h"
#include "app/interrupt.h"
#include "app/output_set.h"
#include "app/progress.h"
#include "app/renderer.h"
#include "app/report_page.h"
#include "app/stats_json.h"
#include "core/error.h"
#include "core/parallel.h"
#include "core/text_file.h"
#include "core/timer.h"

namespace rayes {

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// -o takes the names of what can be written, and nothing else: a.jpg must not become an EXR.
void checkOutputName(const std::string& out) {
  const std::string ext = lowerExtension(out);
  if (ext != ".exr" && ext != ".png" && ext != ".film")
    throw InputError("-o", "", "'" + out + "': " + (ext.empty() ? std::string("no extension") : "unknown extension '" + ext + "'") +
                                   "; an output is .exr (the image, a PNG preview beside it), .png (the preview "
                                   "alone) or .film (the film's state, for rayes merge)");
}

namespace {

// `path` as seen from the folder of `statsFile` (how rayes report finds the image).
std::string pathFromStatsFolder(const std::string& path, const std::string& statsFile) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path from = fs::absolute(fs::path(statsFile), ec).parent_path();
  const fs::path rel = fs::absolute(fs::path(path), ec).lexically_relative(from);
  return ec || rel.empty() ? fs::absolute(fs::path(path), ec).string() : rel.string();
}

std::string secondsText(double s) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", s);
  return text;
}

}  // namespace

int runRender(const RenderArgs& a) {
  const auto wall0 = Clock::now();
  if (!a.out.empty()) checkOutputName(a.out);
  RenderOptions options = checkedOptions(a);
  // Batch jobs: what is checked without the scene.
  if (!a.part.empty()) parsePart(a.part, options.part, options.parts);
  if (!(a.checkpointEvery > 0) || !std::isfinite(a.checkpointEvery))
    throw InputError("--checkpoint-every", "", "must be a positive number of seconds");
  if (a.timeLimit && (!(*a.timeLimit > 0) || !std::isfinite(*a.timeLimit)))
    throw InputError("--time-limit", "", "must be a positive number of seconds");
  // -o NAME.png asks for the preview alone, -o NAME.film for the film's sums alone (a part of a
  // split, for rayes merge); any other name gets the EXR and the preview beside it.
  const std::string stem = a.scene == kStdinScene ? "stdin" : std::filesystem::path(a.scene).stem().string();
  const std::string out = a.out.empty() ? "out/" + stem + ".exr" : a.out;
  const std::string ext = lowerExtension(out);
  const bool filmOut = ext == ".film", pngOnly = ext == ".png";
  const std::string exr = pngOnly || filmOut ? "" : out;
  const std::string png = filmOut ? "" : pngOnly ? out : std::filesystem::path(out).replace_extension(".png").string();
  if (options.parts > 1 && !filmOut)
    throw InputError("--part", "", "a part is a partial film: give -o NAME.film (rayes merge makes the image of the parts)");
  if (a.costLayers && exr.empty())
    throw InputError("--cost-layers", "", "the cost layers are layers of the EXR: give -o NAME.exr (not " +
                                              (filmOut ? std::string("a .film") : std::string("a .png")) + ")");
  if (a.costLayers && a.resume)
    throw InputError("--cost-layers", "", "a resumed render would lack the cost of the batches before its checkpoint: "
                                          "render without --resume");
  const std::string checkpointPath =
      !a.checkpoint.empty() ? a.checkpoint : a.timeLimit || a.resume ? defaultCheckpointPath(out) : "";
  if (!checkpointPath.empty() &&
      std::filesystem::path(checkpointPath).lexically_normal() == std::filesystem::path(out).lexically_normal())
    throw InputError(out, "", "the output and the checkpoint are the same file");
  // A resumable render stops at a signal with a checkpoint; any other dies of it, cleaning up.
  const bool resumable = !checkpointPath.empty();
  // A film's fingerprint holds the scene file's bytes, read again by name.
  if (a.scene == kStdinScene && (resumable || filmOut))
    throw InputError(kStdinSceneName, "", "a scene read from standard input cannot be checkpointed or written as a "
                                          ".film (its fingerprint reads the scene file again): give the scene's file");
  setStopOnSignal(resumable);
  options.frequentBatches = resumable;
  // A preview alone reads no AOV; a checkpoint keeps them for whatever output resumes it.
  options.firstHitAovs = !pngOnly || resumable;
  ThreadLimit limit(a.threads);
  ProgressReporter progress(a.quiet ? ProgressMode::None : progressModeFromName(a.progress));
  ProgressState& live = liveProgress();
  live.setPhase(Phase::LoadingScene);
  Scene scene = preparedScene(a);
  const double loadSeconds = secondsSince(wall0);
  // Not silenced by --quiet, like the precision warning below: the render would not show why.
  for (const std::string& w : scene.warnings) std::fprintf(stderr, "rayes: warning: %s\n", w.c_str());
  if (!a.crop.empty()) options.crop = parseCrop(a.crop, scene.width, scene.height);
  if (!a.reference.empty()) {
    options.reference = imageOfSceneSize(a.reference, scene, "reference image");
    options.progressive = true;  // the error curve has one point per pass
  }
  auto outputs = std::make_unique<OutputSet>();
  if (a.scene != kStdinScene) outputs->addInput(a.scene);
  outputs->addInput(a.reference);
  outputs->addInput(checkpointPath);
  if (filmOut) outputs->add(out, "film");
  if (!exr.empty()) outputs->add(exr, "image");
  if (!png.empty()) outputs->add(png, "preview");
  if (!a.stats.empty()) outputs->add(a.stats, "stats");
  if (!a.report.empty()) outputs->add(a.report, "report");
  std::unique_ptr<Checkpointer> checkpoint;
  if (resumable) checkpoint = std::make_unique<Checkpointer>(checkpointPath, a.checkpointEvery);

  live.setPhase(Phase::BuildingTopLevel);
  Renderer renderer(scene, options);
  // Not silenced by --quiet: a scene far from the camera for its size is the one case where
  // the image can differ from the same scene near the camera with no other sign.
  if (const SceneFeatures& f = renderer.stats().features; f.lowPrecisionLeaves > 0)
    std::fprintf(stderr,
                 "rayes: warning: %s: %llu of %zu leaves lie far from the camera for their size (float spacing up to "
                 "%.3g of a leaf, above 2^-16 of it and 2^-8 of a pixel's footprint there): the image may differ "
                 "from the same view nearer the camera by more than rounding (docs/design.md, \"Precision\"); "
                 "move the camera nearer or scale the scene up\n",
                 a.scene.c_str(), (unsigned long long)f.lowPrecisionLeaves, scene.leaves.size(), f.coarsestRelativeSpacing);
  const FilmFileHeader header =
      resumable || filmOut ? filmHeader("film", a.scene, scene, options, renderer) : FilmFileHeader{};
  bool resumedFrom = false;
  if (checkpoint) {
    checkpoint->describe(header);
    if (a.resume) {
      std::error_code ec;
      if (!std::filesystem::exists(checkpointPath, ec)) {
        if (!a.quiet) std::fprintf(stderr, "rayes: no checkpoint %s yet: rendering from the start\n", checkpointPath.c_str());
      } else {
        FilmFile saved = readFilmFile(checkpointPath);
        if (saved.header.kind != "checkpoint")
          throw InputError(checkpointPath, "", "cannot resume from it: a " + saved.header.kind + " film, not a checkpoint");
        checkSameRender(checkpointPath, saved.header, header, "resume from", "this render");
        renderer.resume(std::move(saved.film),
                        Renderer::Position{saved.header.pass, saved.header.next, saved.header.blockPixels,
                                           saved.header.firstHitsEnd});
        checkpoint->resumed();
        resumedFrom = true;
      }
    }
  }

  live.samplesTotal.store(scene.samplesPerPixel);
  uint64_t done = 0, total = 0;
  Renderer::Control control;
  const double timeLimit = a.timeLimit.value_or(0);
  control.stop = [&] { return stopRequested() || (timeLimit > 0 && secondsSince(wall0) >= timeLimit); };
  if (checkpoint) control.batchDone = [&](const Film& f, const Renderer::Position& at) { checkpoint->batchDone(f, at); };
  const Film film = renderer.render(
      [&](uint64_t d, uint64_t t, int s) {
        done = d;
        total = t;
        progress.update(d, t, s);
      },
      control);
  live.setPhase(Phase::Writing);

  if (renderer.interrupted()) {
    const int sig = stopSignal();
    const std::string why = sig ? std::string("stopped by ") + (sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "SIGHUP")
                                : "the time limit of " + secondsText(timeLimit) + " s is reached";
    const std::string failure = checkpoint->writeNow(film, renderer.position());
    outputs.reset();  // no output of an unfinished render is left, nor a folder made for one
    if (checkpoint->valid()) {
      if (!failure.empty())
        std::fprintf(stderr, "rayes: cannot write a newer checkpoint to %s: %s; the previous one is kept\n",
                     checkpointPath.c_str(), failure.c_str());
      std::fprintf(stderr, "rayes: %s: the checkpoint %s holds %.1f %% of the render; run the same command with --resume to finish it\n",
                   why.c_str(), checkpointPath.c_str(), total ? 100.0 * double(done) / double(total) : 0.0);
      return 4;
    }
    checkpoint.reset();
    if (sig) {
      std::fprintf(stderr, "rayes: %s: cannot write the checkpoint %s: %s\n", why.c_str(), checkpointPath.c_str(), failure.c_str());
      setStopOnSignal(false);
      std::raise(sig);  // dies of it as an unhandled signal would
    }
    throw ResourceError("--checkpoint", why + ", but the checkpoint " + checkpointPath + " cannot be written: " + failure);
  }

  const bool wantStats = !a.stats.empty() || !a.report.empty() || filmOut;
  nlohmann::json stats;
  if (wantStats) {
    const RunInfo run{a.scene, ThreadLimit::active(), scene.width, scene.height, scene.samplesPerPixel, loadSeconds,
                      secondsSince(wall0)};
    stats = statsToJson(scene, options, renderer.stats(), run);
    if (options.costLayers) stats["cost_layers"]["image"] = pathFromStatsFolder(exr, a.stats.empty() ? a.report : a.stats);
    if (checkpoint)
      stats["checkpoints"] = {{"file", checkpointPath}, {"written", checkpoint->written()},
                              {"time_s", checkpoint->seconds()}, {"resumed", resumedFrom}};
  }
  if (filmOut) {
    FilmFileHeader h = header;
    h.kind = options.parts > 1 ? "part" : "film";
    h.complete = true;
    h.pass = renderer.position().pass;
    h.stats = stats;
    outputs->write(out, [&](const std::string& tmp) { writeFilmFile(tmp, h, film); });
  }
  if (!exr.empty()) outputs->write(exr, [&](const std::string& tmp) { writeExr(tmp, film, renderer.pixelCost()); });
  std::string previewPng;  // the report shows the preview inline: a page with no file beside it
  if (!png.empty())
    outputs->write(png, [&](const std::string& tmp) {
      writePngPreview(tmp, film);
      if (!a.report.empty()) previewPng = readTextFile(tmp, "the preview");
    });
  if (!a.stats.empty()) outputs->writeText(a.stats, stats.dump(2) + "\n");
  if (!a.report.empty()) {
    checkStats(stats, a.stats.empty() ? a.report : a.stats);  // what this program writes, it can draw
    std::optional<CostPictures> pictures;
    if (const PixelCost* cost = renderer.pixelCost())
      pictures = CostPictures{film.width(), film.height(), film.beautyRgba(), film.lod(), cost->dicings(), cost->seconds(), exr};
    outputs->writeText(a.report, reportPage({StatsFile{a.stats.empty() ? a.scene : a.stats, stats}}, previewPng,
                                            pictures ? &*pictures : nullptr));
  }
  outputs->commit();
  progress.finish();
  // The render is whole: its checkpoint is of no more use.
  if (checkpoint) checkpoint->removeFile();
  if (!a.quiet) {
    const std::string what = filmOut ? out : exr.empty() ? png : exr + " and " + png;
    std::fprintf(stderr, "rayes: wrote %s (%.2fs)\n", what.c_str(), secondsSince(wall0));
  }
  return 0;
}

}  // namespace rayes
