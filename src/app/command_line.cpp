#include "app/command_line.h"
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <CLI/CLI.hpp>
#include "app/html_report.h"
#include "app/image_io.h"
#include "app/progress.h"
#include "app/renderer.h"
#include "app/stats_json.h"
#include "core/error.h"
#include "core/memory.h"
#include "core/parallel.h"
#include "scene/scene_loader.h"

namespace rayes {
namespace {

// "1G", "512M", "64K" or plain bytes, for the option `option`.
size_t parseBytes(const std::string& s, const char* option) {
  size_t pos = 0;
  double v = 0;
  try {
    v = std::stod(s, &pos);
  } catch (...) {
    throw InputError(option, "", "expected a byte count such as 1G, 512M or 1048576, got '" + s + "'");
  }
  std::string suffix = s.substr(pos);
  double mul = 1;
  if (suffix == "K" || suffix == "k" || suffix == "KiB") mul = 1024.0;
  else if (suffix == "M" || suffix == "m" || suffix == "MiB") mul = 1024.0 * 1024;
  else if (suffix == "G" || suffix == "g" || suffix == "GiB") mul = 1024.0 * 1024 * 1024;
  else if (!suffix.empty())
    throw InputError(option, "", "unknown unit '" + suffix + "' (use K, M or G)");
  if (!(v > 0) || v * mul > 1e15) throw InputError(option, "", "must be a positive byte count");
  return size_t(v * mul);
}

void ensureParentDir(const std::string& path, const char* what) {
  const auto dir = std::filesystem::path(path).parent_path();
  if (dir.empty()) return;
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir))
    throw InputError(path, "", std::string("cannot create the directory for ") + what);
}

struct RenderArgs {
  std::string scene, out, stats, report, reference, res, rayMemory = "1G", lod = "per-ray", traceMode = "sorted",
              method = "pt";
  std::string engine = "rayes", embreeLod, memoryLimit;
  int spp = 0, threads = 0, maxLod = 10, seed = -1;
  bool quiet = false;
};

int render(const RenderArgs& a) {
  const auto wall0 = Clock::now();
  ThreadLimit limit(a.threads);
  Scene scene = loadScene(a.scene);
  const double loadSeconds = secondsSince(wall0);
  if (a.spp != 0) {
    if (a.spp < 0) throw InputError("--spp", "", "samples per pixel must be positive");
    scene.samplesPerPixel = a.spp;
  }
  if (!a.res.empty()) {
    int w = 0, h = 0;
    char x = 0, extra = 0;
    if (std::sscanf(a.res.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') || w <= 0 || h <= 0)
      throw InputError("--res", "", "expected WIDTHxHEIGHT with positive numbers, got '" + a.res + "'");
    scene.width = w;
    scene.height = h;
  }
  if (a.seed >= 0) scene.integrator.seed = uint64_t(a.seed);
  RenderOptions options;
  options.method = integratorMethodFromName(a.method, "--method");
  if (a.maxLod < 0 || a.maxLod > 12) throw InputError("--max-lod", "", "must be in [0, 12]");
  options.maxLod = a.maxLod;
  options.lod = a.lod == "density" ? LodRule::Density : LodRule::PerRay;
  options.sortByLeaf = a.traceMode == "sorted";
  options.rayMemoryBytes = parseBytes(a.rayMemory, "--ray-memory");
  options.engine = a.engine == "embree" ? EngineKind::Embree : EngineKind::Rayes;
  if (!a.embreeLod.empty() && options.engine != EngineKind::Embree)
    throw InputError("--embree-lod", "", "only applies to --engine embree");
  options.embreeAutoLod = a.embreeLod == "auto";
  // The default limit keeps a fifth of the machine for everything else.
  options.memoryLimitBytes = a.memoryLimit.empty() ? size_t(physicalMemoryBytes() / 5 * 4)
                                                   : parseBytes(a.memoryLimit, "--memory-limit");
  if (!a.reference.empty()) {
    int w = 0, h = 0;
    options.reference = readExrRgb(a.reference, w, h);
    if (w != scene.width || h != scene.height)
      throw InputError(a.reference, "", "reference is " + std::to_string(w) + "x" + std::to_string(h) +
                                            ", the render " + std::to_string(scene.width) + "x" +
                                            std::to_string(scene.height));
  }
  std::string out = a.out;
  if (out.empty()) out = "out/" + std::filesystem::path(a.scene).stem().string() + ".exr";
  const std::string png = std::filesystem::path(out).replace_extension(".png").string();
  ensureParentDir(out, "the image");
  if (!a.stats.empty()) ensureParentDir(a.stats, "the stats");
  if (!a.report.empty()) ensureParentDir(a.report, "the report");

  Renderer renderer(scene, options);
  ProgressReporter progress(!a.quiet, scene.samplesPerPixel);
  const Film film = renderer.render([&](uint64_t d, uint64_t t, int s) { progress.update(d, t, s); });
  progress.finish();

  writeExr(out, film);
  writePngPreview(png, film);
  if (!a.stats.empty() || !a.report.empty()) {
    const RunInfo run{a.scene, ThreadLimit::active(), scene.width, scene.height, scene.samplesPerPixel, loadSeconds,
                      secondsSince(wall0)};
    const auto stats = statsToJson(scene, options, renderer.stats(), run);
    if (!a.stats.empty()) writeTextAtomically(a.stats, stats.dump(2) + "\n");
    if (!a.report.empty()) {
      const auto rel = std::filesystem::proximate(png, std::filesystem::path(a.report).parent_path().empty()
                                                           ? std::filesystem::path(".")
                                                           : std::filesystem::path(a.report).parent_path());
      writeTextAtomically(a.report, htmlReport(stats, rel.string()));
    }
  }
  if (!a.quiet) std::fprintf(stderr, "rayes: wrote %s and %s (%.2fs)\n", out.c_str(), png.c_str(), secondsSince(wall0));
  return 0;
}

}  // namespace

int runCommandLine(int argc, char** argv) {
  CLI::App app{"rayes: a streaming micropolygon ray tracer. Rays are traced in generations, sorted by the\n"
               "patch they may hit, and every patch is diced on demand into micropolygons."};
  app.require_subcommand(1);
  RenderArgs a;
  CLI::App* r = app.add_subcommand("render", "render a scene file (JSON, docs/scene-format.md)");
  r->add_option("scene", a.scene, "the scene file")->required();
  r->add_option("-o,--output", a.out, "output OpenEXR (beauty RGBA, depth, normal, lod); a PNG preview is written "
                                      "beside it (default: out/<scene>.exr)");
  r->add_option("--spp", a.spp, "samples per pixel (default: the scene's)");
  r->add_option("--res", a.res, "resolution WIDTHxHEIGHT (default: the scene's)");
  r->add_option("--threads", a.threads, "worker threads (default: all cores)");
  r->add_option("--stats", a.stats, "write render statistics as JSON to this file (docs/stats.md)");
  r->add_option("--report", a.report, "write a readable HTML report of the same statistics: time and memory "
                                      "breakdown, dicing per generation, what was used and skipped");
  r->add_option("--max-lod", a.maxLod, "finest dicing level m: a patch has at most 4^m micropolygons (0..12, default 10)");
  r->add_option("--ray-memory", a.rayMemory,
                "memory for ray, path and candidate buffers, e.g. 512M or 2G (default 1G); a smaller budget "
                "means more batches and iterations, never a different image");
  r->add_option("--lod", a.lod, "level-of-detail rule: per-ray (default; footprint of each ray, order independent) "
                                "or density (the thesis's 4^m >= R/spp; the image then depends on batching)")
      ->check(CLI::IsMember({"per-ray", "density"}));
  r->add_option("--trace-mode", a.traceMode, "sorted (default: the reorder pipeline) or alone (debug: every ray "
                                             "traced by itself, each patch diced per ray; slow)")
      ->check(CLI::IsMember({"sorted", "alone"}));
  r->add_option("--method", a.method, "integrator: pt (default: path tracing with next-event estimation and MIS) or "
                                      "lt (light tracing: paths from the lights, every vertex connected to the "
                                      "camera; the reference for caustics; lights at infinity seen directly are "
                                      "missing)");
  r->add_option("--engine", a.engine, "ray engine: rayes (default; sorted rays, patches diced on demand) or embree "
                                      "(the peer: every patch diced up front into Embree grids)")
      ->check(CLI::IsMember({"rayes", "embree"}));
  r->add_option("--embree-lod", a.embreeLod, "with --engine embree: fixed (default; every patch at --max-lod) or "
                                             "auto (per patch, the finest level a camera ray's footprint needs)")
      ->check(CLI::IsMember({"fixed", "auto"}));
  r->add_option("--memory-limit", a.memoryLimit, "with --engine embree: refuse, before allocating, a tessellation "
                                                 "estimated larger than this, e.g. 8G (default: 80% of physical memory)");
  r->add_option("--reference", a.reference, "reference OpenEXR of the same resolution: the stats then hold the "
                                            "RMSE after every pass against time (error_vs_time)");
  r->add_option("--seed", a.seed, "random seed (default: the scene's, else 0)");
  r->add_flag("-q,--quiet", a.quiet, "no progress output");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "rayes: " << e.what() << "\n(run 'rayes render --help' for the options)\n";
    return 2;
  }
  try {
    if (r->parsed()) return render(a);
  } catch (const InputError& e) {
    std::cerr << "rayes: " << e.message() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "rayes: internal error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace rayes
