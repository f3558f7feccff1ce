// START HERE for shading. The path tracer as per-generation kernels (thesis §6.2.2, "group
// rays by generation"): start() writes the camera rays of a batch of paths; after the tracer
// has traced a generation, shade() consumes its hits and writes the next generation into the
// same RayBatch; finish() adds the batch's samples to the film in a fixed order. The first-hit
// AOVs go to the film earlier, right after the camera generation is shaded (addFirstHits), so a
// path keeps no first hit while it is traced.
//
// Slots: path k of a batch owns ray slots 2k (camera / continuation ray, closest hit) and
// 2k+1 (next-event shadow ray, any hit). shade() reads and rewrites only a path's own slots,
// so paths are shaded in parallel without locks. Before shading, hits are sorted by
// (material, leaf) so each material's data is touched in one block (the thesis's second
// sorting step); the result does not depend on that order.
//
// Estimator: a path tracer with next-event estimation and multiple importance sampling (power
// heuristic) between light sampling and BSDF sampling. At every non-delta vertex one light is
// sampled (shadow ray, slot 2k+1, MIS-weighted against the BSDF's density); the BSDF is sampled
// for the continuation ray (slot 2k), and when that ray finds an emitter -- an emissive patch,
// or nothing at all, so the environment or the sun -- the emission is weighted against the
// light-sampling density of that point (PathBatch keeps the previous vertex's BSDF density).
// Camera rays and delta bounces see emission unweighted. A path ends at max_depth vertices
// (the last continuation ray only gathers emission, and is not traced when the scene has
// nothing a ray could find) or by Russian roulette on throughput x eta². Random numbers are
// keyed by (pixel, sample, bounce, dimension), a fixed set of dimensions per vertex.
// Non-finite contributions are dropped and counted (docs/design.md, invariant 5).
//
// Media (ShadingScene::media, docs/design.md "Volumes"): every closest ray's free flight by delta
// tracking (a real collision makes a medium vertex, shadeMediumVertex: Henyey-Greenstein phase
// function for NEE and the continuation), every unoccluded shadow ray weighted by its ratio-tracked
// transmittance when it arrives; brick by brick, by the sorted engine at brick leaves (the batch's
// BrickLeafTracker) or by walking the ray here through the same per-brick functions. Else nothing.
//
// Caustic paths (docs/design.md, "Caustic paths"): with Options::causticPaths = Without the
// estimate leaves out every path light -> (caustic scatterer)+ -> diffuse vertex, read from the
// light (isCausticScatterer, shading/material.h): emission found by a BSDF-sampled ray, and
// next-event estimation at a glossy vertex, after a diffuse vertex and only caustic scatterers
// since (Only keeps exactly those). A caustic method (photons, beams) estimates them instead,
// through Options::causticRadiance at every diffuse vertex, so nothing is counted twice.
// Options::causticLights narrows both to the caustic paths of the lights the method covers
// (beams: not the environment light): the others stay with the path tracer, MIS unchanged.
#pragma once
#include <cstdint>
#include <memory>
#include <span>
#include <type_traits>
#include <vector>
#include "core/leaf_queries.h"
#include "core/rng.h"
#include "shading/bsdf.h"
#include "shading/integrator.h"
#include "shading/light.h"
#include "shading/medium_leaf_tracker.h"
#include "shading/ray_spawning.h"

namespace rayes {

// A caustic gather posted at a diffuse vertex and run as a leaf query during the next trace()
// (Options::gathersAsLeafQueries): what the estimator's DiffuseVertex needs, by value (the
// shading frame as its normal: ShadingFrame is a pure function of it), the path's throughput
// there, and the radiance the run writes.
struct PostedGather {
  Vec3 p, ng, wo, woL, frameNormal;
  Bsdf bsdf;
  uint32_t sample = 0, bounce = 0;
  Rgb throughput, radiance;
};

// A camera path's first-hit AOVs between its shading and addFirstHits: 28 bytes instead of
// FirstHit's 40 (the shading normal as the hit's octahedral code and a side bit, the level as a
// byte), so it fits the path's closest slot's RayHit, whose hit is spent once shaded.
// unpack() gives the FirstHit the film adds, bit for bit.
struct FirstHitRecord {
  float depth = 0;
  uint32_t normalCode = 0;  // encodeOctahedral of the hit's shading normal (RayHit::nsCode)
  Rgb albedo;
  int32_t materialId = -1;
  uint8_t lod = 0;
  uint8_t flags = 0;
  static constexpr uint8_t kHitSurface = 1, kNormalFlipped = 2;  // flipped: the camera saw its back
  FirstHit unpack() const {
    if (!(flags & kHitSurface)) return FirstHit{};
    const Vec3 n = decodeOctahedral(normalCode);
    return FirstHit{true, depth, (flags & kNormalFlipped) ? -n : n, float(lod), albedo, materialId};
  }
};
static_assert(sizeof(FirstHitRecord) == sizeof(RayHit) && std::is_trivially_copyable_v<FirstHitRecord>);

// The state of a batch of paths, structure of arrays; path k has global id first + k
// (PathTracer::idsOf gives its pixel and sample).
struct PathBatch {
  uint64_t first = 0;
  std::vector<Rgb> throughput, radiance, shadowContribution;
  std::vector<float> bsdfPdf;     // density of the BSDF sample that made the continuation ray
  std::vector<float> etaScale;    // product of etaRel² over refractions (for roulette)
  // One byte per path: its CausticRun (where it stands in a diffuse -> caustic chain, bits 0-1)
  // and whether the sample that made its continuation ray came from a delta lobe (or it is a
  // camera ray; bit 2). Whether a path goes on is its closest slot's kind, not kept here.
  std::vector<uint8_t> flags;
  uint8_t causticRun(size_t k) const { return flags[k] & 3; }
  void setCausticRun(size_t k, uint8_t run) { flags[k] = uint8_t((flags[k] & ~3) | run); }
  bool bsdfDelta(size_t k) const { return (flags[k] & 4) != 0; }
  void setBsdfDelta(size_t k, bool delta) { flags[k] = uint8_t((flags[k] & ~4) | (delta ? 4 : 0)); }
  // Whether shade(0) records the first hits for the AOVs (the render's outputs read them:
  // IntegratorSettings::firstHitAovs); they are kept in the ray slots, not here.
  bool firstHits = true;
  // Caustic gathers as leaf queries: slot k is path k's, at most one per generation, posted
  // by shade() and added to the radiance by the next shade(), after trace() ran it.
  LeafQueries gatherQueries;
  std::vector<PostedGather> gathers;
  // In a scene with media: the tracking the engine runs at brick leaves for this batch's rays
  // (RayBatch::media), and the products of its shadow rays (null without media).
  std::shared_ptr<BrickLeafTracker> media;
  size_t size() const { return flags.size(); }
  void resize(size_t n) {
    throughput.resize(n); radiance.resize(n); shadowContribution.resize(n); flags.resize(n);
    bsdfPdf.resize(n); etaScale.resize(n);
  }
  static constexpr size_t bytesPerPath() { return 3 * sizeof(Rgb) + 2 * sizeof(float) + 1; }
  static constexpr size_t bytesPerGather() { return sizeof(PostedGather) + LeafQueries::bytesPerSlot(); }
};

// Read from the camera: no diffuse vertex yet; the last vertex was diffuse; a diffuse vertex
// followed by one or more caustic scatterers (light reaching the path now is a caustic path).
enum CausticRun : uint8_t { kNoDiffuseYet = 0, kAfterDiffuse = 1, kInCausticChain = 2 };

// A diffuse vertex of a camera path as a caustic estimator sees it.
struct DiffuseVertex {
  Vec3 p, ng;         // the hit and its unit geometric normal
  Vec3 wo, woL;       // toward the viewer: world, and in `frame`
  const ShadingFrame* frame;
  const Bsdf* bsdf;
  uint32_t sample;    // the path's sample number (progressive methods shrink with it)
  uint32_t leaf = kNoLeaf;  // the leaf hit (light beams gather from that leaf's bins)
  uint32_t bounce = 0;      // the camera path's bounce here (0: the first hit): with the light
                            // side's vertices it must stay within max_depth, as in the path tracer
  uint32_t path = 0;        // the path's index in its batch: beams processed in batches keep a
                            // partial sum per (path, bounce)
};

// Reflected radiance along wo carried by caustic paths (light -> caustic scatterers -> here).
// radiance() may be called concurrently for distinct (path, bounce).
class CausticRadiance {
 public:
  virtual ~CausticRadiance() = default;
  virtual Rgb radiance(const DiffuseVertex& v) const = 0;
};

class PathTracer final : public Integrator {
 public:
  struct Options {
    CausticPaths causticPaths = CausticPaths::All;
    const CausticRadiance* causticRadiance = nullptr;  // added at every diffuse vertex (not owned)
    uint8_t causticLights = kAllLights;  // LightKind bits: whose caustic paths causticPaths selects
    // Whether causticRadiance runs as a leaf query of the next trace() (an estimator binned by
    // top-level leaf: light beams) rather than in the shading step (photon maps). Either way the
    // path adds throughput x radiance right after the vertex's emission and before anything of
    // the next vertex, so the image is the same bit for bit.
    bool gathersAsLeafQueries = false;
    // Russian roulette on the caustic estimate after a path's first diffuse vertex: each later
    // one gathers with this probability and counts 1/it (unbiased). Worth it where gathers are
    // dear (glossy beams): their share of a pixel is small, their cost the first vertex's.
    float laterGatherProbability = kLaterGatherProbability;
  };
  explicit PathTracer(const ShadingScene& scene) : PathTracer(scene, Options{}) {}
  PathTracer(const ShadingScene& scene, Options options)
      : scene_(scene), options_(options), shadeRank_(scene.leafRows.gated() ? std::vector<uint32_t>{} : shadeRanks(scene.leafMaterial)),
        window_(PixelWindow::whole(scene.width, scene.height)) {}


  // The Integrator interface over the tracer's own PathBatch (`--method pt`).
  IntegratorTraits traits() const override { return {.shadowPairs = true}; }
  uint32_t raysPerPath() const override { return kRaysPerPath; }
  size_t bytesPerPath() const override {
    return PathBatch::bytesPerPath() +
           (options_.gathersAsLeafQueries ? PathBatch::bytesPerGather() : 0) +
           (scene_.media.empty() ? 0 : sizeof(uint64_t));  // BrickLeafTracker's product
  }
  // The shading sort's items, in the batch's RayBatch::sortScratch (sortByMaterial).
  size_t sortScratchBytesPerPath() const override { return sizeof(SortItem); }
  size_t leafTableBytes() const override { return shadeRank_.capacity() * sizeof(uint32_t); }
  void start(uint64_t first, uint32_t count, RayBatch& rays) override { start(first, count, paths_, rays); }
  size_t shade(uint32_t bounce, RayBatch& rays, ShadeStats& stats) override {
    return shade(bounce, paths_, rays, stats);
  }
  void finish(Film& film, ShadeStats& stats) override { finish(paths_, film, stats); }
  void addFirstHits(RayBatch& rays, Film& film, uint64_t from) override { addFirstHits(paths_, rays, film, from); }
  // Path ids by pixel blocks: pixels [b·n, (b+1)·n) with all their samples are ids
  // [b·n·spp, (b+1)·n·spp), sample-major within a block (sample s of the block's pixel q is
  // id b·n·spp + s·(the block's pixels) + q; the last block may be smaller). n = 0, or the
  // image's pixel count, is one block: the sample-major ids sample · pixels + pixel. A batch of
  // whole blocks then holds every sample of fewer pixels, so its rays meet fewer leaves, each more
  // often (bench/history/2026-11.md, "Batches by pixel blocks"). The pixel and sample of every path
  // and the order each pixel's samples reach the film are the same for every n.
  bool setPixelBlock(uint32_t n) override {
    blockPixels_ = n;
    return true;
  }
  // Camera path ids cover the window's pixels only (--crop, a part of a farm split): the
  // window's pixels are numbered in row order, and idsOf gives each path the full-image pixel
  // it lands on, so a pixel gets the same samples (the RNG is keyed by that pixel) in any
  // window. By default the whole image.
  bool setPixelWindow(const PixelWindow& window) override {
    window_ = window;
    return true;
  }
  // A path's full-image pixel and its sample.
  struct PathIds { uint32_t pixel, sample; };
  PathIds idsOf(uint64_t id) const;
  int64_t cameraPixelOf(uint64_t id) const override { return idsOf(id).pixel; }

  // The kernels on an explicit PathBatch (the tests drive them directly).

  // Starts paths [first, first + count): resets their state, writes camera rays.
  void start(uint64_t first, uint32_t count, PathBatch& paths, RayBatch& rays) const;
  // Shades generation `bounce` (0 = camera rays) and writes the next generation in place.
  // Returns the number of rays written. With gathers as leaf queries, it first adds the
  // gathers the last trace() ran, and leaves rays.queries pointing at the new ones (the caller
  // traces once more, with no rays, while rays.queries->pending()).
  size_t shade(uint32_t bounce, PathBatch& paths, RayBatch& rays, ShadeStats& stats);
  // Adds the batch's radiance to the film, pixel by pixel in sample order. A sample whose
  // radiance overflowed to a non-finite value is dropped (added as black, AOVs kept) and
  // counted in stats.nonFinite.
  void finish(const PathBatch& paths, Film& film, ShadeStats& stats) const;
  // After shade(0) and before the next trace: adds the first hits of the batch's paths with ids
  // >= from to the film's AOV sums, in finish()'s order (those sums are apart from the radiance's,
  // so the film gets the bits of adding both at the end). shade(0) keeps path k's FirstHitRecord
  // in the RayHit of its slot 2k, spent once shaded (a continuation ray's hit is cleared by the
  // next trace); this pass reads every path's and leaves the hit cleared. O(paths), pixels in
  // parallel. Nothing when the batch records no first hits (PathBatch::firstHits).
  void addFirstHits(const PathBatch& paths, RayBatch& rays, Film& film, uint64_t from) const;

 private:
  // shade()'s parts: the (material, leaf) sort, and one path's steps (returns rays written).
  // The sort's items are taken from rays.sortScratch (free while shade() runs: the trace is
  // done) and returned, valid until shade() returns.
  struct SortItem { uint32_t key; uint32_t path; };
  std::span<const SortItem> sortByMaterial(const PathBatch& paths, RayBatch& rays, ShadeStats& stats) const;
  void addRunGathers(PathBatch& paths, ShadeStats& stats) const;
  // Runs a leaf's posted gathers (the batch being shaded) through causticRadiance.
  class GatherRunner final : public LeafQueryRunner {
   public:
    void run(uint32_t leaf, std::span<const uint32_t> ids) override;
    const CausticRadiance* caustics = nullptr;
    PathBatch* paths = nullptr;
  };
  // Before a trace of generation `bounce`: the batch's tracker reset, with the vertex keys of
  // its rays (a closest ray's free flight is keyed as the vertex it makes, bounce + 1; a shadow
  // ray's transmittance as the vertex that wrote it, bounce).
  void prepareMediumTracking(uint32_t bounce, PathBatch& paths, RayBatch& rays) const;
  // Path k's shadow ray's transmittance through the media (1 without media): the engine's
  // product, or the same walked here when the engine did not run the brick leaves.
  float shadowTransmittance(uint32_t bounce, uint32_t k, const PathBatch& paths, const RayBatch& rays,
                            ShadeStats& stats) const;
  // firstHit: null, or (the camera generation) where the path's first hit is recorded.
  size_t shadePath(uint32_t bounce, uint32_t k, PathBatch& paths, RayBatch& rays, ShadeStats& stats,
                   FirstHitRecord* firstHit) const;
  // add(full-image pixel, id) for the ids [first, end), pixel by pixel in sample order: the
  // film's order (finish, addFirstHits); pixels in parallel.
  template <class Add> void inFilmOrder(uint64_t first, uint64_t end, const Add& add) const;
  // A real collision in a medium at t along path k's closest ray (path_tracer.cpp).
  size_t shadeMediumVertex(uint32_t bounce, uint32_t k, float t, const Medium& m, const RngKey& key, PathBatch& paths,
                           RayBatch& rays, ShadeStats& stats) const;
  // The kinds of light whose paths count for light arriving now (inChain: along a caustic path).
  uint8_t countedLights(bool inChain) const {
    if (!inChain) return counts(options_.causticPaths, false) ? kAllLights : 0;
    switch (options_.causticPaths) {
      case CausticPaths::All: return kAllLights;
      case CausticPaths::Without: return uint8_t(kAllLights & ~options_.causticLights);
      case CausticPaths::Only: return options_.causticLights;
    }
    return kAllLights;
  }

  const ShadingScene& scene_;
  Options options_;
  // The shading sort's key of a hit on leaf l is shadeRank_[l] (shadeRanks: 4 bytes per leaf,
  // made once), so a path's sort item is 8 bytes, not a 64-bit (material, leaf) key and the
  // path; kNoHitRank (misses, and paths without a closest ray) sorts last.
  static constexpr uint32_t kNoHitRank = 0xffffffffu;
  std::vector<uint32_t> shadeRank_;  // empty when the scene's rows hold them (a compiled scene)
  uint32_t shadeRankOf(uint32_t leaf) const {
    return scene_.leafRows.gated() ? scene_.leafRows[leaf].shadeRank : shadeRank_[leaf];
  }
  GatherRunner gatherRunner_;
  PathBatch paths_;
  uint32_t blockPixels_ = 0;  // setPixelBlock's n
  PixelWindow window_;        // setPixelWindow's
  const PixelWindow& window() const { return window_; }
  // The id layout idsOf reads and finish inverts: block b holds the window's pixels [b·block,
  // b·block + pixelsIn(b)) (in the window's row order) and ids [b·perBlock, (b+1)·perBlock).
  struct IdBlocks {
    uint64_t pixels, block, perBlock;
    uint64_t pixelsIn(uint64_t b) const { return std::min(block, pixels - b * block); }
  };
  IdBlocks idBlocks() const {
    const uint64_t pixels = window().pixels();
    const uint64_t block = blockPixels_ ? blockPixels_ : pixels;
    return {pixels, block, block * uint64_t(std::max(1, scene_.samplesPerPixel))};
  }
  // The full-image index of the window's pixel q (row order).
  uint32_t fullPixel(const PixelWindow& w, uint64_t q) const {
    const uint64_t ww = uint64_t(w.width());
    return static_cast<uint32_t>((uint64_t(w.y0) + q / ww) * uint64_t(scene_.width) + uint64_t(w.x0) + q % ww);
  }
};

}  // namespace rayes
