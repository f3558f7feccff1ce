#include "app/renderer.h"
#include "app/image_error.h"
#include "app/memory_plan.h"
#include "app/progress_state.h"
#include <algorithm>
#include <cmath>
#include "core/error.h"
#include "core/leaf_queries.h"
#include "core/memory.h"
#include "core/parallel.h"
#include "core/timer.h"

namespace rayes {

size_t defaultRayMemoryBytes(uint64_t limitBytes) {
  constexpr uint64_t kMiB = uint64_t(1) << 20;
  if (limitBytes == 0) return size_t(1024 * kMiB);
  return size_t(std::clamp<uint64_t>(limitBytes / 8, 256 * kMiB, 2048 * kMiB));
}

size_t defaultRayMemoryBytes() {
  static const size_t bytes = defaultRayMemoryBytes(processMemoryLimit().bytes);
  return bytes;
}

Renderer::Renderer(const Scene& scene, const RenderOptions& options)
    : scene_(scene), options_(options), data_(scene), began_(Clock::now()) {
  const auto t0 = began_;
  // A ray names the leaf it leaves from in kRayLeafBits bits (core/ray_batch.h).
  if (const size_t leaves = data_.top.leafBoxes().size(); leaves > kMaxRayLeaves)
    throw InputError(scene.path, "", "the scene has " + std::to_string(leaves) + " leaves (patches and volume bricks); "
                                     "a render takes at most " + std::to_string(kMaxRayLeaves));
  // The tile cache's bound for this render (the cache is the scene's: its lookups give the same
  // values at any size).
  if (scene.textures) scene.textures->setMemoryBytes(options.textureMemoryBytes);
  // The volumes' brick cache, shared by every shading thread (none when no volume reads a file).
  if (const uint64_t bytes = volumeCacheBytes(scene, options, ThreadLimit::active()); bytes > 0)
    data_.shading.volumeCache = std::make_shared<BrickCache>(bytes, ThreadLimit::active(), storedBricks(scene));
  data_.shading.integrator.firstHitAovs = options.firstHitAovs;
  integrator_ = makeMethod(options.method, scene, data_);
  // Some methods are defined by their passes (a photon map and a radius per pass).
  if (integrator_->traits().progressive) options_.progressive = true;
  stats_.progressive = options_.progressive;
  stats_.features = data_.features;
  stats_.leafKinds = data_.leafKinds;
  stats_.topLevelBytes = data_.top.bytes();
  stats_.micropolygonsPotential = uint64_t(scene.leaves.size()) << (2 * options.maxLod);

  // The memory budget: whole paths per batch, and the candidate buffer.
  const bool embree = options.engine == EngineKind::Embree;
  const uint64_t raysPerPath = integrator_->raysPerPath();
  stats_.raysPerPath = raysPerPath;
  const bool caching = !embree && options.diceCacheEntries > 0;
  const size_t engineBytesPerRay = embree    ? EmbreeEngine::bytesPerRaySlot()
                                   : caching ? CachingEngine::bytesPerRaySlot()
                                             : SortedEngine::bytesPerRaySlot(options.lod);
  const size_t engineScratchPerRay = embree || caching ? 0 : SortedEngine::sortScratchBytesPerRaySlot(options.lod);
  stats_.bytesPerPath = integrator_->bytesPerPath() + raysPerPath * (rayBytesPerSlot() + engineBytesPerRay) +
                        sortScratchBytesPerPath(engineScratchPerRay);
  if (options.costLayers) stats_.bytesPerPath += PixelCost::bytesPerPath(raysPerPath);
  const uint64_t pixels = uint64_t(scene.width) * uint64_t(scene.height);
  const uint64_t totalPaths = pixels * uint64_t(scene.samplesPerPixel);
  uint64_t perBatch = options.rayMemoryBytes / stats_.bytesPerPath;
  if (perBatch < 1)
    throw InputError("--ray-memory", "", "a budget of " + std::to_string(options.rayMemoryBytes) +
                     " bytes cannot hold one path (" + std::to_string(stats_.bytesPerPath) + " bytes)");
  perBatch = std::min<uint64_t>({perBatch, totalPaths, uint64_t(1) << 30});
  stats_.pathsPerBatch = perBatch;
  stats_.candidateCapacity = embree || caching ? 0 : raysPerPath * perBatch * SortedEngine::candidatesPerRaySlot(options.lod);
  // Refused here, before the engine, the beams or the film allocate, when it would not fit the memory limit.
  checkRenderMemory(planRenderMemory(scene, options, perBatch * stats_.bytesPerPath, ThreadLimit::active()));

  liveProgress().setPhase(embree ? Phase::Tessellating : Phase::BuildingTopLevel);
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
    ts.residentLod = options.residentLod;
    ts.samplesPerPixel = scene.samplesPerPixel;
    ts.candidateCapacity = stats_.candidateCapacity;
    ts.sortByLeaf = options.sortByLeaf;
    ts.gridCacheBytes = options.gridCacheBytes;
    ts.maxCandidatesPerRay = options.candidatesPerRay;
    if (caching) engine_ = std::make_unique<CachingEngine>(data_.top, scene.leaves, ts, options.diceCacheEntries);
    else engine_ = std::make_unique<SortedEngine>(data_.top, scene.leaves, ts);
  }
  // What the method does up front through the engine (light beams), with the budget's batch size.
  IntegratorSetup setup;
  setup.trace = [this](RayBatch& rays) {
    GenerationStats gs;
    engine_->trace(rays, gs, stats_.trace);
  };
  setup.limitKeptGrids = [this](size_t bytes) { return engine_->limitKeptGrids(bytes); };
  setup.pathsPerBatch = stats_.pathsPerBatch;
  liveProgress().setPhase(integrator_->traits().beamsUpFront ? Phase::TracingBeams : Phase::Preparing);
  integrator_->prepare(setup);
  stats_.method = integrator_->methodStats();
  stats_.engine = engine_->engineStats();
  stats_.memory = memoryAtSetup(raysPerPath);
  stats_.timeSetup = secondsSince(t0);
  sampleMemory(true);
}

void Renderer::sampleMemory(bool always) {
  if (!always && ++sampleTick_ % sampleStride_ != 0) return;
  std::vector<MemorySample>& v = stats_.memoryOverTime;
  if (v.size() >= kMaxMemorySamples) {
    // Thin out: keep every other sample (the first always), sample half as often from now on.
    size_t kept = 0;
    for (size_t i = 0; i < v.size(); i += 2) v[kept++] = v[i];
    v.resize(kept);
    sampleStride_ *= 2;
  }
  const EngineStats e = engine_->engineStats();
  MemorySample m;
  m.seconds = secondsSince(began_);
  m.rayBuffers = stats_.memory.rayBuffers;
  m.candidatesAndSort = stats_.memory.candidatesAndSort;
  m.diceCache = e.cacheBytes;
  m.borderBounds = e.borderBoundBytes;
  m.diceBuffers = e.fixedBytes - e.cachePeakBytes - e.borderBoundBytes;
  m.film = filmBytes_;
  m.rss = currentRssBytes();
  v.push_back(m);
}

MemoryByOwner Renderer::memoryAtSetup(uint64_t raysPerPath) const {
  MemoryByOwner m;
  const uint64_t slots = stats_.pathsPerBatch * raysPerPath;
  m.rayBuffers = size_t(stats_.pathsPerBatch * integrator_->bytesPerPath() + slots * rayBytesPerSlot());
  m.candidatesAndSort = size_t(slots * engine_->bytesPerRay() +
                               stats_.pathsPerBatch * sortScratchBytesPerPath(engine_->sortScratchBytesPerRay()));
  m.topLevel = data_.top.bytes();
  m.leaves = scene_.leaves.size();
  m.sceneDescription = scene_.leaves.descriptionBytes() + scene_.leafMaterial.capacity() * sizeof(uint32_t) +
                       data_.leafTableBytes() + stats_.engine.leafTableBytes + integrator_->leafTableBytes();
  m.uvSets = scene_.uvs ? scene_.uvs->bytes() : 0;
  return m;
}

Renderer::~Renderer() = default;

PixelWindow partBand(const PixelWindow& window, int part, int parts) {
  const int64_t h = window.height();
  return {window.x0, window.y0 + int(int64_t(part - 1) * h / parts), window.x1, window.y0 + int(int64_t(part) * h / parts)};
}

std::pair<uint64_t, uint64_t> partIds(uint64_t total, int part, int parts) {
  using u128 = unsigned __int128;
  return {uint64_t(u128(total) * unsigned(part - 1) / unsigned(parts)), uint64_t(u128(total) * unsigned(part) / unsigned(parts))};
}

PixelWindow Renderer::filmWindow() const {
  const PixelWindow crop = options_.crop.empty() ? PixelWindow::whole(scene_.width, scene_.height) : options_.crop;
  if (integrator_->traits().lightPathIds) return crop;
  return partBand(crop, options_.part, options_.parts);
}

void Renderer::resume(Film film, const Position& at) {
  if (!(film.window() == filmWindow()) || film.fullWidth() != scene_.width || film.fullHeight() != scene_.height)
    throw std::logic_error("Renderer::resume: the film's window is not this render's");
  resumeFilm_ = std::make_unique<Film>(std::move(film));
  position_ = at;
}

// The integrator's own paths before a pass's camera paths (photons), batched by the same budget.
void Renderer::traceLightPass(int s0, int s1, int pass, int& batch, const Control& control) {
  if (!integrator_->traits().lightPasses) return;
  const Integrator::IdRange ids = integrator_->lightPaths(s0, s1);
  if (ids.first == ids.end) return;
  liveProgress().setPhase(Phase::TracingPhotons);
  RayBatch rays;
  rays.timed = raysTimed();
  rays.derivatives = false;  // light paths read their textures as point samples (no footprint)
  rays.shadowPairs = integrator_->traits().shadowPairs;
  for (uint64_t first = ids.first; first < ids.end; first += stats_.pathsPerBatch, ++batch) {
    checkStop(control);
    const uint32_t count = static_cast<uint32_t>(std::min<uint64_t>(stats_.pathsPerBatch, ids.end - first));
    integrator_->startLight(first, count, rays);
    runGenerations(pass, batch, rays, true, control);
    integrator_->finishLightBatch(stats_.shade);
    ++stats_.batches;
  }
  integrator_->lightPassDone(stats_.shade);
  liveProgress().setPhase(Phase::Rendering);
}

void Renderer::runGenerations(int pass, int batch, RayBatch& rays, bool lightPaths, const Control& control,
                              const FirstHitPass* firstHits) {
  for (int depth = 0;; ++depth) {
    checkStop(control);
    GenerationRecord rec{pass, batch, depth, {}, {}};
    const TraceTimes& tt = stats_.trace;
    GenerationTimes& gt = rec.time;
    const GenerationTimes before{0, 0, tt.toplevel.seconds(), tt.sort.seconds(), stats_.shade.shade.seconds(),
                                 tt.dice.seconds(), tt.bottom.seconds(), tt.leafQueries.seconds()};
    const auto traceStart = Clock::now();
    gt.start = std::chrono::duration<double>(traceStart - renderStart_).count();
    engine_->trace(rays, rec.stats, stats_.trace);
    gt.trace = secondsSince(traceStart);
    if (pixelCost_ && !lightPaths) pixelCost_->afterTrace(rays);
    const size_t next = lightPaths ? integrator_->shadeLight(uint32_t(depth), rays, stats_.shade)
                                   : integrator_->shade(uint32_t(depth), rays, stats_.shade);
    gt.toplevel = tt.toplevel.seconds() - before.toplevel;
    gt.sort = tt.sort.seconds() - before.sort;
    gt.shade = stats_.shade.shade.seconds() - before.shade;
    gt.dice = tt.dice.seconds() - before.dice;
    gt.bottom = tt.bottom.seconds() - before.bottom;
    gt.leafQueries = tt.leafQueries.seconds() - before.leafQueries;
    stats_.generations.push_back(std::move(rec));
    sampleMemory(false);
    if (!lightPaths) liveProgress().afterGeneration(uint32_t(depth), rays, integrator_->raysPerPath());
    if (depth == 0 && firstHits) {  // before the next trace clears where they are kept
      const auto tf = Clock::now();
      integrator_->addFirstHits(rays, firstHits->film, firstHits->from);
      position_.firstHitsEnd = std::max(position_.firstHitsEnd, firstHits->end);
      stats_.timeFilm += secondsSince(tf);
    }
    // Gathers posted at the last vertices still run: one more trace, with queries only.
    if (next == 0 && !(rays.queries && rays.queries->pending())) break;
  }
}

void Renderer::runCameraBatch(uint64_t first, uint32_t count, uint64_t firstHitsFrom, int pass, int batch,
                              RayBatch& rays, Film& film, const Control& control) {
  const auto t0 = Clock::now();
  liveProgress().startBatch(count);
  if (pixelCost_) pixelCost_->startBatch(count, integrator_->raysPerPath());
  for (uint32_t round = 0, rounds = integrator_->roundsPerBatch(); round < rounds; ++round) {
    integrator_->startRound(round);
    integrator_->start(first, count, rays);
    const FirstHitPass firstHits{film, std::max(first, firstHitsFrom), first + count};
    runGenerations(pass, batch, rays, false, control, round == 0 ? &firstHits : nullptr);
  }
  const auto tf = Clock::now();
  integrator_->finish(film, stats_.shade);
  stats_.timeFilm += secondsSince(tf);
  if (pixelCost_)
    pixelCost_->finishBatch(secondsSince(t0), [&](uint32_t k) { return integrator_->cameraPixelOf(first + k); });
}

Film Renderer::render(const Progress& progress, const Control& control) {
  const auto t0 = Clock::now();
  renderStart_ = t0;
  liveProgress().setPhase(Phase::Rendering);
  const PixelWindow window = filmWindow();
  const bool lightIds = integrator_->traits().lightPathIds;
  if (!lightIds && !integrator_->setPixelWindow(window) && !(window == PixelWindow::whole(scene_.width, scene_.height)))
    throw std::logic_error("the method cannot render a window of the image");
  Film film = resumeFilm_ ? std::move(*resumeFilm_) : Film(scene_.width, scene_.height, window);
  resumeFilm_.reset();
  filmBytes_ = film.bytes();
  const Position start = position_;
  interrupted_ = false;
  RayBatch rays;
  rays.timed = raysTimed();
  rays.derivatives = raysKeepDerivatives();
  rays.shadowPairs = integrator_->traits().shadowPairs;
  if (options_.costLayers) {
    pixelCost_ = std::make_unique<PixelCost>(window, scene_.width);
    rays.chargeDicings = true;
  }
  // Camera ids per sample: the window's pixels, or light tracing's paths over the whole image.
  const uint64_t pixels = lightIds ? uint64_t(scene_.width) * uint64_t(scene_.height) : window.pixels();
  const int spp = scene_.samplesPerPixel;
  const auto [partFirst, partEnd] =
      lightIds ? partIds(pixels * uint64_t(spp), options_.part, options_.parts) : std::pair<uint64_t, uint64_t>{0, pixels * uint64_t(spp)};
  // A pass's camera ids, this part's share of them.
  auto passIds = [&](int s0, int s1) {
    const uint64_t first = std::max(uint64_t(s0) * pixels, partFirst), end = std::min(uint64_t(s1) * pixels, partEnd);
    return std::pair<uint64_t, uint64_t>{first, std::max(first, end)};
  };
  const uint64_t total = partEnd - partFirst;
  liveProgress().batchDone(0, total, 0);
  uint64_t done = 0;
  int s0 = 0, pass = 0;
  position_ = {};
  try {
    while (s0 < spp) {
      // One pass of every sample, or (progressive) 1, 1, 2, 4, ...: after each progressive pass the
      // film is a complete image, at the cost of re-dicing every leaf once more per pass.
      const int s1 = options_.progressive ? std::min(spp, s0 + std::max(1, s0)) : spp;
      const auto [passFirst, end] = passIds(s0, s1);
      int batch = 0;
      if (pass < start.pass) {
        // Done before the checkpoint. The first pass's light paths may leave state for later
        // passes (pm's map, ppm's first radius): traced again when the render resumes later.
        done += end - passFirst;
        if (pass == 0 && passFirst < end) traceLightPass(s0, s1, pass, batch, control);
        s0 = s1;
        ++pass;
        continue;
      }
      // (A stop in the pass's first batch after its camera generation left that batch's AOVs in
      // the film: resumed in their layout too.)
      const bool resumingHere = pass == start.pass && std::max(start.next, start.firstHitsEnd) > passFirst;
      // A pass of every sample that needs several batches goes block by block of pixels, each
      // batch all the samples of as many pixels as fit (Integrator::setPixelBlock): its rays
      // then meet the leaves of a part of the image, each more often. A resumed pass keeps the
      // layout its checkpoint's ids were counted in.
      uint64_t blockPixels = 0;
      if (resumingHere) {
        blockPixels = start.blockPixels;
      } else if (!lightIds && s0 == 0 && s1 == spp) {
        uint64_t b = stats_.pathsPerBatch / uint64_t(spp);
        if (options_.frequentBatches) b = std::min<uint64_t>(b, (pixels + kCheckpointBatchesPerPass - 1) / kCheckpointBatchesPerPass);
        if (b > 0 && b < pixels) blockPixels = b;
      }
      const bool blocks = blockPixels > 0 && integrator_->setPixelBlock(uint32_t(blockPixels));
      if (!blocks) blockPixels = 0;
      uint64_t step = stats_.pathsPerBatch;
      if (blocks) {
        step = std::min<uint64_t>(blockPixels * uint64_t(spp), stats_.pathsPerBatch);
        stats_.pixelsPerBlock = blockPixels;
      } else if (options_.frequentBatches) {
        step = std::min<uint64_t>(step, std::max<uint64_t>(1, (end - passFirst + kCheckpointBatchesPerPass - 1) / kCheckpointBatchesPerPass));
      }
      uint64_t first = resumingHere ? std::min(start.next, end) : passFirst;
      // Ids below it have their first-hit AOVs in the resumed film already.
      const uint64_t firstHitsDone = resumingHere ? std::max(first, start.firstHitsEnd) : 0;
      done += first - passFirst;
      position_ = {pass, first, blockPixels, std::max(first, firstHitsDone)};
      if (first < end) traceLightPass(s0, s1, pass, batch, control);
      for (; first < end; first += step, ++batch) {
        checkStop(control);
        const uint32_t count = static_cast<uint32_t>(std::min<uint64_t>(step, end - first));
        runCameraBatch(first, count, firstHitsDone, pass, batch, rays, film, control);
        ++stats_.batches;
        done += count;
        position_ = first + count < end ? Position{pass, first + count, blockPixels, std::max(first + count, firstHitsDone)}
                                        : Position{pass + 1, 0, 0, 0};
        if (control.batchDone) control.batchDone(film, position_);
        if (progress) progress(done, total, s0);
      }
      if (!options_.reference.empty())
        stats_.errorCurve.push_back({s1, secondsSince(t0), rmseAgainst(film, options_.reference)});
      if (blocks) integrator_->setPixelBlock(0);
      position_ = {pass + 1, 0, 0};
      s0 = s1;
      ++pass;
      if (progress) progress(done, total, s1);
    }
  } catch (const Stopped&) {
    interrupted_ = true;
    integrator_->setPixelBlock(0);
  }
  // The method's own figures again: some grow while the passes run (beams retraced per round).
  stats_.method = integrator_->methodStats();
  stats_.engine = engine_->engineStats();
  stats_.memory.diceCache = stats_.engine.cachePeakBytes;
  stats_.memory.borderBounds = stats_.engine.borderBoundBytes;
  stats_.memory.diceBuffers = engine_->fixedBytes() - stats_.engine.cachePeakBytes - stats_.engine.borderBoundBytes;
  // The dice buffers alone: the engine's fixed bytes also hold the grid cache and the border
  // bounds, which have their own owners (memory.by_owner), so the two figures agree.
  stats_.diceBufferBytes = options_.engine == EngineKind::Rayes ? stats_.memory.diceBuffers : 0;
  stats_.memory.film = film.bytes();
  stats_.memory.costLayers = pixelCost_ ? pixelCost_->bytes() + stats_.pathsPerBatch * stats_.raysPerPath * sizeof(uint64_t) : 0;
  stats_.splatSaturations = film.splatSaturations();
  if (scene_.textures) stats_.textures = scene_.textures->stats();
  if (pixelCost_) stats_.costLayers = RenderStats::CostLayerTotals{pixelCost_->dicingsCharged(), pixelCost_->secondsCharged()};
  if (data_.shading.volumeCache) stats_.volumeCache = data_.shading.volumeCache->stats();
  stats_.timeTotal = secondsSince(t0);
  sampleMemory(true);
  return film;
}

double rmseAgainst(const Film& film, const std::vector<float>& ref) {
  const PixelRegion whole{0, 0, film.width(), film.height(), {}};
  const PixelWindow& w = film.window();
  if (w == PixelWindow::whole(film.fullWidth(), film.fullHeight()))
    return errorAgainst(film.beautyRgba(), ref, whole, film.width(), film.height()).rmse;
  // The reference is of the full image: its pixels in the film's window.
  std::vector<float> inWindow;
  inWindow.reserve(3 * w.pixels());
  for (int y = w.y0; y < w.y1; ++y) {
    const float* row = ref.data() + 3 * (size_t(y) * size_t(film.fullWidth()) + size_t(w.x0));
    inWindow.insert(inWindow.end(), row, row + 3 * size_t(w.width()));
  }
  return errorAgainst(film.beautyRgba(), inWindow, whole, film.width(), film.height()).rmse;
}

}  // namespace rayes
