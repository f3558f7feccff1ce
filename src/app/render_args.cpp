#include "app/render_args.h"
#include <algorithm>
#include <charconv>
#include <cmath>
#include <iostream>
#include <iterator>
#include "app/image_io.h"
#include "core/error.h"
#include "core/ray_batch.h"
#include "core/memory.h"
#include "scene/compiled_scene.h"
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

}  // namespace

Scene loadSceneFromStdin(const TextureCacheOptions& textures) {
  std::string text((std::istreambuf_iterator<char>(std::cin)), std::istreambuf_iterator<char>());
  if (std::cin.bad()) throw InputError(kStdinSceneName, "", "cannot read the scene from standard input");
  // Named "<stdin>" in messages; its relative paths resolve against the current directory.
  return parseScene(text, kStdinSceneName, textures);
}

// Checks every option that does not need the scene, so that a bad option costs no loading.
RenderOptions checkedOptions(const RenderArgs& a) {
  if (a.spp && (*a.spp < 1 || *a.spp > (1 << 20))) throw InputError("--spp", "", "must be in [1, 2^20]");
  if (a.threads < 0 || a.threads > 4096) throw InputError("--threads", "", "must be in [0, 4096] (0: all cores)");
  if (a.seed && (*a.seed < 0 || *a.seed > (int64_t(1) << 62)))
    throw InputError("--seed", "", "must be in [0, 2^62]");
  RenderOptions options;
  MethodOptions& method = options.method;
  method.name = a.method;
  method.causticPaths = causticPathsFromName(a.causticPaths, "--caustic-paths");
  checkMethodOptions(method);
  if (a.photons < 1 || a.photons > (int64_t(1) << 32)) throw InputError("--photons", "", "must be in [1, 2^32]");
  if (a.photonK < 1 || a.photonK > 4096) throw InputError("--photon-k", "", "must be in [1, 4096]");
  if (!(a.laterGathers >= 1.0f / 64 && a.laterGathers <= 1))
    throw InputError("--later-gathers", "", "must be in [1/64, 1] (the probability of a caustic estimate after a path's first diffuse vertex)");
  if (!(a.photonRadius >= 0) || !std::isfinite(a.photonRadius))
    throw InputError("--photon-radius", "", "must be a finite radius >= 0 (0: chosen from the first photon map)");
  if (!(a.photonAlpha > 0 && a.photonAlpha < 1))
    throw InputError("--photon-alpha", "", "must lie in (0, 1): the radius shrinks as r² (i + alpha) / (i + 1)");
  method.photons.photonsPerSample = uint64_t(a.photons);
  method.photons.neighbours = a.photonK;
  method.laterGatherProbability = a.laterGathers;
  method.photons.radius = a.photonRadius;
  method.photons.alpha = a.photonAlpha;
  // A hit keeps its micro-quad index in 2 * kMaxHitLevel bits (core/ray_batch.h).
  if (a.maxLod < 0 || a.maxLod > kMaxHitLevel)
    throw InputError("--max-lod", "", "must be in [0, " + std::to_string(kMaxHitLevel) + "]");
  options.maxLod = a.maxLod;
  if (a.residentLod < 0 || a.residentLod > 12) throw InputError("--resident-lod", "", "must be in [0, 12]");
  options.residentLod = a.residentLod;
  if (a.beamResolution < 1 || a.beamResolution > 4096) throw InputError("--beam-resolution", "", "must be in [1, 4096]");
  if (a.beamDepth < 1 || a.beamDepth > 64) throw InputError("--beam-depth", "", "must be in [1, 64]");
  method.beams.resolution = a.beamResolution;
  method.beams.maxDepth = a.beamDepth;
  if (a.beamSplitDepth < 0 || a.beamSplitDepth > 12) throw InputError("--beam-split-depth", "", "must be in [0, 12]");
  method.beams.splitDepth = a.beamSplitDepth;
  if (a.beamAreaSamples < 0 || a.beamAreaSamples > 64) throw InputError("--beam-area-samples", "", "must be in [0, 64]");
  method.beams.areaSamples = a.beamAreaSamples;
  method.beams.memoryBytes = parseBytes(a.beamMemory, "--beam-memory");
  if (!(a.beamLobeCells >= 0 && a.beamLobeCells <= 64))
    throw InputError("--beam-lobe-cells", "", "must lie in [0, 64] (a glossy beam's width in lobe widths sigma; 0: keep --beam-resolution)");
  method.beams.lobeCells = a.beamLobeCells;
  options.lod = a.lod == "density" ? LodRule::Density : a.lod == "fixed" ? LodRule::Fixed : LodRule::PerRay;
  options.sortByLeaf = a.traceMode == "sorted";
  if (!a.rayMemory.empty()) options.rayMemoryBytes = parseBytes(a.rayMemory, "--ray-memory");
  if (!a.gridCache.empty()) options.gridCacheBytes = a.gridCache == "0" ? 0 : parseBytes(a.gridCache, "--grid-cache");
  // By default at most an eighth of the memory limit (a cache: same image at any size).
  else if (const uint64_t limit = processMemoryLimit().bytes; limit > 0)
    options.gridCacheBytes = std::min<size_t>(options.gridCacheBytes, size_t(limit / 8));
  options.textureMemoryBytes = textureCacheOptions(a).memoryBytes;
  if (!a.volumeMemory.empty()) {
    if (a.volumeMemory == "0") throw InputError("--volume-memory", "", "must be > 0 (the brick cache cannot hold nothing)");
    options.volumeMemoryBytes = parseBytes(a.volumeMemory, "--volume-memory");
    // A cache larger than the memory that can be had is a resource limit, not a typo.
    if (const uint64_t limit = processMemoryLimit().bytes; limit > 0 && options.volumeMemoryBytes > limit)
      throw ResourceError("--volume-memory", "a brick cache of " + readableBytes(options.volumeMemoryBytes) +
                                                 " exceeds the memory limit of " + readableBytes(limit) +
                                                 " (docs/memory-limits.md); lower --volume-memory");
  }
  if (a.candidatesPerRay < 1 || a.candidatesPerRay > 1000)
    throw InputError("--candidates-per-ray", "", "must be a whole number in [1, 1000]");
  options.candidatesPerRay = a.candidatesPerRay;
  options.progressive = a.progressive;
  options.costLayers = a.costLayers;
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
  // The default limit keeps a fifth of the memory limit that applies (core/memory.h) for
  // everything else; a larger one given still cannot exceed what is available (EmbreeEngine).
  sceneMemoryBytes(a);  // checked before the scene is loaded
  options.memoryLimitBytes = a.memoryLimit.empty() ? size_t(processMemoryLimit().bytes / 5 * 4)
                                                   : parseBytes(a.memoryLimit, "--memory-limit");
  return options;
}

TextureCacheOptions textureCacheOptions(const RenderArgs& a) {
  TextureCacheOptions t;
  if (!a.textureMemory.empty()) {
    // 0 is refused there: a tile cache cannot hold nothing.
    t.memoryBytes = parseBytes(a.textureMemory, "--texture-memory");
  }
  // A cache larger than the memory that can be had is a resource limit, not a typo.
  if (const uint64_t limit = processMemoryLimit().bytes; limit > 0 && t.memoryBytes > limit)
    throw ResourceError("--texture-memory", "a texture cache of " + readableBytes(t.memoryBytes) +
                                                " exceeds the memory limit of " + readableBytes(limit) +
                                                " (docs/memory-limits.md); lower --texture-memory");
  if (!a.textureCacheDir.empty()) t.conversionDir = a.textureCacheDir;
  return t;
}

// The scene with the command line's resolution, samples and seed.
uint64_t sceneMemoryBytes(const RenderArgs& a) {
  if (a.sceneMemory.empty()) return 0;
  const uint64_t bytes = parseBytes(a.sceneMemory, "--scene-memory");
  if (!isCompiledSceneName(a.scene))
    throw InputError("--scene-memory", "", "bounds a compiled scene's mapping: give a .rayes scene (rayes compile)");
  // Below a few blocks every leaf's touch would release another's.
  constexpr uint64_t kMin = 16 * compiled::kBlockBytes;
  if (bytes < kMin) throw InputError("--scene-memory", "", "must be at least 1M (16 blocks of 64 KiB)");
  if (const MemoryLimit& limit = processMemoryLimit(); limit.bytes > 0 && bytes > limit.bytes)
    throw ResourceError("--scene-memory", "'" + a.sceneMemory + "' is more than the memory available (" +
                                              limit.describe() + "); give less, or leave it out for no bound");
  return bytes;
}

Scene preparedScene(const RenderArgs& a) {
  int width = 0, height = 0;
  if (!a.res.empty()) parseResolution(a.res, width, height);
  const TextureCacheOptions textures = textureCacheOptions(a);
  Scene scene = a.scene == kStdinScene          ? loadSceneFromStdin(textures)
                : isCompiledSceneName(a.scene) ? loadCompiledScene(a.scene, sceneMemoryBytes(a), textures)
                                               : loadScene(a.scene, textures);
  if (a.spp) scene.samplesPerPixel = *a.spp;
  if (!a.res.empty()) {
    scene.width = width;
    scene.height = height;
  }
  if (a.seed) scene.integrator.seed = uint64_t(*a.seed);
  return scene;
}

PixelWindow parseCrop(const std::string& text, int width, int height) {
  int64_t v[4];
  size_t at = 0;
  for (int k = 0; k < 4; ++k) {
    const size_t comma = k < 3 ? text.find(',', at) : text.size();
    if (comma == std::string::npos) throw InputError("--crop", "", "expected x0,y0,x1,y1, got '" + text + "'");
    const std::string part = text.substr(at, comma - at);
    const auto [p, ec] = std::from_chars(part.data(), part.data() + part.size(), v[k]);
    if (part.empty() || ec != std::errc() || p != part.data() + part.size())
      throw InputError("--crop", "", "expected x0,y0,x1,y1 with whole numbers, got '" + text + "'");
    at = comma + 1;
  }
  if (!(0 <= v[0] && v[0] < v[2] && v[2] <= width && 0 <= v[1] && v[1] < v[3] && v[3] <= height))
    throw InputError("--crop", "", "'" + text + "' is not a window of the " + std::to_string(width) + "x" +
                                       std::to_string(height) + " image (0 <= x0 < x1 <= width, 0 <= y0 < y1 <= height; x1 and y1 excluded)");
  return {int(v[0]), int(v[1]), int(v[2]), int(v[3])};
}

void parsePart(const std::string& text, int& part, int& parts) {
  const size_t slash = text.find('/');
  int64_t v[2] = {0, 0};
  const std::string s[2] = {slash == std::string::npos ? text : text.substr(0, slash),
                            slash == std::string::npos ? "" : text.substr(slash + 1)};
  for (int k = 0; k < 2; ++k) {
    const auto [p, ec] = std::from_chars(s[k].data(), s[k].data() + s[k].size(), v[k]);
    if (s[k].empty() || ec != std::errc() || p != s[k].data() + s[k].size())
      throw InputError("--part", "", "expected I/N (part I of N, 1-based), got '" + text + "'");
  }
  if (!(1 <= v[0] && v[0] <= v[1] && v[1] <= kMaxParts))
    throw InputError("--part", "", "'" + text + "': needs 1 <= I <= N <= " + std::to_string(kMaxParts));
  part = int(v[0]);
  parts = int(v[1]);
}

std::vector<float> imageOfSceneSize(const std::string& path, const Scene& scene, const char* what) {
  return readExrRgbOfSize(path, what, scene.width, scene.height);
}

}  // namespace rayes
