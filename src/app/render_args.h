// The command line's arguments as parsed (RenderArgs: the strings and numbers CLI11 fills in,
// shared by `render` and `converge`), and their checked form: RenderOptions, and the Scene
// with the command line's resolution, samples and seed. Every check that needs no scene runs
// in checkedOptions, so a bad option costs no loading; each throws InputError naming the
// option.
#pragma once
#include <optional>
#include <string>
#include <vector>
#include "app/renderer.h"
#include "scene/scene.h"

namespace rayes {

struct RenderArgs {
  std::string scene, out, stats, report, reference, res, rayMemory, lod = "per-ray", traceMode = "sorted",
              method = MethodOptions{}.name, causticPaths = "all";
  std::string engine = "rayes", embreeLod, memoryLimit, beamMemory = "1G", gridCache;
  std::string textureMemory, textureCacheDir;  // --texture-memory, --texture-cache-dir
  std::string volumeMemory;                    // --volume-memory
  std::string sceneMemory;  // --scene-memory: a compiled scene's resident budget (empty: none)
  int beamResolution = 128, beamDepth = 4, beamSplitDepth = 4, beamAreaSamples = 2;
  std::optional<int> spp;
  int64_t photons = 20000;
  int photonK = 32;
  float laterGathers = kLaterGatherProbability;
  float photonRadius = 0, photonAlpha = kDefaultPhotonAlpha;
  std::optional<int64_t> seed, diceCache;
  int lodBias = 0;
  int candidatesPerRay = TraceSettings::kDefaultCandidatesPerRay;
  int threads = 0, maxLod = 10;
  int residentLod = TraceSettings::kDefaultResidentLod;
  bool quiet = false, progressive = false;
  bool costLayers = false;  // render: --cost-layers
  std::string progress = "human";  // --progress human|json|none (-q: none)
  // render: batch jobs (docs/batch-and-farm.md)
  std::string crop, part, checkpoint;
  double checkpointEvery = 60;
  std::optional<double> timeLimit;
  bool resume = false;
  // converge
  double beamLobeCells = 2;
  double budget = 0, beamGrowth = 1.4142135623730951;
  std::optional<double> clampedRmse;  // --clamped-rmse QUANTILE
  std::string region, mask, errorMask, svg;
  std::vector<std::string> references;
};

// Throws InputError naming the option.
RenderOptions checkedOptions(const RenderArgs& a);
// SCENE "-": the scene is read from standard input, named "<stdin>" in messages, and the files it
// names resolve against the current directory.
inline constexpr const char* kStdinScene = "-";
inline constexpr const char* kStdinSceneName = "<stdin>";
Scene loadSceneFromStdin(const TextureCacheOptions& textures = {});
// How the scene's texture cache is made: --texture-memory, --texture-cache-dir (checked by
// checkedOptions).
TextureCacheOptions textureCacheOptions(const RenderArgs& a);
// --scene-memory in bytes (0: not given); InputError for a bad value, or given with a JSON
// scene; ResourceError beyond the memory available.
uint64_t sceneMemoryBytes(const RenderArgs& a);
// Loads the scene (kStdinScene: from standard input; a .rayes: the compiled scene, mapped,
// within --scene-memory) and applies --res, --spp and --seed.
Scene preparedScene(const RenderArgs& a);
// --crop x0,y0,x1,y1 (x1, y1 excluded) inside a width x height image; throws InputError("--crop").
PixelWindow parseCrop(const std::string& text, int width, int height);
// --part I/N (1 <= I <= N <= kMaxParts); throws InputError("--part").
inline constexpr int kMaxParts = 65536;
void parsePart(const std::string& text, int& part, int& parts);

// An RGB image of the scene's size from `path`, for `what` (a reference, a mask): its size checked
// from the header before its pixels are read, every value finite (readExrRgbOfSize).
std::vector<float> imageOfSceneSize(const std::string& path, const Scene& scene, const char* what);

}  // namespace rayes
