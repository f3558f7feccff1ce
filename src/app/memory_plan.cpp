#include "app/memory_plan.h"
#include <utility>
#include <vector>
#include "app/renderer.h"
#include "core/memory.h"

namespace rayes {

uint64_t diceBufferEstimate(int maxLod, int threads) {
  const uint64_t side = (uint64_t(1) << maxLod) + 1;
  return side * side * kDiceBytesPerVertex * uint64_t(threads > 0 ? threads : 1);
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
    p.diceBuffers = diceBufferEstimate(options.maxLod, threads);
    if (options.diceCacheEntries == 0) p.gridCache = options.gridCacheBytes;
  }
  p.beams = methodBudgetBytes(options.method);
  if (scene.textures) p.textures = options.textureMemoryBytes;
  return p;
}

namespace {
std::vector<std::pair<const char*, uint64_t>> byOption(const RenderMemoryPlan& p) {
  return {{"--res", p.film + p.outputs}, {"--ray-memory", p.rays}, {"--max-lod", p.diceBuffers},
          {"--grid-cache", p.gridCache}, {"--beam-memory", p.beams}, {"--texture-memory", p.textures}};
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
  return s;
}

void checkRenderMemory(const RenderMemoryPlan& plan) {
  const std::string option = plan.largestOption();
  checkMemoryFits(plan.total(), option, "the render (" + plan.parts() + ")", "lower " + option);
}

}  // namespace rayes
