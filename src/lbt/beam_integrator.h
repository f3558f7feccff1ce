// Light beam tracing as an integrator (`--method lbt`; docs/design.md, "Light beam tracing"):
// the path tracer without caustic paths, plus the beams' caustic gather at every diffuse
// vertex of a camera path. It owns all of it: the seeds, the beam store (or, when the beams
// do not fit --beam-memory, the ranges of seed triangles and the partial gathers of
// BeamBatches), and the path tracer it wraps.
//
//   construction  the path tracer it starts as (gathers as leaf queries, so its bytes per path
//                 hold the gathers the beams will post): what the Renderer sizes batches by;
//   prepare()     the light phase, through the render's engine: the glossy rule's resolution
//                 from a probe, the seeds, the corner rays' generations, the segments binned by
//                 leaf; ranges under the budget; then the path tracer that leaves caustic
//                 paths to the beams (same bytes per path). No scatterer or no light: it stays
//                 the path tracer, and methodStats() says why;
//   rounds        with beams in batches, every camera batch is traced once per range of seed
//                 triangles (startRound traces that range again), and only the last round's
//                 film is added: bit-identical to one store (lbt/beam_batches.h).
//
// Memory: --beam-memory is one account (lbt/beam_budget.h) every byte of the beams is taken
// from before it is allocated: the probe's widths, the seeds (streamed in chunks of grid rows),
// the tracer's working set and split children (a chunk that does not fit is traced in halves),
// a range's segments, its store's bins, envelopes and binning, in batches the partial gathers
// (12 B per camera path and bounce), and while beams are traced the diced grids the engine keeps
// between the corner rays' traces (KeptGrids). What cannot fit even for one seed triangle is
// refused with ResourceError naming --beam-memory (exit code 3). The stats' peak_bytes is the
// account's high-water mark.
#pragma once
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>
#include "core/box.h"
#include "lbt/beam_batches.h"
#include "lbt/beam_budget.h"
#include "lbt/beam_seeds.h"
#include "lbt/beam_store.h"
#include "lbt/beam_tracer.h"
#include "shading/integrator.h"
#include "shading/path_tracer.h"
#include "toplevel/toplevel_bvh.h"

namespace rayes {

struct BeamOptions {
  int resolution = 128;           // cells per side of a light's grid
  int maxDepth = 4;               // specular/glossy bounces
  int splitDepth = 4;             // times an incoherent beam is split before it is dropped
  int areaSamples = 2;            // k: an area light is k×k point sources (0: no beams from area lights)
  size_t memoryBytes = size_t(1) << 30;
  // Glossy beams: the grid is coarsened to about this many lobe widths σ per beam
  // (lbt/beam_resolution.h); 0 keeps `resolution`.
  double lobeCells = 2;
  // The beam gathers in the shading step, as pm's (not leaf queries of the next trace): the
  // reference the leaf queries are checked against, bit for bit (tests/lbt/beam_render_test.cpp).
  bool gathersInShading = false;
};

// What the light phase did (the stats file's "beams" section), or why nothing was built.
struct BeamRenderStats {
  bool built = false;
  std::string skipped;            // the reason, when not built
  BeamTraceStats trace;
  uint64_t binEntries = 0;
  size_t bytes = 0;               // the largest batch's segments and bins
  size_t peakBytes = 0;           // the most the beams held at once (lbt/beam_budget.h): ≤ --beam-memory
  size_t batches = 0;             // ranges of seed triangles processed one after another
  int resolution = 0;             // the grid used: --beam-resolution, or the glossy rule's if coarser
  double seconds = 0;
};

class BeamIntegrator final : public Integrator {
 public:
  // scatterers: the caustic scatterer leaves' surfaces (held until prepare() has seeded the
  // beams); lights: those that send beams. The scene, top level and leaf boxes must outlive it.
  BeamIntegrator(const ShadingScene& scene, const TopLevelBvh& top, GatedSpan<Box3> leafBoxes,
                 std::vector<ScattererSurface> scatterers, BeamLights lights, const BeamOptions& options,
                 CausticPaths causticPaths, float laterGatherProbability);
  ~BeamIntegrator() override;

  IntegratorTraits traits() const override { return {.beamsUpFront = true, .shadowPairs = true}; }
  uint32_t raysPerPath() const override { return pt_->raysPerPath(); }
  size_t bytesPerPath() const override { return pt_->bytesPerPath(); }
  size_t sortScratchBytesPerPath() const override { return pt_->sortScratchBytesPerPath(); }
  size_t leafTableBytes() const override { return pt_->leafTableBytes(); }
  void prepare(const IntegratorSetup& setup) override;
  uint32_t roundsPerBatch() const override { return batches_ ? uint32_t(ranges_.size()) : 1; }
  void startRound(uint32_t round) override;
  void start(uint64_t first, uint32_t count, RayBatch& rays) override { pt_->start(first, count, rays); }
  size_t shade(uint32_t bounce, RayBatch& rays, ShadeStats& stats) override { return pt_->shade(bounce, rays, stats); }
  void finish(Film& film, ShadeStats& stats) override;
  void addFirstHits(RayBatch& rays, Film& film, uint64_t from) override { pt_->addFirstHits(rays, film, from); }
  bool setPixelBlock(uint32_t n) override { return pt_->setPixelBlock(n); }
  bool setPixelWindow(const PixelWindow& window) override { return pt_->setPixelWindow(window); }
  int64_t cameraPixelOf(uint64_t id) const override { return pt_->cameraPixelOf(id); }
  MethodStats methodStats() const override;

  // The beams built by prepare() (null when none were, or when they are in batches:
  // stats().skipped says why), and what the light phase did.
  const BeamStore* beams() const { return range_ && !batches_ ? range_->store.get() : nullptr; }
  const BeamRenderStats& stats() const { return stats_; }

 private:
  // A range's store and the bytes of its segments (its other bytes are the store's own).
  struct Range {
    BeamCharge segments;
    std::unique_ptr<BeamStore> store;
  };
  using SegmentsUse = std::function<void(std::vector<BeamSegment>&&, BeamCharge&&, size_t end, const BeamTraceStats&)>;
  static constexpr size_t kAllRoots = ~size_t(0);
  // While it lives, the engine's grids kept between the corner rays' traces are on the budget
  // (BeamBudget::keep): trace() lets the engine keep what the budget has free and charges what
  // it kept; at its end they are freed and the engine gets its own bound back.
  class KeptGrids {
   public:
    // `current` points at it while it lives.
    KeptGrids(BeamBudget& budget, const std::function<size_t(size_t)>& limit, const KeptGrids*& current);
    ~KeptGrids();
    KeptGrids(const KeptGrids&) = delete;
    KeptGrids& operator=(const KeptGrids&) = delete;
    void trace(const std::function<void(RayBatch&)>& trace, RayBatch& rays) const;

   private:
    BeamBudget& budget_;
    std::function<size_t(size_t)> limit_;
    const KeptGrids*& current_;
  };

  BeamTraceOptions traceOptions() const;
  void traceChunk(const BeamSeeds& seeds, size_t first, const BeamTraceOptions& to, const SegmentsUse& use);
  void traceSeeds(int resolution, size_t first, size_t last, const BeamTraceOptions& to, const SegmentsUse& use);
  std::vector<uint8_t> leafReceives() const;
  std::unique_ptr<Range> storeOf(std::vector<BeamSegment> segments, BeamCharge charge);
  std::unique_ptr<Range> traceRange(size_t first, size_t last, BeamTraceStats& stats);
  static void appendSegments(std::vector<BeamSegment>& segments, BeamCharge& charge, std::vector<BeamSegment>&& part,
                             BeamCharge&& partCharge);
  void takePartialGathers();
  void splitRange(size_t first, size_t last, BeamTraceStats& stats);
  void recordRange(size_t first, size_t last, const Range& range, const BeamTraceStats& trace, BeamTraceStats& stats);
  int chooseResolution();
  void buildBeams();

  const ShadingScene& scene_;
  const TopLevelBvh& top_;
  GatedSpan<Box3> leafBoxes_;
  std::vector<ScattererSurface> scatterers_;
  BeamLights lights_;
  BeamOptions options_;
  CausticPaths causticPaths_;
  float laterGatherProbability_;
  std::unique_ptr<PathTracer> pt_;
  IntegratorSetup setup_;
  BeamBudget budget_;  // before everything it accounts for, so it outlives them
  const KeptGrids* keptGrids_ = nullptr;  // while beams are traced
  std::function<bool()> makeRoom_;  // while ranges are gathered: closes the current one (false: empty)
  size_t chunkTriangles_ = 1;  // seed triangles per chunk traced at once (lowered when one does not fit)
  BeamCharge partialCharge_;
  std::unique_ptr<Range> range_;  // the only range's store, or the one in use
  std::vector<std::pair<size_t, size_t>> ranges_;  // seed triangles [first, last) of each range
  uint64_t segmentCount_ = 0;
  std::unique_ptr<BeamBatches> batches_;
  BeamRenderStats stats_;
};

}  // namespace rayes
