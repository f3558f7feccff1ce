#include "app/render_data.h"
#include <algorithm>
#include <cmath>
#include <limits>
#include <cstring>
#include <map>
#include <numbers>
#include <stdexcept>
#include "core/error.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace rayes {
namespace {

// The per-leaf counts, one leaf at a time (facts are not kept: 32 bytes a leaf).
void countLeaf(SceneFeatures& f, const LeafFacts& facts, const Box3& box, Vec3 camera, float pixelSpread) {
  f.movingLeaves += facts.timeSamples > 1;
  f.displacedLeaves += facts.displaced;
  f.subdivisionLeaves += facts.subdivision;
  f.borderClosureLeaves += facts.borderClosure;
  f.coarsestRelativeSpacing = std::max(f.coarsestRelativeSpacing, double(box.relativeSpacing()));
  f.lowPrecisionLeaves += isLowPrecisionLeaf(box, camera, pixelSpread);
}

void countScene(SceneFeatures& f, const Scene& scene) {
  if (scene.uvs)
    for (size_t i = 0; i < scene.leaves.size(); ++i) f.uvLeaves += scene.uvs->has(uint32_t(i));
  f.uvSetsDropped = scene.uvSetsDropped;
  f.shutterOpen = scene.camera.shutterClose > scene.camera.shutterOpen;
  f.environment = scene.moreLights.environment != nullptr;
  f.distantLights = scene.moreLights.distants.size();
  for (const Material& m : scene.materials) f.texturedMaterials += m.textured();
  f.volumes = scene.media.size();
  for (const auto& m : scene.media) {
    f.volumeBricks += m->bricks();
    f.volumeVoxels += uint64_t(m->densityGrid().storedBricks()) * Medium::kBrickVoxels;  // read once at load
    f.volumeBytes += m->bytes();
    f.emittingVolumes += m->emits() ? 1 : 0;
  }
  f.volumeLoadSeconds = scene.volumeLoadSeconds;
}

}  // namespace

bool isLowPrecisionLeaf(const Box3& box, Vec3 camera, float pixelSpread) {
  if (box.empty()) return false;
  const double ulp = double(box.magnitude()) * 0x1p-23;  // at least the float spacing of every coordinate
  if (!(ulp > 0x1p-16 * double(box.longestSide()))) return false;
  // The camera's distance to the box (0 inside it), in double: the footprint's lower bound.
  double d2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double c = camera[k], gap = std::max({double(box.lo[k]) - c, c - double(box.hi[k]), 0.0});
    d2 += gap * gap;
  }
  return ulp > 0x1p-8 * double(pixelSpread) * std::sqrt(d2);
}

std::vector<PatchLight> patchLightsOf(const Scene& scene) {
  std::vector<PatchLight> lights;
  for (size_t i = 0; i < scene.leaves.size(); ++i) {
    const Material& m = scene.materials[scene.leafMaterial[i]];
    if (!m.emits()) continue;
    PatchPtr patch = scene.leaves.patch(i);
    lights.push_back({[patch](float u, float v, Vec3& p, Vec3& nrm) {
                        const SurfacePoint sp = patch->evaluate(u, v);
                        p = sp.p; nrm = sp.n;
                      },
                      m.emission, m.twoSided, uint32_t(i)});
  }
  return lights;
}

namespace {

// A compiled scene's stored top level, adopted in place (its sections read through the
// mapping's gates, counted under --scene-memory). False for a scene without one.
bool adoptStoredTopLevel(const Scene& scene, TopLevelBvh& top) {
  using compiled::SectionKind;
  if (!scene.compiled || !scene.compiled->has(SectionKind::TopLevel)) return false;
  const MappedFile& file = *scene.compiled;
  const auto bad = [&](const char* section, const std::string& why) {
    throw InputError(file.path(), std::string("section ") + section, why);
  };
  compiled::TopLevelHeader h;
  if (file.sectionBytes(SectionKind::TopLevel) < sizeof h) bad("top_level", "shorter than its header");
  file.read(SectionKind::TopLevel, 0, sizeof h, &h, "header", 0);
  const size_t n = scene.leaves.size();
  if (h.nodeBytes != TopLevelBvh::kNodeBytes || h.leafCount != n ||
      h.nodeCount > (file.sectionBytes(SectionKind::TopLevel) - sizeof h) / TopLevelBvh::kNodeBytes ||
      file.sectionBytes(SectionKind::TopLevel) != sizeof h + h.nodeCount * TopLevelBvh::kNodeBytes)
    bad("top_level", "its header (" + std::to_string(h.nodeCount) + " nodes of " + std::to_string(h.nodeBytes) +
                         " bytes over " + std::to_string(h.leafCount) + " leaves) does not fit the section or the scene's " +
                         std::to_string(n) + " leaves: the file is corrupt");
  if (file.sectionBytes(SectionKind::LeafBoxes) != n * sizeof(Box3))
    bad("leaf_boxes", "not one box per leaf of the scene (" + std::to_string(n) + "): the file is corrupt");
  const MappedFile::GatedSection nodes = file.gated(SectionKind::TopLevel);
  const MappedFile::GatedSection boxes = file.gated(SectionKind::LeafBoxes);
  try {
    top.adopt(nodes.data + sizeof h, size_t(h.nodeCount), nodes.gate, sizeof h, h.root,
              GatedSpan<Box3>(reinterpret_cast<const Box3*>(boxes.data), n, boxes.gate));
  } catch (const std::invalid_argument& e) {
    bad("top_level", std::string("not a tree the traversal can walk: ") + e.what());
  }
  return true;
}

// A compiled scene's LeafShading rows, gated; an ungated (empty) span for a scene without them.
GatedSpan<LeafShadingRow> storedShadingRows(const Scene& scene) {
  using compiled::SectionKind;
  if (!scene.compiled || !scene.compiled->has(SectionKind::LeafShading)) return {};
  const MappedFile& file = *scene.compiled;
  const size_t n = scene.leaves.size();
  if (file.sectionBytes(SectionKind::LeafShading) != n * sizeof(LeafShadingRow))
    throw InputError(file.path(), "section leaf_shading", "not one 16-byte row per leaf of the scene (" + std::to_string(n) +
                                                              "): the file is corrupt");
  const MappedFile::GatedSection rows = file.gated(SectionKind::LeafShading);
  return GatedSpan<LeafShadingRow>(reinterpret_cast<const LeafShadingRow*>(rows.data), n, rows.gate);
}

}  // namespace

RenderData::RenderData(const Scene& scene) {
  const size_t n = scene.leaves.size();
  // A compiled scene's top level is adopted (nothing built, no box kept); otherwise it is
  // built over the boxes gathered below.
  const bool adopted = adoptStoredTopLevel(scene, top);
  // ... and its per-leaf shading tables read in place, not made.
  shading.leafRows = storedShadingRows(scene);
  const bool rowsStored = shading.leafRows.gated();
  std::vector<Box3> leafBoxes(adopted ? 0 : n);  // kept by the top level (TopLevelBvh::leafBoxes), not copied
  if (!rowsStored) shading.leafDicingError.resize(n);
  if (adopted && !rowsStored) shading.leafSide.resize(n);
  // The facts are gathered once (a generated leaf's patch is made and dropped again), a chunk
  // of leaves at a time, so that they never take 32 bytes a leaf at once (10 M leaves: 326 MB
  // beside the top level's build); only the dicing error is kept per leaf.
  constexpr size_t kChunk = size_t(1) << 16;
  const float pixelSpread =
      2.0f * std::tan(0.5f * scene.camera.fovYDegrees * std::numbers::pi_v<float> / 180.0f) / float(scene.height);
  std::vector<LeafFacts> facts;
  std::vector<Box3> chunkBoxes;
  Box3 all;  // the union of the leaves' boxes, in leaf order
  std::map<std::string, uint64_t> kinds;
  std::string kind;
  for (size_t c0 = 0; c0 < n; c0 += kChunk) {
    const size_t c1 = std::min(n, c0 + kChunk);
    facts.resize(c1 - c0);
    chunkBoxes.resize(c1 - c0);
    tbb::parallel_for(tbb::blocked_range<size_t>(c0, c1, 1024), [&](const auto& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        chunkBoxes[i - c0] = scene.leaves.bounds(i);
        if (!adopted) leafBoxes[i] = chunkBoxes[i - c0];
        facts[i - c0] = scene.leaves.facts(i);
        // Stored rows are read at hits without checks: each is checked here, once, against the
        // leaf table and the scene's materials (its CRC only says it is what was written).
        if (rowsStored) {
          const LeafShadingRow row = shading.leafRows[i];
          const float side = chunkBoxes[i - c0].longestSide();
          if (row.material != scene.leafMaterial[i] || row.shadeRank >= n ||
              std::memcmp(&row.side, &side, sizeof(float)) != 0 ||
              std::memcmp(&row.dicingError, &facts[i - c0].dicingError, sizeof(float)) != 0)
            throw InputError(scene.compiled->path(), "section leaf_shading (leaf " + std::to_string(i) + ")",
                             "disagrees with the leaf table: the file is corrupt");
        }
      }
    });
    for (size_t i = c0; i < c1; ++i) {
      const LeafFacts& f = facts[i - c0];
      if (kind != f.kind) kind = f.kind;  // leaves of a kind come in runs: no string made per leaf
      ++kinds[kind];
      countLeaf(features, f, chunkBoxes[i - c0], scene.camera.position, pixelSpread);
      if (!rowsStored) shading.leafDicingError[i] = f.dicingError;
      if (adopted && !rowsStored) shading.leafSide[i] = chunkBoxes[i - c0].longestSide();
      all.extend(chunkBoxes[i - c0]);
    }
  }
  facts = {};
  chunkBoxes = {};
  leafKinds.assign(kinds.begin(), kinds.end());
  countScene(features, scene);
  // The media's bricks (or groups of them: BrickNumbering) are top-level leaves after the
  // patches (core/medium_leaves.h), so the sorted engine sorts rays by brick; a scene without
  // media adds none.
  shading.bricks = BrickNumbering(scene.media);
  shading.firstBrickLeaf = uint32_t(n);
  if (!adopted && shading.bricks.leaves() > 0) {
    const BrickNumbering& bricks = shading.bricks;
    leafBoxes.resize(n + bricks.leaves());
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, bricks.leaves(), 1024), [&](const auto& r) {
      for (uint32_t l = r.begin(); l != r.end(); ++l) {
        const Medium& m = *scene.media[bricks.mediumOfLeaf(l)];
        Box3 box;
        for (const uint32_t global : bricks.bricksOfLeaf(l)) box.extend(m.brickWorldBounds(bricks.brickOf(global).brick));
        leafBoxes[n + l] = box;
      }
    });
  }
  // Built before the tables below are made: its build (Embree's primitives and nodes) is the
  // set-up's peak, which they would add to.
  if (!adopted) top.build(std::move(leafBoxes));

  const CameraDesc& cam = scene.camera;
  shading.camera = PerspectiveCamera(cam.position, cam.lookAt, cam.up, cam.fovYDegrees, scene.width, scene.height,
                                     cam.apertureRadius, cam.focusDistance, cam.shutterOpen, cam.shutterClose);
  shading.width = scene.width;
  shading.height = scene.height;
  shading.samplesPerPixel = scene.samplesPerPixel;
  shading.integrator = scene.integrator;
  shading.materials = scene.materials;
  if (!rowsStored) shading.leafMaterial = scene.leafMaterial;
  shading.media = scene.media;
  for (const auto& m : scene.media) shading.mediaEmit = shading.mediaEmit || m->emits();
  shading.texCoords = scene.uvs;  // null when no leaf has a uv set: lookups read (u, v) alone
  if (!adopted && !rowsStored) {
    const GatedSpan<Box3> boxes = top.leafBoxes();
    shading.leafSide.resize(n);
    for (size_t i = 0; i < n; ++i) shading.leafSide[i] = boxes[i].longestSide();
  }
  // Lights at infinity are picked by power through a disk of the scene's bounding radius, and
  // light paths leave them from such a disk about the scene's centre.
  const float radius = all.empty() ? 1.0f : std::max(std::numeric_limits<float>::min(), 0.5f * length(all.extent()));
  const Vec3 center = all.empty() ? Vec3{} : all.center();
  shading.lights = LightSampler(scene.pointLights, patchLightsOf(scene), scene.moreLights, radius, center);
}

size_t RenderData::leafTableBytes() const {
  return shading.leafMaterial.capacity() * sizeof(uint32_t) +
         shading.leafSide.capacity() * sizeof(float) + shading.leafDicingError.capacity() * sizeof(float);
}

}  // namespace rayes
