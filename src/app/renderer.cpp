#include "app/renderer.h"
#include <algorithm>
#include <cmath>
#include <map>
#include "core/error.h"
#include "core/timer.h"

namespace rayes {
namespace {
// The candidate buffer holds this many slots per ray of a full batch: the first iteration of
// the camera generation then gets N = 8 candidates per ray (2 ray slots per path), as in the
// thesis's Table 6.3, and later iterations more as rays terminate.
constexpr size_t kCandidatesPerRay = 4;
}  // namespace

size_t Renderer::bytesPerPath() {
  const size_t perRay = RayBatch::bytesPerRay() + Tracer::bytesPerRayState() + 2 * sizeof(uint32_t) +
                        kCandidatesPerRay * Tracer::bytesPerCandidate();
  return PathBatch::bytesPerPath() + 16 /* shading sort item */ + 2 * perRay;
}

Renderer::Renderer(const Scene& scene, const RenderOptions& options) : scene_(scene), options_(options) {
  const auto t0 = Clock::now();
  // Leaves and their boxes.
  const size_t n = scene.patches.size();
  leafBoxes_.resize(n);
  std::map<std::string, uint64_t> kinds;
  SceneFeatures& f = stats_.features;
  for (size_t i = 0; i < n; ++i) {
    const Patch& patch = *scene.patches[i];
    leafBoxes_[i] = patch.bounds();
    const std::string kind = patch.kind();
    ++kinds[kind];
    f.movingLeaves += patch.timeSamples() > 1;
    f.displacedLeaves += kind.rfind("displaced", 0) == 0;
    f.subdivisionLeaves += kind.find("subdiv") != std::string::npos;
    f.borderClosureLeaves += patch.needsBorderClosure();
    const float spacing = leafBoxes_[i].relativeSpacing();
    f.coarsestRelativeSpacing = std::max(f.coarsestRelativeSpacing, double(spacing));
    f.lowPrecisionLeaves += spacing > 0x1p-16f;
  }
  f.shutterOpen = scene.camera.shutterClose > scene.camera.shutterOpen;
  f.environment = scene.moreLights.environment != nullptr;
  f.distantLights = scene.moreLights.distants.size();
  stats_.leafKinds.assign(kinds.begin(), kinds.end());
  top_.build(leafBoxes_);
  stats_.topLevelBytes = top_.bytes();
  stats_.micropolygonsPotential = uint64_t(n) << (2 * options.maxLod);

  // Shading's view of the scene.
  const CameraDesc& cam = scene.camera;
  shading_.camera = PerspectiveCamera(cam.position, cam.lookAt, cam.up, cam.fovYDegrees, scene.width, scene.height,
                                      cam.apertureRadius, cam.focusDistance, cam.shutterOpen, cam.shutterClose);
  shading_.width = scene.width;
  shading_.height = scene.height;
  shading_.samplesPerPixel = scene.samplesPerPixel;
  shading_.integrator = scene.integrator;
  shading_.materials = scene.materials;
  shading_.leafMaterial = scene.patchMaterial;
  shading_.leafSide.resize(n);
  shading_.leafDicingError.resize(n);
  std::vector<PatchLight> patchLights;
  for (size_t i = 0; i < n; ++i) {
    shading_.leafSide[i] = leafBoxes_[i].longestSide();
    shading_.leafDicingError[i] = scene.patches[i]->dicingErrorCoefficient();
    const Material& m = scene.materials[scene.patchMaterial[i]];
    if (!m.emits()) continue;
    PatchPtr patch = scene.patches[i];
    patchLights.push_back({[patch](float u, float v, Vec3& p, Vec3& nrm) {
                             const SurfacePoint sp = patch->evaluate(u, v);
                             p = sp.p; nrm = sp.n;
                           },
                           m.emission, m.twoSided, uint32_t(i)});
  }
  // Lights at infinity are picked by power through a disk of the scene's bounding radius.
  Box3 all;
  for (const Box3& b : leafBoxes_) all.extend(b);
  const float radius = all.empty() ? 1.0f : std::max(std::numeric_limits<float>::min(), 0.5f * length(all.extent()));
  shading_.lights = LightSampler(scene.pointLights, std::move(patchLights), scene.moreLights, radius);

  // The memory budget: whole paths per batch, and the candidate buffer.
  stats_.bytesPerPath = bytesPerPath();
  const uint64_t pixels = uint64_t(scene.width) * uint64_t(scene.height);
  const uint64_t totalPaths = pixels * uint64_t(scene.samplesPerPixel);
  uint64_t perBatch = options.rayMemoryBytes / stats_.bytesPerPath;
  if (perBatch < 1)
    throw InputError("--ray-memory", "", "a budget of " + std::to_string(options.rayMemoryBytes) +
                     " bytes cannot hold one path (" + std::to_string(stats_.bytesPerPath) + " bytes)");
  perBatch = std::min<uint64_t>({perBatch, totalPaths, uint64_t(1) << 30});
  stats_.pathsPerBatch = perBatch;
  stats_.candidateCapacity = 2 * perBatch * kCandidatesPerRay;

  TraceSettings ts;
  ts.maxLod = options.maxLod;
  ts.lod = options.lod;
  ts.samplesPerPixel = scene.samplesPerPixel;
  ts.candidateCapacity = stats_.candidateCapacity;
  ts.sortByLeaf = options.sortByLeaf;
  tracer_ = std::make_unique<Tracer>(top_, scene.patches, ts);
  stats_.timeSetup = secondsSince(t0);
}

Renderer::~Renderer() = default;

Film Renderer::render(const Progress& progress) {
  const auto t0 = Clock::now();
  Film film(scene_.width, scene_.height);
  PathTracer tracer(shading_);
  PathBatch paths;
  RayBatch rays;
  const uint64_t pixels = uint64_t(scene_.width) * uint64_t(scene_.height);
  const int spp = scene_.samplesPerPixel;
  const uint64_t total = pixels * uint64_t(spp);
  uint64_t done = 0;
  int s0 = 0, pass = 0;
  while (s0 < spp) {
    const int s1 = std::min(spp, s0 + std::max(1, s0));  // 1, 1, 2, 4, ...
    const uint64_t end = uint64_t(s1) * pixels;
    int batch = 0;
    for (uint64_t first = uint64_t(s0) * pixels; first < end; first += stats_.pathsPerBatch, ++batch) {
      const uint32_t count = static_cast<uint32_t>(std::min<uint64_t>(stats_.pathsPerBatch, end - first));
      tracer.start(first, count, paths, rays);
      for (int depth = 0;; ++depth) {
        GenerationRecord rec{pass, batch, depth, {}};
        tracer_->trace(rays, rec.stats, stats_.trace);
        stats_.generations.push_back(std::move(rec));
        if (tracer.shade(uint32_t(depth), paths, rays, stats_.shade) == 0) break;
      }
      {
        const auto tf = Clock::now();
        tracer.finish(paths, film, stats_.shade);
        stats_.timeFilm += secondsSince(tf);
      }
      ++stats_.batches;
      done += count;
      if (progress) progress(done, total, s0);
    }
    if (!options_.reference.empty())
      stats_.errorCurve.push_back({s1, secondsSince(t0), rmseAgainst(film, options_.reference)});
    s0 = s1;
    ++pass;
    if (progress) progress(done, total, s1);
  }
  stats_.diceBufferBytes = tracer_->diceBufferBytes();
  stats_.timeTotal = secondsSince(t0);
  return film;
}

double rmseAgainst(const Film& film, const std::vector<float>& ref) {
  const std::vector<float> rgba = film.beautyRgba();
  const size_t n = rgba.size() / 4;
  double sum = 0;
  for (size_t p = 0; p < n; ++p)
    for (int c = 0; c < 3; ++c) {
      const double d = double(rgba[4 * p + c]) - double(ref[3 * p + c]);
      sum += d * d;
    }
  return n ? std::sqrt(sum / double(3 * n)) : 0.0;
}

}  // namespace rayes
