#include "app/renderer.h"
#include "app/image_error.h"
#include <algorithm>
#include <cmath>
#include "core/error.h"
#include "core/leaf_queries.h"
#include "core/memory.h"
#include "core/timer.h"
#include "lbt/beam_resolution.h"
#include "lbt/photon_mapper.h"
#include "shading/path_tracer.h"

namespace rayes {

size_t defaultRayMemoryBytes(uint64_t physicalBytes) {
  constexpr uint64_t kMiB = uint64_t(1) << 20;
  if (physicalBytes == 0) return size_t(1024 * kMiB);
  return size_t(std::clamp<uint64_t>(physicalBytes / 8, 256 * kMiB, 2048 * kMiB));
}

size_t defaultRayMemoryBytes() {
  static const size_t bytes = defaultRayMemoryBytes(physicalMemoryBytes());
  return bytes;
}

Renderer::Renderer(const Scene& scene, const RenderOptions& options)
    : scene_(scene), options_(options), data_(scene) {
  const auto t0 = Clock::now();
  // Progressive photon mapping is defined by its passes: one photon map and radius per pass.
  if (options.method == IntegratorMethod::ProgressivePhotonMapping) options_.progressive = true;
  stats_.progressive = options_.progressive;
  stats_.features = data_.features;
  stats_.leafKinds = data_.leafKinds;
  stats_.topLevelBytes = data_.top.bytes();
  stats_.micropolygonsPotential = uint64_t(scene.leaves.size()) << (2 * options.maxLod);
  const bool photons = options.method == IntegratorMethod::PhotonMapping ||
                       options.method == IntegratorMethod::ProgressivePhotonMapping;
  integrator_ = photons ? makePhotonMapper(options.method == IntegratorMethod::ProgressivePhotonMapping, data_.shading,
                                           options.integrator)
                        : makeIntegrator(options.method, data_.shading, options.integrator);

  // The memory budget: whole paths per batch, and the candidate buffer.
  const bool embree = options.engine == EngineKind::Embree;
  const uint64_t raysPerPath = integrator_->raysPerPath();
  stats_.raysPerPath = raysPerPath;
  const bool caching = !embree && options.diceCacheEntries > 0;
  const size_t engineBytesPerRay = embree    ? EmbreeEngine::bytesPerRaySlot()
                                   : caching ? CachingEngine::bytesPerRaySlot()
                                             : SortedEngine::bytesPerRaySlot();
  stats_.bytesPerPath =
      integrator_->bytesPerPath() + raysPerPath * (RayBatch::bytesPerRay(raysTimed()) + engineBytesPerRay);
  const uint64_t pixels = uint64_t(scene.width) * uint64_t(scene.height);
  const uint64_t totalPaths = pixels * uint64_t(scene.samplesPerPixel);
  uint64_t perBatch = options.rayMemoryBytes / stats_.bytesPerPath;
  if (perBatch < 1)
    throw InputError("--ray-memory", "", "a budget of " + std::to_string(options.rayMemoryBytes) +
                     " bytes cannot hold one path (" + std::to_string(stats_.bytesPerPath) + " bytes)");
  perBatch = std::min<uint64_t>({perBatch, totalPaths, uint64_t(1) << 30});
  stats_.pathsPerBatch = perBatch;
  stats_.candidateCapacity = embree || caching ? 0 : raysPerPath * perBatch * SortedEngine::kCandidatesPerRay;

  if (embree) {
    EmbreeSettings es;
    es.maxLod = options.maxLod;
    es.autoLod = options.embreeAutoLod;
    const PerspectiveCamera& camera = data_.shading.camera;
    es.camera = {camera.position(), camera.apertureRadius(), camera.pixelSpread()};
    es.memoryLimit = options.memoryLimitBytes;
    engine_ = std::make_unique<EmbreeEngine>(scene.leaves, es);
  } else {
    TraceSettings ts;
    ts.maxLod = options.maxLod;
    ts.lod = options.lod;
    ts.lodBias = options.lodBias;
    ts.samplesPerPixel = scene.samplesPerPixel;
    ts.candidateCapacity = stats_.candidateCapacity;
    ts.sortByLeaf = options.sortByLeaf;
    ts.gridCacheBytes = options.gridCacheBytes;
    ts.maxCandidatesPerRay = options.candidatesPerRay;
    if (caching) engine_ = std::make_unique<CachingEngine>(data_.top, scene.leaves, ts, options.diceCacheEntries);
    else engine_ = std::make_unique<SortedEngine>(data_.top, scene.leaves, ts);
  }
  if (options.method == IntegratorMethod::LightBeams) buildBeams();
  else stats_.beams.skipped = "--method is not lbt: no beams traced";
  stats_.engine = engine_->engineStats();
  stats_.memory = memoryAtSetup(raysPerPath);
  stats_.timeSetup = secondsSince(t0);
}

MemoryByOwner Renderer::memoryAtSetup(uint64_t raysPerPath) const {
  MemoryByOwner m;
  const uint64_t slots = stats_.pathsPerBatch * raysPerPath;
  m.rayBuffers = size_t(stats_.pathsPerBatch * integrator_->bytesPerPath() + slots * RayBatch::bytesPerRay(raysTimed()));
  m.candidatesAndSort = size_t(slots * engine_->bytesPerRay());
  m.topLevel = data_.top.bytes();
  m.leaves = scene_.leaves.size();
  m.sceneDescription = scene_.leaves.descriptionBytes() + scene_.leafMaterial.capacity() * sizeof(uint32_t) +
                       data_.leafTableBytes() + stats_.engine.leafTableBytes + integrator_->leafTableBytes();
  return m;
}

BeamTraceOptions Renderer::beamTraceOptions() const {
  const Box3 bounds = data_.top.bounds();
  BeamTraceOptions to;
  to.maxDepth = options_.beams.maxDepth;
  to.splitDepth = options_.beams.splitDepth;
  to.far = 4 * (length(bounds.extent()) + bounds.magnitude()) + 1;
  to.raysPerTrace = std::max<size_t>(1, stats_.pathsPerBatch * integrator_->raysPerPath());
  return to;
}

std::vector<BeamSegment> Renderer::traceBeamSeeds(const BeamSeeds& seeds, const BeamTraceOptions& to,
                                                  BeamTraceStats& stats) {
  auto trace = [&](RayBatch& rays) {
    GenerationStats gs;
    engine_->trace(rays, gs, stats_.trace);
  };
  return traceBeams(data_.shading, seeds, to, trace, stats);
}

std::unique_ptr<BeamStore> Renderer::traceBeamRange(size_t first, size_t last, size_t budget, BeamTraceStats& stats) {
  const ShadingScene& shading = data_.shading;
  std::vector<BeamSegment> segments = traceBeamSeeds(beamSeeds_.range(first, last), beamTraceOptions(), stats);
  std::vector<uint8_t> leafReceives(shading.leafMaterial.size());
  for (size_t l = 0; l < leafReceives.size(); ++l)
    leafReceives[l] = isCausticScatterer(shading.materials[shading.leafMaterial[l]]) ? 0 : 1;
  return std::make_unique<BeamStore>(std::move(segments), data_.top, data_.leafBoxes, budget, leafReceives,
                                     scene_.integrator.maxDepth);
}

// --beam-resolution, or the glossy rule's coarser grid (lbt/beam_resolution.h) from a probe of
// one bounce without splits at a resolution of at most kProbe.
int Renderer::beamResolution(const BeamLights& lights, std::span<const ScattererSurface> scatterers) {
  constexpr int kProbe = 16;
  const int requested = options_.beams.resolution;
  if (!(options_.beams.lobeCells > 0)) return requested;
  const int probeResolution = std::min(requested, kProbe);
  BeamTraceOptions to = beamTraceOptions();
  to.maxDepth = 1;
  to.splitDepth = 0;
  BeamTraceStats probeStats;  // not the render's beams: not counted
  const std::vector<BeamSegment> probe =
      traceBeamSeeds(seedBeams(lights, scatterers, data_.top.bounds(), probeResolution), to, probeStats);
  const int lobe = lobeResolution(probe, probeResolution, options_.beams.lobeCells, to.far);
  return lobe > 0 ? std::min(requested, lobe) : requested;
}

void Renderer::buildBeams() {
  const auto t0 = Clock::now();
  const ShadingScene& shading = data_.shading;
  // The scatterer leaves' surfaces, for their beam grids (their patches live while the beams
  // are seeded: only caustic scatterers, not the scene's other leaves).
  std::vector<ScattererSurface> scatterers;
  for (size_t l = 0; l < data_.leafBoxes.size(); ++l)
    if (isCausticScatterer(shading.materials[shading.leafMaterial[l]]) && !data_.leafBoxes[l].empty()) {
      PatchPtr patch = scene_.leaves.patch(l);
      scatterers.push_back({uint32_t(l), [patch](float u, float v) { return patch->evaluate(u, v).p; }});
    }
  const BeamLights lights{scene_.pointLights, scene_.moreLights.spots, scene_.moreLights.distants,
                          options_.beams.areaSamples > 0 ? patchLightsOf(scene_) : std::vector<PatchLight>{},
                          options_.beams.areaSamples};
  BeamRenderStats& bs = stats_.beams;
  if (scatterers.empty() || lights.empty()) {
    bs.skipped = scatterers.empty() ? "no specular or glossy surface: no beams traced, lbt is the path tracer"
                                    : "no point, spot, distant or area light (--beam-area-samples 0 leaves area lights out): no beams "
                                      "traced, lbt is the path tracer";
    return;
  }
  bs.resolution = beamResolution(lights, scatterers);
  beamSeeds_ = seedBeams(lights, scatterers, data_.top.bounds(), bs.resolution);
  // The ranges of seed triangles whose beams fit the budget: all of them if they do, else
  // halves, quarters, ... (a tried range's segments are held once before they are binned).
  // Batches keep a partial gather per (path, bounce) of a camera batch (BeamBatches): those
  // share the budget, so every range's store gets what they leave.
  const size_t roots = beamSeeds_.triangles.size();
  const size_t partialBytes = BeamBatches::bytesFor(stats_.pathsPerBatch, scene_.integrator.maxDepth);
  size_t budget = options_.beams.memoryBytes;  // one store of every beam: no partial gathers
  size_t count = roots, segments = 0;
  for (size_t first = 0; first < roots; first += count) {
    count = std::min(count, roots - first);
    for (;;) {
      BeamTraceStats trial;
      std::unique_ptr<BeamStore> store = traceBeamRange(first, first + count, budget, trial);
      if (count == roots && !store->fits()) {
        const size_t oneBeam = BeamStore::minimumBytes(data_.leafBoxes.size());
        if (partialBytes + oneBeam > options_.beams.memoryBytes)
          throw InputError("--beam-memory", "",
                           "a budget of " + std::to_string(options_.beams.memoryBytes) +
                               " bytes cannot hold the beams in batches: the partial gathers of a camera batch take " +
                               std::to_string(partialBytes) + " bytes (" + std::to_string(stats_.pathsPerBatch) +
                               " paths x " + std::to_string(std::max(scene_.integrator.maxDepth, 1)) +
                               " bounces x " + std::to_string(sizeof(Rgb)) + " B) besides " + std::to_string(oneBeam) +
                               " for one beam; raise --beam-memory or lower --ray-memory");
        budget = options_.beams.memoryBytes - partialBytes;  // what did not fit the whole budget fits no less
      }
      if (store->fits()) {
        bs.trace.add(trial);  // a trial that did not fit is not counted
        bs.binEntries += store->binEntries();
        bs.bytes = std::max(bs.bytes, store->bytes());
        segments += store->segmentCount();
        beamRanges_.push_back({first, first + count});
        beams_ = std::move(store);
        break;
      }
      if (count == 1)
        throw InputError("--beam-memory", "", "a budget of " + std::to_string(budget) +
                         " bytes cannot hold one beam (seed triangle " + std::to_string(first) + " needs " +
                         std::to_string(store->neededBytes()) + " bytes for its segments and bins" +
                         (budget < options_.beams.memoryBytes ? " besides the partial gathers of a camera batch)" : ")"));
      count = (count + 1) / 2;
    }
  }
  bs.batches = beamRanges_.size();
  beamStoreBudget_ = budget;
  bs.seconds = secondsSince(t0);
  if (segments == 0) {
    bs.skipped = "no beam reached past a specular or glossy surface: lbt is the path tracer";
    beams_.reset();
    beamRanges_.clear();
    return;
  }
  // The path tracer leaves caustic paths to the beams (same bytes per path as the one the
  // budget was computed with).
  const CausticRadiance* caustics = beams_.get();
  if (beamRanges_.size() > 1) {
    beams_.reset();
    beamBatches_ = std::make_unique<BeamBatches>(stats_.pathsPerBatch, scene_.integrator.maxDepth);
    caustics = beamBatches_.get();
    bs.bytes += beamBatches_->bytes();
  }
  // Environment lights get no beams: their caustic paths stay with the path tracer (with
  // --caustic-paths only, those paths alone besides the beams).
  const uint8_t covered = kPointLight | kSpotLight | kDistantLight | (lights.patches.empty() ? 0 : kPatchLight);
  const bool only = options_.integrator.causticPaths == CausticPaths::Only;
  integrator_ = std::make_unique<PathTracer>(
      data_.shading, PathTracer::Options{.causticPaths = only ? CausticPaths::Only : CausticPaths::Without,
                                         .causticRadiance = caustics,
                                         .causticLights = only ? uint8_t(kAllLights & ~covered) : covered,
                                         .gathersAsLeafQueries = !options_.beamGathersInShading,
                                         .laterGatherProbability = options_.integrator.laterGatherProbability});
  bs.built = true;
}

Renderer::~Renderer() = default;

// The integrator's own paths before a pass's camera paths (photons), batched by the same budget.
void Renderer::traceLightPass(int s0, int s1, int pass, int& batch) {
  const Integrator::IdRange ids = integrator_->lightPaths(s0, s1);
  if (ids.first == ids.end) return;
  RayBatch rays;
  rays.timed = raysTimed();
  for (uint64_t first = ids.first; first < ids.end; first += stats_.pathsPerBatch, ++batch) {
    const uint32_t count = static_cast<uint32_t>(std::min<uint64_t>(stats_.pathsPerBatch, ids.end - first));
    integrator_->startLight(first, count, rays);
    runGenerations(pass, batch, rays, true);
    integrator_->finishLightBatch(stats_.shade);
    ++stats_.batches;
  }
  integrator_->lightPassDone(stats_.shade);
}

void Renderer::runGenerations(int pass, int batch, RayBatch& rays, bool lightPaths) {
  for (int depth = 0;; ++depth) {
    GenerationRecord rec{pass, batch, depth, {}};
    engine_->trace(rays, rec.stats, stats_.trace);
    stats_.generations.push_back(std::move(rec));
    const size_t next = lightPaths ? integrator_->shadeLight(uint32_t(depth), rays, stats_.shade)
                                   : integrator_->shade(uint32_t(depth), rays, stats_.shade);
    // Gathers posted at the last vertices still run: one more trace, with queries only.
    if (next == 0 && !(rays.queries && rays.queries->pending())) break;
  }
}

void Renderer::runCameraBatch(uint64_t first, uint32_t count, int pass, int batch, RayBatch& rays) {
  integrator_->start(first, count, rays);
  runGenerations(pass, batch, rays, false);
}

Film Renderer::render(const Progress& progress) {
  const auto t0 = Clock::now();
  Film film(scene_.width, scene_.height);
  RayBatch rays;
  rays.timed = raysTimed();
  const uint64_t pixels = uint64_t(scene_.width) * uint64_t(scene_.height);
  const int spp = scene_.samplesPerPixel;
  const uint64_t total = pixels * uint64_t(spp);
  uint64_t done = 0;
  int s0 = 0, pass = 0;
  while (s0 < spp) {
    // One pass of every sample, or (progressive) 1, 1, 2, 4, ...: after each progressive pass the
    // film is a complete image, at the cost of re-dicing every leaf once more per pass.
    const int s1 = options_.progressive ? std::min(spp, s0 + std::max(1, s0)) : spp;
    const uint64_t end = uint64_t(s1) * pixels;
    // A pass of every sample that needs several batches goes block by block of pixels, each
    // batch all the samples of as many pixels as fit (Integrator::setPixelBlock): its rays
    // then meet the leaves of a part of the image, each more often.
    uint64_t step = stats_.pathsPerBatch;
    const uint64_t blockPixels = stats_.pathsPerBatch / uint64_t(spp);
    const bool blocks = s0 == 0 && s1 == spp && blockPixels > 0 && blockPixels < pixels &&
                        integrator_->setPixelBlock(uint32_t(blockPixels));
    if (blocks) {
      step = blockPixels * uint64_t(spp);
      stats_.pixelsPerBlock = blockPixels;
    }
    int batch = 0;
    traceLightPass(s0, s1, pass, batch);
    for (uint64_t first = uint64_t(s0) * pixels; first < end; first += step, ++batch) {
      const uint32_t count = static_cast<uint32_t>(std::min<uint64_t>(step, end - first));
      if (beamBatches_) {
        // Beams in batches: the camera paths once per range of beams, the film from the last.
        beamBatches_->startPaths();
        for (const auto& [r0, r1] : beamRanges_) {
          beams_.reset();
          BeamTraceStats again;
          beams_ = traceBeamRange(r0, r1, beamStoreBudget_, again);
          beamBatches_->use(beams_.get());
          runCameraBatch(first, count, pass, batch, rays);
        }
        beamBatches_->use(nullptr);
        beams_.reset();
      } else {
        runCameraBatch(first, count, pass, batch, rays);
      }
      {
        const auto tf = Clock::now();
        integrator_->finish(film, stats_.shade);
        stats_.timeFilm += secondsSince(tf);
      }
      ++stats_.batches;
      done += count;
      if (progress) progress(done, total, s0);
    }
    if (!options_.reference.empty())
      stats_.errorCurve.push_back({s1, secondsSince(t0), rmseAgainst(film, options_.reference)});
    if (blocks) integrator_->setPixelBlock(0);
    s0 = s1;
    ++pass;
    if (progress) progress(done, total, s1);
  }
  stats_.engine = engine_->engineStats();
  stats_.diceBufferBytes = options_.engine == EngineKind::Rayes ? engine_->fixedBytes() : 0;
  stats_.memory.diceCache = stats_.engine.cachePeakBytes;
  stats_.memory.borderBounds = stats_.engine.borderBoundBytes;
  stats_.memory.diceBuffers = engine_->fixedBytes() - stats_.engine.cachePeakBytes - stats_.engine.borderBoundBytes;
  stats_.memory.film = film.bytes();
  stats_.timeTotal = secondsSince(t0);
  return film;
}

double rmseAgainst(const Film& film, const std::vector<float>& ref) {
  const PixelRegion whole{0, 0, film.width(), film.height(), {}};
  return errorAgainst(film.beautyRgba(), ref, whole, film.width(), film.height()).rmse;
}

}  // namespace rayes
