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
// Memory: --beam-memory bounds the segments and bins of one store plus, in batches, the
// partial gathers (12 B per camera path and bounce); what cannot fit is refused with
// InputError naming --beam-memory.
#pragma once
#include <memory>
#include <span>
#include <string>
#include <vector>
#include "core/box.h"
#include "lbt/beam_batches.h"
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
  size_t batches = 0;             // ranges of seed triangles processed one after another
  int resolution = 0;             // the grid used: --beam-resolution, or the glossy rule's if coarser
  double seconds = 0;
};

class BeamIntegrator final : public Integrator {
 public:
  // scatterers: the caustic scatterer leaves' surfaces (held until prepare() has seeded the
  // beams); lights: those that send beams. The scene, top level and leaf boxes must outlive it.
  BeamIntegrator(const ShadingScene& scene, const TopLevelBvh& top, std::span<const Box3> leafBoxes,
                 std::vector<ScattererSurface> scatterers, BeamLights lights, const BeamOptions& options,
                 CausticPaths causticPaths, float laterGatherProbability);
  ~BeamIntegrator() override;

  uint32_t raysPerPath() const override { return pt_->raysPerPath(); }
  size_t bytesPerPath() const override { return pt_->bytesPerPath(); }
  size_t leafTableBytes() const override { return pt_->leafTableBytes(); }
  void prepare(const IntegratorSetup& setup) override;
  uint32_t roundsPerBatch() const override { return batches_ ? uint32_t(ranges_.size()) : 1; }
  void startRound(uint32_t round) override;
  void start(uint64_t first, uint32_t count, RayBatch& rays) override { pt_->start(first, count, rays); }
  size_t shade(uint32_t bounce, RayBatch& rays, ShadeStats& stats) override { return pt_->shade(bounce, rays, stats); }
  void finish(Film& film, ShadeStats& stats) override;
  bool setPixelBlock(uint32_t n) override { return pt_->setPixelBlock(n); }
  MethodStats methodStats() const override;

  // The beams built by prepare() (null when none were, or when they are in batches:
  // stats().skipped says why), and what the light phase did.
  const BeamStore* beams() const { return store_.get(); }
  const BeamRenderStats& stats() const { return stats_; }

 private:
  BeamTraceOptions traceOptions() const;
  std::vector<BeamSegment> traceSeeds(const BeamSeeds& seeds, const BeamTraceOptions& to, BeamTraceStats& stats) const;
  std::unique_ptr<BeamStore> traceRange(size_t first, size_t last, size_t budget, BeamTraceStats& stats) const;
  int chooseResolution() const;
  void buildBeams();

  const ShadingScene& scene_;
  const TopLevelBvh& top_;
  std::span<const Box3> leafBoxes_;
  std::vector<ScattererSurface> scatterers_;
  BeamLights lights_;
  BeamOptions options_;
  CausticPaths causticPaths_;
  float laterGatherProbability_;
  std::unique_ptr<PathTracer> pt_;
  IntegratorSetup setup_;
  BeamSeeds seeds_;
  std::unique_ptr<BeamStore> store_;  // the only range's, or the one in use
  std::vector<std::pair<size_t, size_t>> ranges_;
  size_t storeBudget_ = 0;  // each range's store: --beam-memory less the partial gathers when batched
  std::unique_ptr<BeamBatches> batches_;
  BeamRenderStats stats_;
};

}  // namespace rayes
