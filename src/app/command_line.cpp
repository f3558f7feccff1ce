#include "app/command_line.h"
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <CLI/CLI.hpp>
#include "app/converge.h"
#include "app/html_report.h"
#include "app/image_io.h"
#include "app/output_set.h"
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

// WIDTHxHEIGHT, each positive, at most 2^28 pixels in all (64-bit arithmetic: 65536x65536
// must not wrap to 0).
void parseResolution(const std::string& text, int& width, int& height) {
  const auto bad = [&](const std::string& why) { throw InputError("--res", "", why + ", got '" + text + "'"); };
  const size_t x = text.find_first_of("xX");
  if (x == std::string::npos) bad("expected WIDTHxHEIGHT");
  int64_t v[2] = {0, 0};
  const std::string part[2] = {text.substr(0, x), text.substr(x + 1)};
  for (int k = 0; k < 2; ++k) {
    const auto [p, ec] = std::from_chars(part[k].data(), part[k].data() + part[k].size(), v[k]);
    if (ec == std::errc::result_out_of_range) bad("width and height must be at most 2^28");
    if (part[k].empty() || ec != std::errc() || p != part[k].data() + part[k].size())
      bad("expected WIDTHxHEIGHT with whole numbers");
    if (v[k] <= 0) bad("width and height must be positive");
    if (v[k] > (int64_t(1) << 28)) bad("width and height must be at most 2^28");
  }
  if (v[0] * v[1] > (int64_t(1) << 28)) bad("more than 2^28 pixels");
  width = int(v[0]);
  height = int(v[1]);
}

struct RenderArgs {
  std::string scene, out, stats, report, reference, res, rayMemory, lod = "per-ray", traceMode = "sorted",
              method = "pt", causticPaths = "all";
  std::string engine = "rayes", embreeLod, memoryLimit, beamMemory = "1G", gridCache;
  int beamResolution = 128, beamDepth = 4, beamSplitDepth = 4, beamAreaSamples = 2;
  std::optional<int> spp;
  int64_t photons = 20000;
  int photonK = 32;
  float laterGathers = kLaterGatherProbability;
  float photonRadius = 0, photonAlpha = 2.0f / 3.0f;
  std::optional<int64_t> seed, diceCache;
  int lodBias = 0;
  int candidatesPerRay = TraceSettings::kDefaultCandidatesPerRay;
  int threads = 0, maxLod = 10;
  bool quiet = false, progressive = false;
  // converge
  double beamLobeCells = 2;
  double budget = 0, beamGrowth = 1.4142135623730951;
  std::string region, mask, errorMask, svg;
  std::vector<std::string> references;
};

// Checks every option that does not need the scene, so that a bad option costs no loading.
RenderOptions checkedOptions(const RenderArgs& a) {
  if (a.spp && (*a.spp < 1 || *a.spp > (1 << 20))) throw InputError("--spp", "", "must be in [1, 2^20]");
  if (a.threads < 0 || a.threads > 4096) throw InputError("--threads", "", "must be in [0, 4096] (0: all cores)");
  if (a.seed && (*a.seed < 0 || *a.seed > (int64_t(1) << 62)))
    throw InputError("--seed", "", "must be in [0, 2^62]");
  RenderOptions options;
  options.method = integratorMethodFromName(a.method, "--method");
  options.integrator.causticPaths = causticPathsFromName(a.causticPaths, "--caustic-paths");
  const bool causticMethod = options.method == IntegratorMethod::LightBeams ||
                             options.method == IntegratorMethod::PhotonMapping ||
                             options.method == IntegratorMethod::ProgressivePhotonMapping;
  if (causticMethod && options.integrator.causticPaths == CausticPaths::Without)
    throw InputError("--caustic-paths", "", "lbt, pm and ppm take all or only: without their caustic estimate they "
                                            "are pt --caustic-paths without");
  if (a.photons < 1 || a.photons > (int64_t(1) << 32)) throw InputError("--photons", "", "must be in [1, 2^32]");
  if (a.photonK < 1 || a.photonK > 4096) throw InputError("--photon-k", "", "must be in [1, 4096]");
  if (!(a.laterGathers >= 1.0f / 64 && a.laterGathers <= 1))
    throw InputError("--later-gathers", "", "must be in [1/64, 1] (the probability of a caustic estimate after a path's first diffuse vertex)");
  if (!(a.photonRadius >= 0) || !std::isfinite(a.photonRadius))
    throw InputError("--photon-radius", "", "must be a finite radius >= 0 (0: chosen from the first photon map)");
  if (!(a.photonAlpha > 0 && a.photonAlpha < 1))
    throw InputError("--photon-alpha", "", "must lie in (0, 1): the radius shrinks as r² (i + alpha) / (i + 1)");
  options.integrator.photonsPerSample = uint64_t(a.photons);
  options.integrator.photonNeighbours = a.photonK;
  options.integrator.laterGatherProbability = a.laterGathers;
  options.integrator.photonRadius = a.photonRadius;
  options.integrator.photonAlpha = a.photonAlpha;
  if (a.maxLod < 0 || a.maxLod > 12) throw InputError("--max-lod", "", "must be in [0, 12]");
  options.maxLod = a.maxLod;
  if (a.beamResolution < 1 || a.beamResolution > 4096) throw InputError("--beam-resolution", "", "must be in [1, 4096]");
  if (a.beamDepth < 1 || a.beamDepth > 64) throw InputError("--beam-depth", "", "must be in [1, 64]");
  options.beams.resolution = a.beamResolution;
  options.beams.maxDepth = a.beamDepth;
  if (a.beamSplitDepth < 0 || a.beamSplitDepth > 12) throw InputError("--beam-split-depth", "", "must be in [0, 12]");
  options.beams.splitDepth = a.beamSplitDepth;
  if (a.beamAreaSamples < 0 || a.beamAreaSamples > 64) throw InputError("--beam-area-samples", "", "must be in [0, 64]");
  options.beams.areaSamples = a.beamAreaSamples;
  options.beams.memoryBytes = parseBytes(a.beamMemory, "--beam-memory");
  if (!(a.beamLobeCells >= 0 && a.beamLobeCells <= 64))
    throw InputError("--beam-lobe-cells", "", "must lie in [0, 64] (a glossy beam's width in lobe widths sigma; 0: keep --beam-resolution)");
  options.beams.lobeCells = a.beamLobeCells;
  options.lod = a.lod == "density" ? LodRule::Density : a.lod == "fixed" ? LodRule::Fixed : LodRule::PerRay;
  options.sortByLeaf = a.traceMode == "sorted";
  if (!a.rayMemory.empty()) options.rayMemoryBytes = parseBytes(a.rayMemory, "--ray-memory");
  if (!a.gridCache.empty()) options.gridCacheBytes = a.gridCache == "0" ? 0 : parseBytes(a.gridCache, "--grid-cache");
  if (a.candidatesPerRay < 1 || a.candidatesPerRay > 1000)
    throw InputError("--candidates-per-ray", "", "must be a whole number in [1, 1000]");
  options.candidatesPerRay = a.candidatesPerRay;
  options.progressive = a.progressive;
  options.engine = a.engine == "embree" ? EngineKind::Embree : EngineKind::Rayes;
  if (!a.embreeLod.empty() && options.engine != EngineKind::Embree)
    throw InputError("--embree-lod", "", "only applies to --engine embree");
  options.embreeAutoLod = a.embreeLod == "auto";
  if (a.diceCache) {
    if (*a.diceCache < 1 || *a.diceCache > (int64_t(1) << 32))
      throw InputError("--dice-cache", "", "must be a whole number of entries in [1, 2^32]");
    if (options.engine == EngineKind::Embree) throw InputError("--dice-cache", "", "does not apply to --engine embree");
    if (!options.sortByLeaf)
      throw InputError("--dice-cache", "", "traces every ray alone already; leave out --trace-mode alone");
    options.diceCacheEntries = size_t(*a.diceCache);
  }
  if (a.lodBias < -TraceSettings::kMaxLodBias || a.lodBias > TraceSettings::kMaxLodBias)
    throw InputError("--lod-bias", "", "must be a whole number of levels in [-12, 12]");
  if (a.lodBias != 0 && options.engine == EngineKind::Embree)
    throw InputError("--lod-bias", "", "does not apply to --engine embree");
  options.lodBias = a.lodBias;
  // The default limit keeps a fifth of the machine for everything else.
  options.memoryLimitBytes = a.memoryLimit.empty() ? size_t(physicalMemoryBytes() / 5 * 4)
                                                   : parseBytes(a.memoryLimit, "--memory-limit");
  return options;
}

bool endsWithPng(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".png";
}

// The scene with the command line's resolution, samples and seed.
Scene preparedScene(const RenderArgs& a) {
  int width = 0, height = 0;
  if (!a.res.empty()) parseResolution(a.res, width, height);
  Scene scene = loadScene(a.scene);
  if (a.spp) scene.samplesPerPixel = *a.spp;
  if (!a.res.empty()) {
    scene.width = width;
    scene.height = height;
  }
  if (a.seed) scene.integrator.seed = uint64_t(*a.seed);
  return scene;
}

// An RGB image of the scene's size from `path`, for `what` (a reference, a mask).
std::vector<float> imageOfSceneSize(const std::string& path, const Scene& scene, const char* what) {
  int w = 0, h = 0;
  std::vector<float> rgb = readExrRgb(path, w, h);
  if (w != scene.width || h != scene.height)
    throw InputError(path, "", std::string(what) + " is " + std::to_string(w) + "x" + std::to_string(h) +
                                   ", the render " + std::to_string(scene.width) + "x" + std::to_string(scene.height));
  return rgb;
}

int render(const RenderArgs& a) {
  const auto wall0 = Clock::now();
  RenderOptions options = checkedOptions(a);
  ThreadLimit limit(a.threads);
  Scene scene = preparedScene(a);
  const double loadSeconds = secondsSince(wall0);
  if (!a.reference.empty()) {
    options.reference = imageOfSceneSize(a.reference, scene, "reference");
    options.progressive = true;  // the error curve has one point per pass
  }
  // -o NAME.png asks for the preview alone; any other name gets the EXR and the preview beside it.
  const std::string out = a.out.empty() ? "out/" + std::filesystem::path(a.scene).stem().string() + ".exr" : a.out;
  const bool pngOnly = endsWithPng(out);
  const std::string exr = pngOnly ? "" : out;
  const std::string png = pngOnly ? out : std::filesystem::path(out).replace_extension(".png").string();
  OutputSet outputs;
  const auto claim = [&](const std::string& target, const char* what) {
    std::error_code ec;
    for (const std::string& input : {a.scene, a.reference})
      if (!input.empty() && std::filesystem::equivalent(target, input, ec))
        throw InputError(target, "", std::string("the ") + what + " would overwrite an input of this run");
    outputs.add(target, what);
  };
  if (!exr.empty()) claim(exr, "image");
  claim(png, "preview");
  if (!a.stats.empty()) claim(a.stats, "stats");
  if (!a.report.empty()) claim(a.report, "report");

  Renderer renderer(scene, options);
  // Not silenced by --quiet: a scene far from the origin for its size is the one case where
  // the image can differ from the same scene near the origin with no other sign.
  if (const SceneFeatures& f = renderer.stats().features; f.lowPrecisionLeaves > 0)
    std::fprintf(stderr,
                 "rayes: warning: %s: %llu of %zu leaves lie far from the origin for their size (float spacing up to "
                 "%.3g of a leaf, above 2^-16): the image may differ from the same scene near the origin by more "
                 "than rounding (docs/design.md, \"Precision\"); move the scene nearer the origin\n",
                 a.scene.c_str(), (unsigned long long)f.lowPrecisionLeaves, scene.leaves.size(), f.coarsestRelativeSpacing);
  ProgressReporter progress(!a.quiet, scene.samplesPerPixel);
  const Film film = renderer.render([&](uint64_t d, uint64_t t, int s) { progress.update(d, t, s); });
  progress.finish();

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
  if (!a.quiet) {
    const std::string what = exr.empty() ? png : exr + " and " + png;
    std::fprintf(stderr, "rayes: wrote %s (%.2fs)\n", what.c_str(), secondsSince(wall0));
  }
  return 0;
}

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

int runConverge(const RenderArgs& a) {
  RenderOptions options = checkedOptions(a);
  if (!(a.budget > 0) || !std::isfinite(a.budget)) throw InputError("--budget", "", "must be a positive number of seconds");
  if (!a.region.empty() && !a.mask.empty()) throw InputError("--mask", "", "give --region or --mask, not both");
  if (!(a.beamGrowth >= 1 && a.beamGrowth <= 4))
    throw InputError("--beam-growth", "", "must lie in [1, 4] (the beam resolution's factor per doubling of spp)");
  ThreadLimit limit(a.threads);
  const Scene scene = preparedScene(a);
  // Several references are summed: pt --caustic-paths without plus lt --caustic-paths only.
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
  std::error_code ec;
  std::vector<std::string> inputs{a.scene, a.mask, a.errorMask};
  inputs.insert(inputs.end(), a.references.begin(), a.references.end());
  for (const std::string& target : {csv, svg})
    for (const std::string& input : inputs)
      if (!input.empty() && std::filesystem::equivalent(target, input, ec))
        throw InputError(target, "", "the output would overwrite an input of this run");
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

// The options `render` and `converge` share: how to render, not what to write.
void addSharedOptions(CLI::App* c, RenderArgs& a) {
  c->add_option("--res", a.res, "resolution WIDTHxHEIGHT, at most 2^28 pixels (default: the scene's)");
  c->add_option("--threads", a.threads, "worker threads, 0..4096 (default 0: all cores)");
  c->add_option("--max-lod", a.maxLod, "finest dicing level m: a patch has at most 4^m micropolygons (0..12, default 10)");
  c->add_option("--ray-memory", a.rayMemory,
                "memory for ray, path and candidate buffers, e.g. 512M or 2G (default: an eighth of physical "
                "memory, within [256M, 2G]); a smaller budget means more batches, iterations and dicings, "
                "never a different image");
  c->add_option("--grid-cache", a.gridCache,
                "memory for diced grids kept across iterations and generations of a batch, e.g. 256M (default "
                "512M; 0: off); a smaller cache means more dicings, never a different image");
  c->add_option("--candidates-per-ray", a.candidatesPerRay,
                "candidate leaves a ray gets per iteration of the sorted pipeline, at most (1..1000, default " +
                    std::to_string(TraceSettings::kDefaultCandidatesPerRay) +
                    "); more means fewer iterations but more leaves diced past the hit, never a different image");
  c->add_option("--lod", a.lod, "level-of-detail rule: per-ray (default; footprint of each ray, order independent) "
                                "density (the thesis's 4^m >= R/spp; the image then depends on batching) or fixed "
                                "(every ray at --max-lod: one geometry for every ray, for references)")
      ->check(CLI::IsMember({"per-ray", "density", "fixed"}));
  c->add_option("--trace-mode", a.traceMode, "sorted (default: the reorder pipeline) or alone (debug: every ray "
                                             "traced by itself, each patch diced per ray; slow)")
      ->check(CLI::IsMember({"sorted", "alone"}));
  c->add_option("--method", a.method, "integrator: pt (default: path tracing with next-event estimation and MIS), "
                                      "lt (light tracing: paths from the lights, every vertex connected to the "
                                      "camera; the reference for caustics; lights at infinity seen directly are "
                                      "missing), pm (photon mapping: pt without caustic paths plus a k-nearest "
                                      "photon estimate of them), ppm (progressive photon mapping: a photon map "
                                      "per pass, radius shrinking per sample) or lbt (light beams: pt without "
                                      "caustic paths plus beams from point, spot, distant and area lights through "
                                      "mirrors, glass and glossy surfaces, gathered at diffuse surfaces)");
  c->add_option("--beam-resolution", a.beamResolution, "lbt: N, each scatterer leaf's grid of beams has cells at "
                                                       "most 2/N rad wide as a light sees them (an N x N cube-map "
                                                       "face; distant lights: the scatterers' extent / N), "
                                                       "1..4096 (default 128)");
  c->add_option("--beam-depth", a.beamDepth, "lbt: most specular/glossy bounces a beam follows, 1..64 (default 4)");
  c->add_option("--beam-split-depth", a.beamSplitDepth, "lbt: times a beam whose corner rays part (another "
                                                        "material, a silhouette, total internal reflection, no "
                                                        "longer coaxial) is split in four before it is dropped, "
                                                        "0..12 (default 4)");
  c->add_option("--beam-area-samples", a.beamAreaSamples, "lbt: an area light sends beams from k x k points on "
                                                          "it, each a point light with a cosine lobe and its share "
                                                          "of the power, 0..64 (default 2; 0: none)");
  c->add_option("--beam-memory", a.beamMemory, "lbt: budget for the beam segments and their bins, e.g. 256M "
                                               "(default 1G); beams that do not fit are processed in batches "
                                               "(the camera paths traced once per batch); a budget too small "
                                               "for one beam is refused");
  c->add_option("--beam-lobe-cells", a.beamLobeCells, "lbt: glossy beams are made about this many lobe widths "
                                                      "sigma wide after their first glossy bounce, the light's grid "
                                                      "coarsened from --beam-resolution to match (never refined), "
                                                      "0..64 (default 2; 0: keep --beam-resolution)");
  c->add_option("--photons", a.photons, "pm, ppm: photons per sample per pixel of the render (default 20000): pm "
                                        "traces photons x spp into one map, ppm photons x the pass's samples per pass");
  c->add_option("--photon-k", a.photonK, "pm: neighbours of the k-nearest estimate, 1..4096 (default 32)");
  c->add_option("--later-gathers", a.laterGathers, "lbt, pm, ppm: probability of a caustic estimate at a diffuse "
                                                   "vertex after a path's first (counted 1/q: unbiased), 1/64..1 "
                                                   "(default 1; 0.25 pays off where glossy gathers dominate)");
  c->add_option("--photon-radius", a.photonRadius, "ppm: first gather radius; pm: a quarter of the largest (default "
                                                   "0: the median distance to the k-th neighbour in the first map)");
  c->add_option("--photon-alpha", a.photonAlpha, "ppm: radius shrinking, in (0, 1) (default 2/3)");
  c->add_option("--caustic-paths", a.causticPaths, "pt and lt: all (default), without (leave out light -> "
                                                   "(mirror, glass or glossy)+ -> diffuse paths, which pm, ppm "
                                                   "and lbt estimate) or only (those paths alone); lbt, pm and "
                                                   "ppm: all or only (the caustic estimate alone, plus the path "
                                                   "tracer's caustic paths of lights it does not cover)");
  c->add_option("--engine", a.engine, "ray engine: rayes (default; sorted rays, patches diced on demand) or embree "
                                      "(the peer: every patch diced up front into Embree grids)")
      ->check(CLI::IsMember({"rayes", "embree"}));
  c->add_option("--embree-lod", a.embreeLod, "with --engine embree: fixed (default; every patch at --max-lod) or "
                                             "auto (per patch, the finest level a camera ray's footprint needs)")
      ->check(CLI::IsMember({"fixed", "auto"}));
  c->add_option("--memory-limit", a.memoryLimit, "with --engine embree: refuse, before allocating, a tessellation "
                                                 "estimated larger than this, e.g. 8G (default: 80% of physical memory)");
  c->add_option("--dice-cache", a.diceCache, "trace rays one at a time, unsorted, keeping the last K diced patches "
                                             "in an LRU cache (the thesis's alternative to reordering; same image, "
                                             "one thread, for counting dicings). K >= 1");
  c->add_option("--lod-bias", a.lodBias, "shift every ray's dicing level by B levels, -12..12 (default 0; negative: "
                                         "coarser and faster, positive: finer)");
  c->add_option("--seed", a.seed, "random seed, 0..2^62 (default: the scene's, else 0)");
  c->add_flag("-q,--quiet", a.quiet, "no progress output");
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
                                      "beside it (default: out/<scene>.exr). A name ending in .png writes the "
                                      "preview alone, no EXR. Outputs are all or nothing: on any failure none "
                                      "is left");
  r->add_option("--spp", a.spp, "samples per pixel, 1..2^20 (default: the scene's)");
  r->add_option("--stats", a.stats, "write render statistics as JSON to this file (docs/stats.md)");
  r->add_option("--report", a.report, "write a readable HTML report of the same statistics: time and memory "
                                      "breakdown, dicing per generation, what was used and skipped");
  r->add_option("--reference", a.reference, "reference OpenEXR of the same resolution: the stats then hold the "
                                            "RMSE after every pass against time (error_vs_time); implies --progressive");
  r->add_flag("--progressive", a.progressive, "render in passes of 1, 1, 2, 4, ... samples per pixel, a complete "
                                             "image after each (more dicings; the same final image). Implied by "
                                             "--reference");
  addSharedOptions(r, a);

  RenderArgs ca;
  CLI::App* c = app.add_subcommand("converge", "error against run time: render at doubling effort (spp 1, 2, 4, ...; "
                                               "pm and ppm double their photons with it, lbt grows its beam resolution "
                                               "by --beam-growth) until the budget, compare each render with a "
                                               "reference; writes a CSV and an SVG chart");
  c->add_option("scene", ca.scene, "the scene file")->required();
  c->add_option("--reference", ca.references, "reference OpenEXR of the render's resolution; given several times, "
                                              "their sum (e.g. pt --caustic-paths without + lt --caustic-paths only)")
      ->required();
  c->add_option("--error-mask", ca.errorMask, "an OpenEXR of the render's size: RMSE and rel_mse count only the pixels "
                                              "with non-zero red (default: every pixel)");
  c->add_option("--beam-growth", ca.beamGrowth, "lbt: factor of the beam resolution per doubling of spp, from "
                                                "--beam-resolution at 1 spp, in [1, 4] (default sqrt 2: twice the "
                                                "beams per step; 1: fixed beams)");
  c->add_option("--budget", ca.budget, "seconds to spend in all (the next doubling is skipped when it would not fit)")
      ->required();
  c->add_option("--region", ca.region, "x0,y0,x1,y1: the pixel box (x1, y1 excluded) whose mean signed error is the "
                                       "bias column (default: the whole image)");
  c->add_option("--mask", ca.mask, "instead of --region: an OpenEXR of the render's size; pixels with non-zero red "
                                   "are the region");
  c->add_option("-o,--output", ca.out, "the CSV (default out/<scene>-<method>-converge.csv): seconds, cpu_seconds, "
                                       "spp, photons, beam_resolution, beam_segments, rmse, rel_mse, region_bias; "
                                       "the SVG chart goes beside it");
  c->add_option("--svg", ca.svg, "the chart's file (default: the CSV's name with .svg)");
  addSharedOptions(c, ca);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // Point at the help of the subcommand that was being parsed.
    const char* which = c->parsed() ? "converge " : r->parsed() ? "render " : "";
    std::cerr << "rayes: " << e.what() << "\n(run 'rayes " << which << "--help' for the options)\n";
    return 2;
  }
  try {
    if (r->parsed()) return render(a);
    if (c->parsed()) return runConverge(ca);
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
