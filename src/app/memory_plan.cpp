#include "app/memory_plan.h"
#include <algorithm>
#include <utility>
#include <vector>
#include "app/renderer.h"
#include "core/error.h"
#include "core/memory.h"
#include "rays/sorted_engine.h"

namespace rayes {

uint64_t diceBufferEstimate(int maxLod, int threads) {
  const uint64_t side = (uint64_t(1) << maxLod) + 1;
  return side * side * kDiceBytesPerVertex * uint64_t(threads > 0 ? threads : 1);
}

uint64_t storedBricks(const Scene& scene) {
  uint64_t stored = 0;
  for (const auto& m : scene.media) {
    stored += m->densityGrid().storedBricks();
    if (m->emission().intensity) stored += m->emission().intensity->storedBricks();
    if (m->emission().temperature) stored += m->emission().temperature->storedBricks();
  }
  return stored;
}

namespace {
// The slots of every brick the scene's volumes read from files: the most the cache can hold.
uint64_t storedBrickBytes(const Scene& scene) { return storedBricks(scene) * BrickCache::kSlotBytes; }
}  // namespace

uint64_t volumeCacheBytes(const Scene& scene, const RenderOptions& options, int threads) {
  const uint64_t all = storedBrickBytes(scene), minimum = BrickCache::minimumBytes(threads);
  if (all == 0) return 0;
  if (options.volumeMemoryBytes == RenderOptions::kVolumeMemoryDefault) {
    const uint64_t limit = processMemoryLimit().bytes;
    return limit == 0 ? all : std::max(std::min(all, limit / 8), std::min(all, minimum));
  }
  if (options.volumeMemoryBytes < minimum && options.volumeMemoryBytes < all)
    throw InputError("--volume-memory", "", "a brick cache of " + std::to_string(options.volumeMemoryBytes) +
                                                " bytes is too small for " + std::to_string(threads) +
                                                " threads: at least " + std::to_string(minimum) + " bytes (" +
                                                std::to_string(BrickCache::kSlotBytes) + " per brick, six per thread and one more)");
  return options.volumeMemoryBytes;
}

RenderMemoryPlan planRenderMemory(const Scene& scene, const RenderOptions& options, uint64_t rayBytes, int threads) {
  RenderMemoryPlan p;
  p.width = scene.width;
  p.height = scene.height;
  // The film and the outputs hold the crop window alone (a part's band is within it).
  const uint64_t pixels = options.crop.empty() ? uint64_t(scene.width) * uint64_t(scene.height) : options.crop.pixels();
  p.film = pixels * kFilmBytesPerPixel;
  p.outputs = pixels * kOutputBytesPerPixel;
  p.rays = rayBytes;
  // The Embree engine checks its own tessellation (EmbreeEngine); the caching engine's grids
  // are counted in entries, not bytes.
  if (options.engine == EngineKind::Rayes) {
    // The sorted pipeline's buffers hold the resident level (finer leaves are split); the
    // caching engine dices whole leaves at any level.
    const int level = options.diceCacheEntries == 0 ? SortedEngine::residentLevelFor(options.residentLod, options.maxLod)
                                                    : options.maxLod;
    p.diceBuffers = diceBufferEstimate(level, threads);
    if (options.diceCacheEntries == 0) p.gridCache = options.gridCacheBytes;
  }
  p.beams = methodBudgetBytes(options.method);
  if (scene.textures) p.textures = options.textureMemoryBytes;
  p.volumes = std::min(volumeCacheBytes(scene, options, threads), storedBrickBytes(scene));
  return p;
}

namespace {
std::vector<std::pair<const char*, uint64_t>> byOption(const RenderMemoryPlan& p) {
  return {{"--res", p.film + p.outputs}, {"--ray-memory", p.rays}, {"--resident-lod", p.diceBuffers},
          {"--grid-cache", p.gridCache}, {"--beam-memory", p.beams}, {"--texture-memory", p.textures},
          {"--volume-memory", p.volumes}};
}
}  // namespace

std::string RenderMemoryPlan::largestOption() const {
  const char* best = "--res";
  uint64_t most = 0;
  for (const auto& [option, bytes] : byOption(*this))
    if (bytes > most) {
      most = bytes;
      best = option;
    }
  return best;
}

std::string RenderMemoryPlan::parts() const {
  std::string s = "the film of " + std::to_string(width) + "x" + std::to_string(height) + " pixels " +
                  readableBytes(film) + " and its outputs " + readableBytes(outputs) + " (--res), rays " +
                  readableBytes(rays) + " (--ray-memory), dice buffers " + readableBytes(diceBuffers) +
                  " (--max-lod, --threads), grid cache " + readableBytes(gridCache) + " (--grid-cache)";
  if (beams) s += ", beams " + readableBytes(beams) + " (--beam-memory)";
  if (textures) s += ", texture cache " + readableBytes(textures) + " (--texture-memory)";
  if (volumes) s += ", brick cache " + readableBytes(volumes) + " (--volume-memory)";
  return s;
}

void checkRenderMemory(const RenderMemoryPlan& plan) {
  const std::string option = plan.largestOption();
  checkMemoryFits(plan.total(), option, "the render (" + plan.parts() + ")", "lower " + option);
}

}  // namespace rayes
