// START HERE for the whole program. The Renderer is the scheduler: it turns a Scene into a
// Film by driving one Integrator (made by app/methods.h from --method; the Renderer knows no
// method by name) and one RayEngine through memory-bounded batches. It owns the budget, the
// passes, the batches and the generations, and nothing else:
//
//   setup:  RenderData (leaf boxes, TopLevelBvh, shading's view of the scene, feature counts);
//           the integrator, and the ray engine (--engine: the sorted engine, the caching engine,
//           or the Embree engine that tessellates everything here); the ray memory budget
//           divided by the bytes one path costs (the integrator's state, its ray slots and the
//           engine's bytes per ray slot) fixes how many paths a batch holds and the candidate
//           capacity; then Integrator::prepare, with a way to trace through the engine.
//   passes: one pass of all samples per pixel, split into batches of whole paths that fit the
//           budget, so every leaf is diced as few times as the budget allows: by blocks of
//           pixels, each batch every sample of a stripe of the image (Integrator::
//           setPixelBlock), where the integrator allows it. Progressive (--progressive, a
//           --reference to measure against, or an integrator whose traits ask for it): passes
//           of 1, 1, 2, 4, ... samples per pixel, a complete image after each (the
//           error-against-time curve is recorded per pass), for about 1 + log2(spp) times the
//           dicings. All give the same bits: a path's pixel and sample do not depend on the
//           order of ids, and the film adds a pixel's samples in sample order. Before a pass's
//           camera paths, the integrator's light paths (Integrator::lightPaths), if any.
//   batch:  for each of Integrator::roundsPerBatch rounds: startRound, start -> repeat
//           { RayEngine::trace (one generation) -> Integrator::shade (next generation) } until
//           no ray is left, with Integrator::addFirstHits after round 0's camera generation;
//           then Integrator::finish.
//
//   window: what this process renders of the frame (RenderOptions::crop, part/parts): the
//           film holds the crop, or for part I of N of a method whose camera ids are pixels a
//           band of its rows, rows [y0 + floor((I-1) h / N), y0 + floor(I h / N)) (partBand);
//           light tracing (Integrator traits().lightPathIds) splits its light path ids
//           [0, pixels x spp) into N ranges instead and keeps the crop's splats. Light passes
//           (photons) and prepare (beams) are the whole frame's in every part.
//   stop:   Control::stop is asked between generations; when it says stop, the batch in flight
//           is abandoned and render() returns the film as it was after the last whole batch,
//           but for the first-hit AOVs of the batch in flight when its camera generation was
//           shaded, with interrupted() and the Position to resume from. A Position (pass, the
//           next batch's first id, the pass's pixel block, and the first id whose AOVs are not
//           in the film) names a batch boundary; resume() starts there with the film a
//           checkpoint kept, adding no AOVs twice, tracing the first pass's and the current
//           pass's light paths again (Integrator, "Resume").
//
// Determinism: the film is a pure function of (scene, settings, seed) under the default
// per-ray LOD: batches cover whole sample indices or whole pixels, the film adds samples in
// order, and light tracing's splats add exactly; a window, a part or a resume changes none of
// the pixels it renders.
// Not thread-safe; render() uses all threads allowed by the caller's ThreadLimit.
#pragma once
#include <algorithm>
#include <chrono>
#include <optional>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>
#include "app/render_data.h"
#include "app/methods.h"
#include "app/pixel_cost.h"
#include "rays/caching_engine.h"
#include "rays/embree_engine.h"
#include "rays/sorted_engine.h"
#include "scene/scene.h"
#include "shading/film.h"
#include "shading/integrator.h"

namespace rayes {

enum class EngineKind { Rayes, Embree };

// The default ray memory budget under a memory limit of `limitBytes` (core/memory.h: the
// cgroup's, RLIMIT_AS or physical memory, the smallest): an eighth of it, at least 256 MiB and
// at most 2 GiB, so that a render's peak (the budget, one dice buffer per thread, the film, the
// scene) stays under 4 GiB; 1 GiB where no limit can be read (0).
// A larger batch means fewer dicings per ray, never a different image.
size_t defaultRayMemoryBytes(uint64_t limitBytes);
size_t defaultRayMemoryBytes();  // under this process's limit

struct RenderOptions {
  EngineKind engine = EngineKind::Rayes;
  bool embreeAutoLod = false;    // Embree engine: per-patch level from the camera (else maxLod)
  size_t memoryLimitBytes = 0;   // Embree engine: refuse a tessellation larger than this (0: none)
  size_t diceCacheEntries = 0;   // > 0: the CachingEngine with this many entries (--dice-cache)
  int maxLod = 10;
  LodRule lod = LodRule::PerRay;
  int lodBias = 0;               // TraceSettings::lodBias (--lod-bias)
  int residentLod = TraceSettings::kDefaultResidentLod;  // TraceSettings::residentLod (--resident-lod)
  int candidatesPerRay = TraceSettings::kDefaultCandidatesPerRay;  // TraceSettings::maxCandidatesPerRay (--candidates-per-ray)
  size_t rayMemoryBytes = defaultRayMemoryBytes();
  size_t gridCacheBytes = size_t(512) << 20;  // TraceSettings::gridCacheBytes (--grid-cache); 0: off
  // The texture cache's bound (--texture-memory), set on the scene's cache when it has one; any
  // size gives the same image.
  uint64_t textureMemoryBytes = kDefaultTextureMemoryBytes;
  // The volumes' brick cache bound (--volume-memory); kVolumeMemoryDefault: every stored brick,
  // at most an eighth of the memory limit (volumeCacheBytes). Any size gives the same image.
  uint64_t volumeMemoryBytes = kVolumeMemoryDefault;
  static constexpr uint64_t kVolumeMemoryDefault = 0;
  bool sortByLeaf = true;
  bool progressive = false;      // passes of 1, 1, 2, 4, ... spp (implied by a reference)
  MethodOptions method;          // --method and the options of each method
  std::vector<float> reference;  // RGB per pixel; empty: no error curve; else one point per pass
  PixelWindow crop;              // the pixels rendered (--crop); empty: the whole image
  int part = 1, parts = 1;       // this process renders part `part` of `parts` (--part I/N)
  // Batches small enough to stop at often (--checkpoint, --time-limit): at least
  // kCheckpointBatchesPerPass per pass; the image does not change.
  bool frequentBatches = false;
  // The per-pixel cost layers (--cost-layers, app/pixel_cost.h): dicings charged to pixels and
  // time per pixel. Off: no shares per ray, no per-path counts, nothing measured per batch.
  bool costLayers = false;
  // Whether the outputs read the first-hit AOVs (the EXR's layers, a film's or checkpoint's
  // sums): a render that writes only a PNG preview records and adds no first hit
  // (IntegratorSettings::firstHitAovs).
  bool firstHitAovs = true;
};

inline constexpr int kCheckpointBatchesPerPass = 16;

// Part `part` of `parts` (1-based) of a window's rows: rows [y0 + floor((part-1) h / parts),
// y0 + floor(part h / parts)), every column (empty when parts exceeds the rows).
PixelWindow partBand(const PixelWindow& window, int part, int parts);
// Part `part` of `parts` of the ids [0, total): [floor((part-1) total / parts), floor(part total / parts)).
std::pair<uint64_t, uint64_t> partIds(uint64_t total, int part, int parts);

// Where one generation's time went: wall clock (its start since the render's, its trace, and
// inside the trace the top level and the sort; its shading) and time summed over threads
// (dicing, bottom level, leaf queries: they run in parallel, so never added to wall time).
struct GenerationTimes {
  double start = 0, trace = 0, toplevel = 0, sort = 0, shade = 0;
  double dice = 0, bottom = 0, leafQueries = 0;
};

struct GenerationRecord {
  int pass = 0, batch = 0, depth = 0;
  GenerationStats stats;
  GenerationTimes time;
};

// Memory by owner at one moment of the render (docs/stats.md, `memory_over_time`): what the
// engine holds now (its dice buffers, the grids it keeps, the border bounds), the fixed owners,
// and the process's resident set. Read at setup's end, after every generation and at the end:
// a few loads and one read of /proc/self/statm, nothing on the trace's hot path.
struct MemorySample {
  double seconds = 0;  // since the Renderer began (setup included)
  size_t rayBuffers = 0, candidatesAndSort = 0, diceBuffers = 0, diceCache = 0, borderBounds = 0, film = 0;
  uint64_t rss = 0;
};
// The most samples kept: beyond, every other one is dropped and the sampling stride doubles.
inline constexpr size_t kMaxMemorySamples = 2048;

struct ErrorSample {
  int spp;
  double seconds;
  double rmse;
};

// Memory by owner (docs/stats.md): what each part of a render holds at its largest. Only the
// scene description grows with the leaf count; nothing grows with the micropolygons a scene
// could produce.
struct MemoryByOwner {
  size_t rayBuffers = 0;         // the RayBatch and the integrator's path state, at the batch size
  size_t candidatesAndSort = 0;  // the engine's per-ray-slot state (candidates, sort order, trace state) and the sorts' shared scratch
  size_t topLevel = 0;           // the top-level BVH's nodes
  size_t diceBuffers = 0;        // Rayes: the per-thread dice buffers; Embree: the whole tessellation
  size_t diceCache = 0;          // diced grids kept between uses (--grid-cache, --dice-cache), at their peak
  size_t borderBounds = 0;       // Rayes: border boxes and radii kept between dicings (fixed capacity)
  size_t film = 0;
  size_t uvSets = 0;             // the leaves' uv sets (scene/leaf_uv_table.h); 0 without any
  size_t sceneDescription = 0;   // the leaves (records, boxes, stored patches) and every per-leaf table
  size_t costLayers = 0;         // --cost-layers: the per-pixel sums and the batch's per-path counts
  uint64_t leaves = 0;
};

struct RenderStats {
  SceneFeatures features;
  std::vector<GenerationRecord> generations;
  double timeSetup = 0, timeTotal = 0, timeFilm = 0;
  TraceTimes trace;
  ShadeStats shade;
  EngineStats engine;
  uint64_t micropolygonsPotential = 0;
  uint64_t pathsPerBatch = 0, candidateCapacity = 0, batches = 0;
  uint64_t pixelsPerBlock = 0;   // batches by blocks of this many pixels, all their samples (0: sample-major)
  uint64_t splatSaturations = 0; // light tracing: splats or sums beyond the film's fixed-point range (Film)
  bool progressive = false;      // rendered in passes (asked for, or the integrator's traits)
  size_t raysPerPath = 0;        // ray slots per path (bytes_per_ray = bytesPerPath / raysPerPath)
  size_t bytesPerPath = 0, topLevelBytes = 0, diceBufferBytes = 0;
  MemoryByOwner memory;
  std::vector<ErrorSample> errorCurve;
  std::vector<std::pair<std::string, uint64_t>> leafKinds;
  MethodStats method;            // the method's own section (Integrator::methodStats)
  std::optional<TextureCacheStats> textures;  // the texture cache's figures; none: the scene reads no image
  // --cost-layers: dicings charged to pixels (exact) and the seconds apportioned to them.
  struct CostLayerTotals {
    double dicingsCharged = 0, secondsCharged = 0;
  };
  std::optional<CostLayerTotals> costLayers;
  std::vector<MemorySample> memoryOverTime;
  std::optional<BrickCacheStats> volumeCache;  // the brick cache's; none: no volume reads a file
};

class Renderer {
 public:
  // Throws InputError when the budget cannot hold a single path.
  Renderer(const Scene& scene, const RenderOptions& options);
  ~Renderer();

  // progress(done paths, total paths, samples finished so far)
  using Progress = std::function<void(uint64_t, uint64_t, int)>;
  // A batch boundary: the pass, the first id of the next camera batch in that pass's id layout
  // (0: the pass's start), the pixel block of that layout (0: sample-major ids), and the first id
  // of the pass whose first-hit AOVs the film does not hold: `next`, or the end of the batch in
  // flight when a stop came after its camera generation added them (exact where undoing a sum
  // is not, and no memory per path); a resumed render adds no AOVs below it.
  struct Position {
    int pass = 0;
    uint64_t next = 0;
    uint64_t blockPixels = 0;
    uint64_t firstHitsEnd = 0;
  };
  struct Control {
    std::function<bool()> stop;  // asked between generations and batches; true: stop (see above)
    // After every camera batch, with the film and the position of the next batch.
    std::function<void(const Film&, const Position&)> batchDone;
  };
  // The film's window: the crop, or its band for this part (light tracing: the crop).
  PixelWindow filmWindow() const;
  // Continue from a checkpoint: `film` (of filmWindow()) holds every batch before `at`.
  void resume(Film film, const Position& at);
  Film render(const Progress& progress = {}, const Control& control = {});
  // After render(): whether Control::stop stopped it, and where it stopped (or ended).
  bool interrupted() const { return interrupted_; }
  const Position& position() const { return position_; }
  const RenderStats& stats() const { return stats_; }
  // What one path costs in the ray memory budget (the unit of --ray-memory).
  size_t bytesPerPath() const { return stats_.bytesPerPath; }
  // The method being rendered with (its own statistics: Integrator::methodStats).
  const Integrator& integrator() const { return *integrator_; }
  // The per-pixel cost layers after render() (--cost-layers), or null.
  const PixelCost* pixelCost() const { return pixelCost_.get(); }

 private:
  MemoryByOwner memoryAtSetup(uint64_t raysPerPath) const;
  // Whether the ray batches keep a shutter time per ray: only when something moves.
  bool raysTimed() const { return stats_.features.movingLeaves > 0; }
  // Whether they keep the surface derivatives at the hits: only when a material reads a texture.
  bool raysKeepDerivatives() const { return stats_.features.texturedMaterials > 0; }
  // The RayBatch's bytes per ray slot: the record, and what these features and the method's
  // slot layout keep (a shadow slot of a pair keeps only its occluder: IntegratorTraits::shadowPairs).
  size_t rayBytesPerSlot() const {
    return RayBatch::bytesPerRay(raysTimed(), raysKeepDerivatives(), integrator_->traits().shadowPairs);
  }
  // The batch's sort scratch per path (RayBatch::sortScratch): the engine's candidate sort
  // (engineScratchPerRay per ray slot) and the integrator's shading sort take it in turn, so
  // the larger need, once.
  size_t sortScratchBytesPerPath(size_t engineScratchPerRay) const {
    return std::max<size_t>(integrator_->sortScratchBytesPerPath(), integrator_->raysPerPath() * engineScratchPerRay);
  }
  void traceLightPass(int s0, int s1, int pass, int& batch, const Control& control);
  struct Stopped {};  // thrown by the stop check, caught by render()
  void checkStop(const Control& control) const {
    if (control.stop && control.stop()) throw Stopped{};
  }

  const Scene& scene_;
  RenderOptions options_;
  RenderData data_;
  std::unique_ptr<Integrator> integrator_;
  std::unique_ptr<RayEngine> engine_;
  RenderStats stats_;
  std::unique_ptr<Film> resumeFilm_;
  std::unique_ptr<PixelCost> pixelCost_;
  // memory over time: the Renderer's start, the film's bytes once made, the sampling stride.
  std::chrono::steady_clock::time_point began_, renderStart_;
  size_t filmBytes_ = 0;
  uint64_t sampleStride_ = 1, sampleTick_ = 0;
  void sampleMemory(bool always);
  Position position_;
  bool interrupted_ = false;
  // One camera batch: every round of the integrator, then its film; the first-hit AOVs of its
  // ids >= firstHitsFrom (those a resumed film does not hold yet).
  void runCameraBatch(uint64_t first, uint32_t count, uint64_t firstHitsFrom, int pass, int batch, RayBatch& rays,
                      Film& film, const Control& control);
  // Where a camera batch's round 0 adds the first-hit AOVs after its camera generation: ids
  // [from, end) of the batch.
  struct FirstHitPass {
    Film& film;
    uint64_t from, end;
  };
  // Generations of the batch in `rays` until no path goes on (camera paths, or the
  // integrator's light paths).
  void runGenerations(int pass, int batch, RayBatch& rays, bool lightPaths, const Control& control,
                      const FirstHitPass* firstHits = nullptr);
};

// Root-mean-square difference of the film's mean RGB against a reference (RGB per pixel).
double rmseAgainst(const Film& film, const std::vector<float>& referenceRgb);

}  // namespace rayes
