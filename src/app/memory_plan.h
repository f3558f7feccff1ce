// What a render will hold at its largest, by part, known before any of it is allocated; the
// Renderer checks it against the memory limit that applies (core/memory.h: a cgroup, RLIMIT_AS,
// physical memory) and refuses with ResourceError (exit code 3) naming the option of the largest
// part, instead of dying in the allocation. The parts are budgets (rays, grid cache, beams) or
// exact sizes (film, outputs) or estimates (dice buffers); the scene is already loaded and
// counts as memory in use.
#pragma once
#include <cstdint>
#include <string>

namespace rayes {

// The film's sums per pixel (shading/film.h: 15 doubles, 3 32-bit counters), and what writing
// the EXR adds per pixel (14 float channels, made from the film before writing).
constexpr uint64_t kFilmBytesPerPixel = 12 * 8 + 3 * 16 + 3 * 4;  // doubles, fixed-point splats, counts
constexpr uint64_t kOutputBytesPerPixel = 14 * 4;
// A dice buffer per thread at level m holds about this much per grid vertex ((2^m + 1)^2
// vertices: positions, normals, the implicit BVH, border trees): 58 MB at level 10.
constexpr uint64_t kDiceBytesPerVertex = 55;

struct RenderMemoryPlan {
  int width = 0, height = 0;
  uint64_t film = 0, outputs = 0;  // --res
  uint64_t rays = 0;               // --ray-memory: the batch's paths, ray slots and the engine's per-ray state
  uint64_t diceBuffers = 0;        // --resident-lod, --max-lod (and --threads): one dice buffer per thread
  uint64_t gridCache = 0;          // --grid-cache
  // --beam-memory (lbt): everything the beams allocate, freed pages returned (lbt/beam_budget.h);
  // lbt's larger dice buffers are in diceBuffers, its camera batch's gathers in rays.
  uint64_t beams = 0;
  uint64_t textures = 0;           // --texture-memory, when the scene reads an image
  uint64_t volumes = 0;            // --volume-memory, when a volume reads bricks from a file (at most all of them)
  uint64_t total() const { return film + outputs + rays + diceBuffers + gridCache + beams + textures + volumes; }
  // The option whose part is largest, and the parts for a message.
  std::string largestOption() const;
  std::string parts() const;
};

struct Scene;
struct RenderOptions;
// The plan of a render of `scene` with `options`, whose ray batches take `rayBytes`, on `threads` threads.
RenderMemoryPlan planRenderMemory(const Scene& scene, const RenderOptions& options, uint64_t rayBytes, int threads);

// The brick cache's bound for `scene` (0: no volume reads bricks from a file): --volume-memory,
// by default every stored brick's slot but at most an eighth of the memory limit. Throws
// InputError naming --volume-memory when a given bound is below what `threads` threads need and
// does not hold every brick anyway.
uint64_t volumeCacheBytes(const Scene& scene, const RenderOptions& options, int threads);
// The bricks the scene's volumes read from files (the brick cache's keys).
uint64_t storedBricks(const Scene& scene);

// The dice buffers of `threads` threads at level `maxLod`.
uint64_t diceBufferEstimate(int maxLod, int threads);

// Throws ResourceError naming the option of the largest part when the plan does not fit what
// the memory limit has available now.
void checkRenderMemory(const RenderMemoryPlan& plan);

}  // namespace rayes
