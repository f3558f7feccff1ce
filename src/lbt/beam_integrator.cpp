#include "lbt/beam_integrator.h"
#include <algorithm>
#include "core/error.h"
#include "core/timer.h"
#include "lbt/beam_resolution.h"

namespace rayes {

BeamIntegrator::BeamIntegrator(const ShadingScene& scene, const TopLevelBvh& top, std::span<const Box3> leafBoxes,
                               std::vector<ScattererSurface> scatterers, BeamLights lights, const BeamOptions& options,
                               CausticPaths causticPaths, float laterGatherProbability)
    : scene_(scene), top_(top), leafBoxes_(leafBoxes), scatterers_(std::move(scatterers)), lights_(std::move(lights)),
      options_(options), causticPaths_(causticPaths), laterGatherProbability_(laterGatherProbability),
      // Until the beams are built (and for good when none are): its bytes per path hold the
      // gathers the beams will post.
      pt_(std::make_unique<PathTracer>(scene, PathTracer::Options{.causticPaths = causticPaths, .gathersAsLeafQueries = true})) {}

BeamIntegrator::~BeamIntegrator() = default;

void BeamIntegrator::prepare(const IntegratorSetup& setup) {
  setup_ = setup;
  buildBeams();
  scatterers_.clear();  // their patches were needed for the seeds alone
  scatterers_.shrink_to_fit();
}

BeamTraceOptions BeamIntegrator::traceOptions() const {
  const Box3 bounds = top_.bounds();
  BeamTraceOptions to;
  to.maxDepth = options_.maxDepth;
  to.splitDepth = options_.splitDepth;
  to.far = 4 * (length(bounds.extent()) + bounds.magnitude()) + 1;
  to.raysPerTrace = std::max<size_t>(1, setup_.pathsPerBatch * pt_->raysPerPath());
  return to;
}

std::vector<BeamSegment> BeamIntegrator::traceSeeds(const BeamSeeds& seeds, const BeamTraceOptions& to,
                                                    BeamTraceStats& stats) const {
  return traceBeams(scene_, seeds, to, setup_.trace, stats);
}

std::unique_ptr<BeamStore> BeamIntegrator::traceRange(size_t first, size_t last, size_t budget,
                                                      BeamTraceStats& stats) const {
  std::vector<BeamSegment> segments = traceSeeds(seeds_.range(first, last), traceOptions(), stats);
  std::vector<uint8_t> leafReceives(scene_.leafMaterial.size());
  for (size_t l = 0; l < leafReceives.size(); ++l)
    leafReceives[l] = isCausticScatterer(scene_.materials[scene_.leafMaterial[l]]) ? 0 : 1;
  return std::make_unique<BeamStore>(std::move(segments), top_, leafBoxes_, budget, leafReceives,
                                     scene_.integrator.maxDepth);
}

// --beam-resolution, or the glossy rule's coarser grid (lbt/beam_resolution.h) from a probe of
// one bounce without splits at a resolution of at most kProbe.
int BeamIntegrator::chooseResolution() const {
  constexpr int kProbe = 16;
  const int requested = options_.resolution;
  if (!(options_.lobeCells > 0)) return requested;
  const int probeResolution = std::min(requested, kProbe);
  BeamTraceOptions to = traceOptions();
  to.maxDepth = 1;
  to.splitDepth = 0;
  BeamTraceStats probeStats;  // not the render's beams: not counted
  const std::vector<BeamSegment> probe =
      traceSeeds(seedBeams(lights_, scatterers_, top_.bounds(), probeResolution), to, probeStats);
  const int lobe = lobeResolution(probe, probeResolution, options_.lobeCells, to.far);
  return lobe > 0 ? std::min(requested, lobe) : requested;
}

void BeamIntegrator::buildBeams() {
  const auto t0 = Clock::now();
  BeamRenderStats& bs = stats_;
  if (scatterers_.empty() || lights_.empty()) {
    bs.skipped = scatterers_.empty() ? "no specular or glossy surface: no beams traced, lbt is the path tracer"
                                     : "no point, spot, distant or area light (--beam-area-samples 0 leaves area lights out): no beams "
                                       "traced, lbt is the path tracer";
    return;
  }
  bs.resolution = chooseResolution();
  seeds_ = seedBeams(lights_, scatterers_, top_.bounds(), bs.resolution);
  // The ranges of seed triangles whose beams fit the budget: all of them if they do, else
  // halves, quarters, ... (a tried range's segments are held once before they are binned).
  // Batches keep a partial gather per (path, bounce) of a camera batch (BeamBatches): those
  // share the budget, so every range's store gets what they leave.
  const size_t roots = seeds_.triangles.size();
  const int maxDepth = scene_.integrator.maxDepth;
  const size_t partialBytes = BeamBatches::bytesFor(setup_.pathsPerBatch, maxDepth);
  size_t budget = options_.memoryBytes;  // one store of every beam: no partial gathers
  size_t count = roots, segments = 0;
  for (size_t first = 0; first < roots; first += count) {
    count = std::min(count, roots - first);
    for (;;) {
      BeamTraceStats trial;
      std::unique_ptr<BeamStore> store = traceRange(first, first + count, budget, trial);
      if (count == roots && !store->fits()) {
        const size_t oneBeam = BeamStore::minimumBytes(leafBoxes_.size());
        if (partialBytes + oneBeam > options_.memoryBytes)
          throw InputError("--beam-memory", "",
                           "a budget of " + std::to_string(options_.memoryBytes) +
                               " bytes cannot hold the beams in batches: the partial gathers of a camera batch take " +
                               std::to_string(partialBytes) + " bytes (" + std::to_string(setup_.pathsPerBatch) +
                               " paths x " + std::to_string(std::max(maxDepth, 1)) + " bounces x " +
                               std::to_string(sizeof(Rgb)) + " B) besides " + std::to_string(oneBeam) +
                               " for one beam; raise --beam-memory or lower --ray-memory");
        budget = options_.memoryBytes - partialBytes;  // what did not fit the whole budget fits no less
      }
      if (store->fits()) {
        bs.trace.add(trial);  // a trial that did not fit is not counted
        bs.binEntries += store->binEntries();
        bs.bytes = std::max(bs.bytes, store->bytes());
        segments += store->segmentCount();
        ranges_.push_back({first, first + count});
        store_ = std::move(store);
        break;
      }
      if (count == 1)
        throw InputError("--beam-memory", "", "a budget of " + std::to_string(budget) +
                         " bytes cannot hold one beam (seed triangle " + std::to_string(first) + " needs " +
                         std::to_string(store->neededBytes()) + " bytes for its segments and bins" +
                         (budget < options_.memoryBytes ? " besides the partial gathers of a camera batch)" : ")"));
      count = (count + 1) / 2;
    }
  }
  bs.batches = ranges_.size();
  storeBudget_ = budget;
  bs.seconds = secondsSince(t0);
  if (segments == 0) {
    bs.skipped = "no beam reached past a specular or glossy surface: lbt is the path tracer";
    store_.reset();
    ranges_.clear();
    return;
  }
  // The path tracer leaves caustic paths to the beams (same bytes per path as the one the
  // budget was computed with).
  const CausticRadiance* caustics = store_.get();
  if (ranges_.size() > 1) {
    store_.reset();
    batches_ = std::make_unique<BeamBatches>(setup_.pathsPerBatch, maxDepth);
    caustics = batches_.get();
    bs.bytes += batches_->bytes();
  }
  // Environment lights get no beams: their caustic paths stay with the path tracer (with
  // --caustic-paths only, those paths alone besides the beams).
  const uint8_t covered = kPointLight | kSpotLight | kDistantLight | (lights_.patches.empty() ? 0 : kPatchLight);
  const bool only = causticPaths_ == CausticPaths::Only;
  pt_ = std::make_unique<PathTracer>(
      scene_, PathTracer::Options{.causticPaths = only ? CausticPaths::Only : CausticPaths::Without,
                                  .causticRadiance = caustics,
                                  .causticLights = only ? uint8_t(kAllLights & ~covered) : covered,
                                  .gathersAsLeafQueries = !options_.gathersInShading,
                                  .laterGatherProbability = laterGatherProbability_});
  bs.built = true;
}

void BeamIntegrator::startRound(uint32_t round) {
  if (!batches_) return;
  // Beams in batches: the camera paths once per range of beams, the film from the last.
  if (round == 0) batches_->startPaths();
  store_.reset();
  BeamTraceStats again;
  store_ = traceRange(ranges_[round].first, ranges_[round].second, storeBudget_, again);
  batches_->use(store_.get());
}

void BeamIntegrator::finish(Film& film, ShadeStats& stats) {
  if (batches_) {
    batches_->use(nullptr);
    store_.reset();
  }
  pt_->finish(film, stats);
}

MethodStats BeamIntegrator::methodStats() const {
  MethodStats m;
  m.section = "beams";
  const BeamRenderStats& b = stats_;
  if (!b.built) m.skipped.push_back({"beams", b.skipped});
  m.add("generator_triangles", b.trace.generatorTriangles);
  m.add("corner_rays", b.trace.cornerRays);
  m.add("generations", int64_t(b.trace.generations));
  m.add("segments", b.trace.segments);
  m.add("bin_entries", b.binEntries);
  m.add("bytes", uint64_t(b.bytes));
  m.add("seconds", b.seconds);
  m.add("resolution", int64_t(b.resolution));
  m.add("requested_resolution", int64_t(options_.resolution));
  m.add("lobe_cells", options_.lobeCells);
  m.add("max_depth", int64_t(options_.maxDepth));
  m.add("memory_budget_bytes", uint64_t(options_.memoryBytes));
  m.add("batches", uint64_t(b.batches));
  m.add("split_depth", int64_t(options_.splitDepth));
  m.add("splits", b.trace.splits);
  m.add("reflected_branches", b.trace.reflectedBranches);
  m.add("dropped_flux_watts", b.trace.droppedFlux);
  m.add("stopped.mixed", b.trace.stoppedMixed);
  m.add("stopped.silhouette", b.trace.stoppedSilhouette);
  m.add("stopped.tir_straddle", b.trace.stoppedTir);
  m.add("stopped.divergent", b.trace.stoppedDivergent);
  return m;
}

}  // namespace rayes
