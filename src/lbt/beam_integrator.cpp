#include "lbt/beam_integrator.h"
#include <algorithm>
#include <cstdint>
#include "core/error.h"
#include "core/timer.h"
#include "lbt/beam_resolution.h"
#include "shading/material.h"

namespace rayes {

BeamIntegrator::BeamIntegrator(const ShadingScene& scene, const TopLevelBvh& top, GatedSpan<Box3> leafBoxes,
                               std::vector<ScattererSurface> scatterers, BeamLights lights, const BeamOptions& options,
                               CausticPaths causticPaths, float laterGatherProbability)
    : scene_(scene), top_(top), leafBoxes_(leafBoxes), scatterers_(std::move(scatterers)), lights_(std::move(lights)),
      options_(options), causticPaths_(causticPaths), laterGatherProbability_(laterGatherProbability),
      // Until the beams are built (and for good when none are): its bytes per path hold the
      // gathers the beams will post.
      pt_(std::make_unique<PathTracer>(scene, PathTracer::Options{.causticPaths = causticPaths, .gathersAsLeafQueries = true})),
      budget_(options.memoryBytes) {}

BeamIntegrator::~BeamIntegrator() = default;

// The diced grids the engine keeps between the corner rays' traces are the beams' memory: the
// corner rays' narrow cones ask for grids far finer than the camera's (they filled 178 MB of the
// engine's cache on two quads at --beam-resolution 1024 with a 64 MiB budget, bench/history/
// 2026-11.md). While beams are traced, each trace may keep grids in what the account has free,
// and they are charged to it after the trace (BeamBudget::keep); a take() that does not fit
// frees them first. When the tracing ends they are freed, so the camera paths start from the
// engine's own grid cache as without beams. A tight budget only dices more often; no hit changes.
BeamIntegrator::KeptGrids::KeptGrids(BeamBudget& budget, const std::function<size_t(size_t)>& limit,
                                     const KeptGrids*& current)
    : budget_(budget), limit_(limit), current_(current) {
  current_ = this;
  if (limit_) budget_.shrinkKeptWith(limit_);
}

void BeamIntegrator::KeptGrids::trace(const std::function<void(RayBatch&)>& trace, RayBatch& rays) const {
  if (!limit_) return trace(rays);
  limit_(budget_.kept() + budget_.left());
  trace(rays);
  budget_.keep(limit_(budget_.kept() + budget_.left()));
}

BeamIntegrator::KeptGrids::~KeptGrids() {
  current_ = nullptr;
  if (!limit_) return;
  budget_.keep(limit_(0));
  budget_.shrinkKeptWith(nullptr);
  limit_(SIZE_MAX);
}

void BeamIntegrator::prepare(const IntegratorSetup& setup) {
  setup_ = setup;
  {
    const KeptGrids grids(budget_, setup_.limitKeptGrids, keptGrids_);
    buildBeams();
  }
  if (batches_) return;  // every round seeds its range again
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

// A chunk of seeds traced under the budget: halves, quarters, ... when its beams' working set
// does not fit (each part handed to `use` in order); one seed triangle that does not fit alone is
// refused. Only the runs that fit are counted in `stats`.
void BeamIntegrator::traceChunk(const BeamSeeds& seeds, size_t first, const BeamTraceOptions& to,
                                const SegmentsUse& use) {
  BeamCharge keep;
  std::vector<BeamSegment> segments;
  BeamTraceStats stats;
  try {
    // Chunks are traced only inside prepare()'s and startRound()'s KeptGrids.
    const auto trace = [this](RayBatch& rays) { keptGrids_->trace(setup_.trace, rays); };
    segments = traceBeams(scene_, seeds, to, trace, stats, &budget_, &keep);
  } catch (const BeamBudgetExceeded& e) {
    // First the range being gathered makes room (closes: its store is built and freed), then
    // the chunk is halved.
    if (makeRoom_ && makeRoom_()) {
      traceChunk(seeds, first, to, use);
      return;
    }
    const size_t n = seeds.triangles.size();
    if (n <= 1)
      throw ResourceError("--beam-memory", "a budget of " + std::to_string(budget_.limit()) +
                                               " bytes cannot trace one beam (seed triangle " + std::to_string(first) +
                                               ": " + e.what() + "); raise --beam-memory or lower --beam-split-depth, "
                                               "--beam-depth or --beam-area-samples");
    chunkTriangles_ = std::max<size_t>(1, std::min(chunkTriangles_, n) / 2);  // the next chunks too
    for (const auto& [a, b] : {std::pair<size_t, size_t>{0, n / 2}, std::pair<size_t, size_t>{n / 2, n}}) {
      const BeamCharge part(&budget_, seeds.org.size() * sizeof(uint32_t) + BeamSeeds::bytesFor(seeds.org.size(), b - a),
                            "half a chunk of beam seeds");
      traceChunk(seeds.range(a, b), first + a, to, use);
    }
    return;
  }
  use(std::move(segments), std::move(keep), first + seeds.triangles.size(), stats);
}

// The seed triangles [first, last) of the render's grid traced chunk by chunk; `use` gets each
// chunk's segments, in order, with the root after them.
void BeamIntegrator::traceSeeds(int resolution, size_t first, size_t last, const BeamTraceOptions& to,
                                const SegmentsUse& use) {
  seedBeams(lights_, scatterers_, top_.bounds(), resolution, chunkTriangles_, first, last, &budget_,
            [&](SeedChunk&& chunk) {
              const SeedChunk held = std::move(chunk);
              traceChunk(held.seeds, held.first, to, use);
            });
}

std::vector<uint8_t> BeamIntegrator::leafReceives() const {
  std::vector<uint8_t> receives(scene_.leafCount());
  for (size_t l = 0; l < receives.size(); ++l)
    receives[l] = isCausticScatterer(scene_.materials[scene_.materialOf(uint32_t(l))]) ? 0 : 1;
  return receives;
}

// The store of segments already traced (their bytes on `charge`, which it then holds), or null
// when it does not fit what the budget has left.
std::unique_ptr<BeamIntegrator::Range> BeamIntegrator::storeOf(std::vector<BeamSegment> segments, BeamCharge charge) {
  const BeamCharge receivesBytes(&budget_, scene_.leafCount(), "the beams' receiving leaves");
  const std::vector<uint8_t> receives = leafReceives();
  auto range = std::make_unique<Range>();
  range->segments = std::move(charge);
  range->store = std::make_unique<BeamStore>(std::move(segments), top_, leafBoxes_, budget_.limit(), receives,
                                             scene_.integrator.maxDepth, &budget_);
  if (!range->store->fits()) return nullptr;
  return range;
}

// Roots [first, last) traced again and stored: a range found at setup (so it fits), or a part of
// one whose store did not fit (null again when it does not).
std::unique_ptr<BeamIntegrator::Range> BeamIntegrator::traceRange(size_t first, size_t last, BeamTraceStats& stats) {
  std::vector<BeamSegment> segments;
  BeamCharge charge(&budget_, 0, "");
  traceSeeds(stats_.resolution, first, last, traceOptions(),
             [&](std::vector<BeamSegment>&& part, BeamCharge&& partCharge, size_t, const BeamTraceStats& partStats) {
               appendSegments(segments, charge, std::move(part), std::move(partCharge));
               stats.add(partStats);
             });
  return storeOf(std::move(segments), std::move(charge));
}

// Appends `part` to `segments` (growing its array on `charge` first: BeamBudgetExceeded when
// the larger array does not fit beside the smaller one).
void BeamIntegrator::appendSegments(std::vector<BeamSegment>& segments, BeamCharge& charge,
                                    std::vector<BeamSegment>&& part, BeamCharge&& partCharge) {
  if (segments.empty()) {
    segments = std::move(part);
    charge.release();
    charge = std::move(partCharge);
    return;
  }
  const size_t need = segments.size() + part.size();
  if (need > segments.capacity()) {
    const size_t grown = std::max(need, 2 * segments.capacity());
    charge.add(grown * sizeof(BeamSegment), "beam segments of a range");
    std::vector<BeamSegment> bigger;
    bigger.reserve(grown);
    bigger.insert(bigger.end(), segments.begin(), segments.end());
    charge.sub(segments.capacity() * sizeof(BeamSegment));
    segments = std::move(bigger);
  }
  segments.insert(segments.end(), part.begin(), part.end());
}

// The partial gathers of batches, taken when the beams turn out not to fit at once; refused
// when the budget cannot hold them and one beam.
void BeamIntegrator::takePartialGathers() {
  if (partialCharge_.bytes() > 0) return;
  const int maxDepth = scene_.integrator.maxDepth;
  const size_t partialBytes = BeamBatches::bytesFor(setup_.pathsPerBatch, maxDepth);
  const size_t oneBeam = BeamStore::minimumBytes(leafBoxes_.size());
  const std::string why = " the partial gathers of a camera batch take " + std::to_string(partialBytes) + " bytes (" +
                          std::to_string(setup_.pathsPerBatch) + " paths x " + std::to_string(std::max(maxDepth, 1)) +
                          " bounces x " + std::to_string(sizeof(Rgb)) + " B) besides " + std::to_string(oneBeam) +
                          " for one beam; raise --beam-memory or lower --ray-memory";
  if (partialBytes + oneBeam > budget_.left())
    throw ResourceError("--beam-memory", "a budget of " + std::to_string(options_.memoryBytes) +
                                             " bytes cannot hold the beams in batches: " + std::to_string(budget_.used()) +
                                             " bytes are in use, and" + why);
  partialCharge_ = BeamCharge(&budget_, partialBytes, "the partial gathers of batches");
}

// Roots [first, last) whose store did not fit: stored in halves, quarters, ... each recorded as
// a range (and checked to fit); one root whose store does not fit alone is refused.
void BeamIntegrator::splitRange(size_t first, size_t last, BeamTraceStats& stats) {
  const size_t mid = first + (last - first) / 2;
  for (const auto& [a, b] : {std::pair<size_t, size_t>{first, mid}, std::pair<size_t, size_t>{mid, last}}) {
    if (a == b) continue;
    BeamTraceStats part;
    std::unique_ptr<Range> range = traceRange(a, b, part);
    if (range) {
      recordRange(a, b, *range, part, stats);
      continue;
    }
    if (b - a == 1)
      throw ResourceError("--beam-memory", "a budget of " + std::to_string(budget_.limit()) +
                                               " bytes cannot hold the store of one beam (seed triangle " +
                                               std::to_string(a) + ") besides the partial gathers of a camera batch; "
                                               "raise --beam-memory");
    splitRange(a, b, stats);
  }
}

void BeamIntegrator::recordRange(size_t first, size_t last, const Range& range, const BeamTraceStats& trace,
                                 BeamTraceStats& stats) {
  stats.add(trace);
  stats_.binEntries += range.store->binEntries();
  stats_.bytes = std::max(stats_.bytes, range.store->bytes());
  segmentCount_ += range.store->segmentCount();
  if (range.store->segmentCount() > 0) ranges_.push_back({first, last});
}

// --beam-resolution, or the glossy rule's coarser grid (lbt/beam_resolution.h) from a probe of
// one bounce without splits at a resolution of at most kProbe (its widths on the budget).
int BeamIntegrator::chooseResolution() {
  constexpr int kProbe = 16;
  const int requested = options_.resolution;
  if (!(options_.lobeCells > 0)) return requested;
  const int probeResolution = std::min(requested, kProbe);
  BeamTraceOptions to = traceOptions();
  to.maxDepth = 1;
  to.splitDepth = 0;
  std::vector<double> widths;  // the probe is not the render's beams: its stats are not counted
  BeamCharge widthBytes(&budget_, 0, "");
  size_t specular = 0;
  traceSeeds(probeResolution, 0, kAllRoots, to,
             [&](std::vector<BeamSegment>&& segments, BeamCharge&&, size_t, const BeamTraceStats&) {
               widthBytes.add(segments.size() * sizeof(double), "the glossy probe's widths");
               widths.reserve(widths.size() + segments.size());
               addProbeWidths(segments, to.far, widths, specular);
             });
  const int lobe = lobeResolution(widths, specular, probeResolution, options_.lobeCells);
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
  // Chunks of seed triangles whose beams' working set is about a quarter of the budget at
  // about 1 KiB per triangle (seeds, corner rays, a generation's scatterings, segments); halved
  // when one does not fit (traceChunk).
  chunkTriangles_ = std::clamp<size_t>(options_.memoryBytes / 4096, 1, size_t(1) << 20);
  try {
    bs.resolution = chooseResolution();
  } catch (const BeamBudgetExceeded& e) {
    throw ResourceError("--beam-memory", std::string("the glossy resolution rule's probe does not fit: ") + e.what() +
                                             "; raise --beam-memory or set --beam-lobe-cells 0");
  }
  // The ranges of seed triangles whose beams fit the budget: segments gathered chunk by chunk
  // into a range while they take at most a quarter of what the budget has (the store's bins,
  // envelopes and binning need the rest), then the range's store is built to check that it
  // fits (kept when it is the only range). A range that cannot take the next chunk closes
  // before it. When the beams turn out not to fit at once, the partial gathers of batches
  // (12 B per camera path and bounce) are taken from the budget first.
  // Batches are known to be needed only when a range closes before the last seed: then the
  // light phase starts again with the partial gathers taken first (so every range is built
  // with them held, as its rounds will be), at most once.
  struct Restart {};
  std::unique_ptr<Range> only;
  std::vector<std::pair<size_t, size_t>> unfit;  // ranges whose store did not fit
  const auto stream = [&] {
    std::vector<BeamSegment> segments;
    BeamCharge charge(&budget_, 0, "");
    BeamTraceStats trace;
    size_t rangeFirst = 0, rangeLast = 0;
    bool full = false;
    const auto close = [&](bool last) {
      const bool batched = partialCharge_.bytes() > 0;
      if (!last && !batched) throw Restart{};
      const size_t first = rangeFirst, end = rangeLast;
      const BeamTraceStats closed = trace;
      trace = {};
      std::unique_ptr<Range> range = storeOf(std::move(segments), std::move(charge));
      segments = {};
      charge = BeamCharge(&budget_, 0, "");
      rangeFirst = rangeLast;
      full = false;
      if (!range) {
        if (!batched) throw Restart{};
        unfit.push_back({first, end});  // split once the seeds are no longer held
        return;
      }
      recordRange(first, end, *range, closed, bs.trace);
      if (last && ranges_.size() == 1 && !batched) only = std::move(range);
    };
    makeRoom_ = [&] {
      if (segments.empty()) return false;
      close(false);
      return true;
    };
    traceSeeds(bs.resolution, 0, kAllRoots, traceOptions(),
               [&](std::vector<BeamSegment>&& part, BeamCharge&& partCharge, size_t end, const BeamTraceStats& partStats) {
                 if (full) close(false);
                 try {
                   appendSegments(segments, charge, std::move(part), std::move(partCharge));
                 } catch (const BeamBudgetExceeded&) {
                   // part (and its bytes) came back untouched: it starts the next range.
                   close(false);
                   appendSegments(segments, charge, std::move(part), std::move(partCharge));
                 }
                 trace.add(partStats);
                 rangeLast = end;
                 full = charge.bytes() > budget_.left() / 3;
               });
    makeRoom_ = nullptr;
    if (rangeLast > rangeFirst) close(ranges_.empty());
    for (const auto& [first, last] : unfit) splitRange(first, last, bs.trace);
    // In root order: a gather continues the previous ranges' sums in segment order.
    std::sort(ranges_.begin(), ranges_.end());
  };
  try {
    try {
      stream();
    } catch (const Restart&) {
      makeRoom_ = nullptr;
      ranges_.clear();
      unfit.clear();
      bs.trace = {};
      bs.binEntries = 0;
      bs.bytes = 0;
      segmentCount_ = 0;
      takePartialGathers();
      stream();
    }
  } catch (const BeamBudgetExceeded& e) {
    makeRoom_ = nullptr;
    throw ResourceError("--beam-memory", "a budget of " + std::to_string(budget_.limit()) +
                                             " bytes cannot hold the beams' seeds and one range of them: " + e.what() +
                                             "; raise --beam-memory");
  }
  bs.batches = ranges_.size();
  bs.seconds = secondsSince(t0);
  if (segmentCount_ == 0) {
    bs.skipped = "no beam reached past a specular or glossy surface: lbt is the path tracer";
    ranges_.clear();
    partialCharge_.release();
    bs.peakBytes = budget_.peak();
    return;
  }
  // The path tracer leaves caustic paths to the beams (same bytes per path as the one the
  // budget was computed with).
  const CausticRadiance* caustics = nullptr;
  const int maxDepth = scene_.integrator.maxDepth;
  if (only) {
    range_ = std::move(only);
    caustics = range_->store.get();
    partialCharge_.release();
  } else {
    takePartialGathers();
    batches_ = std::make_unique<BeamBatches>(setup_.pathsPerBatch, maxDepth);
    caustics = batches_.get();
    bs.bytes += batches_->bytes();
  }
  bs.peakBytes = budget_.peak();
  // Environment lights get no beams: their caustic paths stay with the path tracer (with
  // --caustic-paths only, those paths alone besides the beams).
  const uint8_t covered = kPointLight | kSpotLight | kDistantLight | (lights_.patches.empty() ? 0 : kPatchLight);
  const bool onlyCaustics = causticPaths_ == CausticPaths::Only;
  pt_ = std::make_unique<PathTracer>(
      scene_, PathTracer::Options{.causticPaths = onlyCaustics ? CausticPaths::Only : CausticPaths::Without,
                                  .causticRadiance = caustics,
                                  .causticLights = onlyCaustics ? uint8_t(kAllLights & ~covered) : covered,
                                  .gathersAsLeafQueries = !options_.gathersInShading,
                                  .laterGatherProbability = laterGatherProbability_});
  bs.built = true;
}

void BeamIntegrator::startRound(uint32_t round) {
  if (!batches_) return;
  // Beams in batches: the camera paths once per range of beams, the film from the last.
  if (round == 0) batches_->startPaths();
  batches_->use(nullptr);
  range_.reset();
  BeamTraceStats again;
  {
    const KeptGrids grids(budget_, setup_.limitKeptGrids, keptGrids_);
    range_ = traceRange(ranges_[round].first, ranges_[round].second, again);
  }
  if (!range_) throw std::logic_error("a range of beams that fit at setup no longer fits --beam-memory");
  stats_.peakBytes = std::max(stats_.peakBytes, budget_.peak());
  batches_->use(range_->store.get());
}

void BeamIntegrator::finish(Film& film, ShadeStats& stats) {
  if (batches_) {
    batches_->use(nullptr);
    range_.reset();
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
  m.add("peak_bytes", uint64_t(b.peakBytes));
  m.add("seconds", b.seconds);
  m.add("resolution", int64_t(b.resolution));
  m.add("requested_resolution", int64_t(options_.resolution));
  m.add("lobe_cells", options_.lobeCells);
  m.add("max_depth", int64_t(options_.maxDepth));
  m.add("memory_budget_bytes", uint64_t(options_.memoryBytes));
  m.add("memory_releases", uint64_t(budget_.releases()));
  m.add("release_step_bytes", uint64_t(budget_.releaseStep()));
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
