#include "app/command_line.h"
#include <algorithm>
#include <iostream>
#include <string>
#include <CLI/CLI.hpp>
#include "app/closest_name.h"
#include "app/commands.h"
#include "app/farm_command.h"
#include "core/error.h"
#include "core/memory.h"
#include "core/version.h"

namespace rayes {
namespace {

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
  c->add_option("--texture-memory", a.textureMemory,
                "memory for the texture cache's tiles, e.g. 64M (default " +
                    std::to_string(kDefaultTextureMemoryBytes >> 20) +
                    "M; > 0); a smaller cache means more tile reads, never a different image");
  c->add_option("--volume-memory", a.volumeMemory,
                "memory for the volumes' brick cache (8^3 voxels read from the .vdb on demand), e.g. 64M "
                "(default: every brick, at most an eighth of the memory limit; > 0); a smaller cache means "
                "more reads, never a different image");
  c->add_option("--texture-cache-dir", a.textureCacheDir,
                "folder for plain images converted to tiled MIP-mapped textures (default: "
                "$XDG_CACHE_HOME/rayes/textures or ~/.cache/rayes/textures)");
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
                                      "missing), pm (photon mapping: pt without caustic paths plus a photon "
                                      "density estimate of them), ppm (progressive photon mapping: a photon map "
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
                                        "traces photons x spp into one map, ppm photons x the pass's samples per pass; refused "
                                        "(exit 3) when that map, every photon stored, would not fit half of "
                                        "physical memory");
  c->add_option("--photon-k", a.photonK, "pm: each photon's gather disk reaches its k-th nearest other photon, "
                                        "1..4096 (default 32)");
  c->add_option("--later-gathers", a.laterGathers, "lbt, pm, ppm: probability of a caustic estimate at a diffuse "
                                                   "vertex after a path's first (counted 1/q: unbiased), 1/64..1 "
                                                   "(default 1; 0.25 pays off where glossy gathers dominate)");
  c->add_option("--photon-radius", a.photonRadius, "ppm: first gather radius; pm: a quarter of the largest photon radius (default "
                                                   "0: the median distance to the k-th neighbour in the first map)");
  c->add_option("--photon-alpha", a.photonAlpha, "ppm: radius shrinking, in (0, 1) (default 1/3)");
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
  c->add_option("--resident-lod", a.residentLod, "finest level a dice buffer holds, 0..12 (default 8; raised to 6 and "
                                                 "to half of --max-lod): a leaf a ray needs finer is diced as "
                                                 "sub-leaves, the same micro-triangles");
  c->add_option("--lod-bias", a.lodBias, "shift every ray's dicing level by B levels, -12..12 (default 0; negative: "
                                         "coarser and faster, positive: finer)");
  c->add_option("--seed", a.seed, "random seed, 0..2^62 (default: the scene's, else 0)");
  c->add_option("--scene-memory", a.sceneMemory, "a compiled scene (.rayes): bound the pages of its mapping kept "
                                                 "resident, e.g. 256M (at least 1M; default: no bound); the least "
                                                 "recently used are released and read again when touched, never "
                                                 "a different image");
  c->add_flag("-q,--quiet", a.quiet, "no progress output");
}

// Every name an option of `app` answers to ("--spp", "-o", ...).
std::vector<std::string> optionNames(const CLI::App* app) {
  std::vector<std::string> names;
  for (const CLI::Option* o : app->get_options()) {
    for (const std::string& l : o->get_lnames()) names.push_back("--" + l);
    for (const std::string& s : o->get_snames()) names.push_back("-" + s);
  }
  return names;
}

// What CLI11 left over (the subcommands allow extras, so that a mistyped option can be named with
// the nearest real one): "rayes: --sp: unknown option; did you mean --spp?". Empty when nothing
// was left over.
std::string leftOverMessage(const CLI::App* app) {
  const std::vector<std::string> rest = app->remaining();
  if (rest.empty()) return "";
  const std::string& first = rest.front();
  if (first.size() < 2 || first[0] != '-') return first + ": unexpected argument (" + app->get_name() + " takes one scene)";
  const std::string typed = first.substr(0, first.find('='));
  const std::string near = closestName(typed, optionNames(app));
  return typed + ": unknown option" + (near.empty() ? "" : "; did you mean " + near + "?");
}

}  // namespace

CLI::App* addRenderCommand(CLI::App& app, RenderArgs& a) {
  CLI::App* r = app.add_subcommand("render", "render a scene file (JSON, docs/scene-format.md, or a compiled .rayes)");
  r->add_option("scene", a.scene, "the scene file (JSON, or a .rayes from rayes compile, memory-mapped); - reads "
                                  "JSON from standard input (its relative file names then resolve against the "
                                  "current directory)")->required();
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
  r->add_flag("--cost-layers", a.costLayers, "add the per-pixel cost layers to the EXR: dicings.Y (dicings charged to "
                                            "the pixel's camera paths, each dicing shared among the rays that caused "
                                            "it) and time.Y (each batch's time shared by rays); the stats name the "
                                            "image, and the report draws them as heat maps (docs/dashboard.md)");
  addSharedOptions(r, a);
  r->add_option("--progress", a.progress, "progress on stderr: human (default; a line redrawn on a terminal, plain "
                                          "lines otherwise), json (one JSON object per line: elapsed, phase, "
                                          "samples, paths, ETA, resident memory) or none (as -q)")
      ->check(CLI::IsMember({"human", "json", "none"}));
  r->allow_extras();
  // Batch jobs and farms (docs/batch-and-farm.md).
  r->add_option("--crop", a.crop, "x0,y0,x1,y1: render only this window of pixels (x1, y1 excluded), the same "
                                  "pixels as the whole render's there; the EXR's data window, the PNG its size");
  r->add_option("--part", a.part, "I/N: render part I of N of the frame (bands of rows; lt: ranges of light paths) "
                                  "into -o NAME.film; rayes merge makes the image of the N parts, the same bits as "
                                  "one render");
  r->add_option("--checkpoint", a.checkpoint, "keep the render's progress in this .film file (every "
                                              "--checkpoint-every seconds and when stopped by SIGTERM, SIGINT or "
                                              "SIGHUP: exit code 4); removed when the render is done");
  r->add_option("--checkpoint-every", a.checkpointEvery, "seconds between checkpoints (default 60)");
  r->add_flag("--resume", a.resume, "continue from the checkpoint (--checkpoint, or the --time-limit default) if "
                                    "it exists; a checkpoint of another scene, settings or version is refused");
  r->add_option("--time-limit", a.timeLimit, "stop after this many seconds with a checkpoint (exit code 4; without "
                                             "--checkpoint it is <output>.checkpoint.film)");
  return r;
}

int runCommandLine(int argc, char** argv) {
  CLI::App app{"rayes: a streaming micropolygon ray tracer. Rays are traced in generations, sorted by the\n"
               "patch they may hit, and every patch is diced on demand into micropolygons."};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("rayes ") + programVersion(), "print the program's version and exit");
  RenderArgs a;
  CLI::App* r = addRenderCommand(app, a);

  CLI::App* m = app.add_subcommand("merge", "combine the parts of a split render (rayes render --part I/N -o "
                                            "part-I.film) into the image, the same bits as one render");
  MergeArgs ma;
  m->add_option("parts", ma.parts, "the parts' .film files (or one complete .film)")->required();
  m->add_option("-o,--output", ma.outputs, "the image: .exr (a PNG preview beside it unless a .png is named too), "
                                           ".png or .film; may be given several times")
      ->required()
      ->allow_extra_args(false);  // one name per -o, so parts may follow it
  m->add_option("--stats", ma.stats, "the parts' statistics combined as JSON (docs/stats.md, \"Merged parts\")");
  m->add_flag("-q,--quiet", ma.quiet, "no message when done");

  ReportArgs ra;
  CLI::App* rep = app.add_subcommand("report", "the statistics of one render (--stats), a farm job's parts or a frame "
                                               "sequence as one self-contained HTML page of charts (docs/dashboard.md); "
                                               "with --compare, two runs side by side with ratios");
  rep->add_option("stats", ra.stats, "the stats files (JSON, docs/stats.md), or finished .film files (a farm part's "
                                     "header holds its stats)");
  rep->add_option("--watch", ra.watch, "DIR: a running job's folder: rewrite the page (atomically) as its parts write "
                                       "their stats (*.json, finished *.film), the page reloading itself until the job "
                                       "is complete (--watch-until, all parts of a farm split, or a file DIR/complete) "
                                       "or a signal stops the watch");
  rep->add_option("--watch-until", ra.watchUntil, "with --watch: the job is complete once this many stats were read");
  rep->add_option("--watch-interval", ra.watchInterval, "with --watch: seconds between looks at the folder (default 1)");
  rep->add_option("-o,--output", ra.out, "the page, NAME.html")->required()->allow_extra_args(false);
  rep->add_flag("--compare", ra.compare, "two stats files of the same scene and resolution: times, memory, dicings "
                                         "and error side by side with ratios B / A");
  rep->add_flag("-q,--quiet", ra.quiet, "no message when done");

  CompileArgs pa;
  CLI::App* p = app.add_subcommand("compile", "compile a scene (JSON) into a .rayes file that rayes render "
                                              "memory-maps, reading a leaf's patch only when it is diced; the "
                                              "same image bits as the JSON (docs/scene-format.md, \"Compiled scenes\")");
  p->add_option("scene", pa.scene, "the scene file (JSON)")->required();
  p->add_option("-o,--output", pa.out, "the compiled scene, NAME.rayes (default: the scene's name with .rayes)");
  p->add_flag("-q,--quiet", pa.quiet, "no message when done");

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
  c->add_option("--budget", ca.budget, "seconds for the whole run, loading included: a render starts only when its "
                                       "predicted time fits, and one that reaches the budget is stopped without a row "
                                       "(the first render always completes)")
      ->required();
  c->add_option("--clamped-rmse", ca.clampedRmse, "QUANTILE in (0, 1), e.g. 0.999: adds the column clamped_rmse, the "
                                                  "RMSE with each pixel's squared error clamped at this quantile of them");
  c->add_option("--region", ca.region, "x0,y0,x1,y1: the pixel box (x1, y1 excluded) whose mean signed error is the "
                                       "bias column (default: the whole image)");
  c->add_option("--mask", ca.mask, "instead of --region: an OpenEXR of the render's size; pixels with non-zero red "
                                   "are the region");
  c->add_option("-o,--output", ca.out, "the CSV (default out/<scene>-<method>-converge.csv): seconds, cpu_seconds, "
                                       "spp, photons, beam_resolution, beam_segments, rmse, rel_mse, region_bias "
                                       "(and clamped_rmse); the SVG chart goes beside it");
  c->add_option("--svg", ca.svg, "the chart's file (default: the CSV's name with .svg)");
  addSharedOptions(c, ca);
  c->allow_extras();

  // rayes farm submit: the words after "--" are for sbatch, not for CLI11.
  FarmArgs fa;
  CLI::App* f = addFarmCommand(app, fa);
  if (argc > 1 && std::string(argv[1]) == "farm")
    for (int i = 2; i < argc; ++i)
      if (std::string(argv[i]) == "--") {
        fa.sbatchArgs.assign(argv + i + 1, argv + argc);
        argc = i;
        break;
      }

  // What a subcommand that takes extras (to name a mistyped option) left over: one message.
  const auto reportLeftOver = [&] {
    for (const CLI::App* sub : {r, c})
      if (sub->parsed())
        if (const std::string left = leftOverMessage(sub); !left.empty()) {
          std::cerr << "rayes: " << left << "\n(run 'rayes " << sub->get_name() << " --help' for the options)\n";
          return true;
        }
    return false;
  };
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // A mistyped subcommand: name the nearest.
    const std::vector<std::string> commands = {"render", "compile", "converge", "merge", "farm", "report"};
    if (!r->parsed() && !c->parsed() && !m->parsed() && !f->parsed() && !p->parsed() && !rep->parsed() && argc > 1 && argv[1][0] != '-' &&
        std::find(commands.begin(), commands.end(), argv[1]) == commands.end()) {
      const std::string near = closestName(argv[1], commands);
      std::cerr << "rayes: " << argv[1] << ": unknown command" << (near.empty() ? "" : "; did you mean " + near + "?")
                << "\n(run 'rayes --help' for the commands)\n";
      return 2;
    }
    // A mistyped option explains the rest (a required option "missing" is usually the mistyped one).
    if (reportLeftOver()) return 2;
    // Point at the help of the subcommand that was being parsed.
    const char* which = c->parsed()   ? "converge "
                        : r->parsed() ? "render "
                        : m->parsed() ? "merge "
                        : f->parsed() ? "farm submit "
                        : p->parsed() ? "compile "
                        : rep->parsed() ? "report "
                                      : "";
    std::cerr << "rayes: " << e.what() << "\n(run 'rayes " << which << "--help' for the options)\n";
    return 2;
  }
  if (reportLeftOver()) return 2;
  try {
    if (r->parsed()) return runRender(a);
    if (c->parsed()) return runConverge(ca);
    if (m->parsed()) return runMerge(ma);
    if (p->parsed()) return runCompile(pa);
    if (rep->parsed()) return runReport(ra);
    if (f->parsed()) return runFarmSubmit(fa, f->remaining());
  } catch (const ResourceError& e) {
    std::cerr << "rayes: " << e.message() << "\n";
    return 3;
  } catch (const InputError& e) {
    std::cerr << "rayes: " << e.message() << "\n";
    return 2;
  } catch (const std::bad_alloc&) {
    // Every large allocation is checked against the memory limit before it is made; this is
    // what one that was not (or an estimate that fell short) gives: still a resource limit.
    std::cerr << "rayes: out of memory (" << readMemoryLimit().describe()
              << "); lower --res, --ray-memory, --grid-cache, --max-lod or --beam-memory\n";
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "rayes: internal error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace rayes
