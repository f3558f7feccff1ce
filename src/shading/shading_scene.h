// Everything shading knows of a scene, indexed by leaf where per patch. The app builds it from
// the loaded Scene (app/render_data.h); every integrator reads it and never changes it.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>
#include "core/gated_span.h"
#include "core/ray_batch.h"
#include "shading/camera.h"
#include "shading/light.h"
#include "shading/material.h"
#include "shading/medium.h"
#include "shading/volume_tracking.h"

namespace rayes {

struct IntegratorSettings {
  int maxDepth = 8;          // path vertices after the camera; 1 = direct lighting only
  int rouletteDepth = 1;     // first bounce at which Russian roulette may end a path
  uint64_t seed = 0;
  // Shadow segments through media: ratio tracking (false, the default) or delta tracking's
  // binary estimate (true: 1 when no real collision, for comparing the two; scene key
  // integrator.transmittance).
  bool deltaTransmittance = false;
  // Whether camera paths record their first hit for the film's AOVs (added to the film when the
  // camera rays are shaded): set by the render from its outputs, not by the scene; without, the
  // film gets no AOVs, coverage included.
  bool firstHitAovs = true;
};

// What shading reads of a leaf at a hit, as a compiled scene stores it (one 16-byte row per
// leaf of the render, the shapes' then the lights': scene/compiled_scene.h).
struct LeafShadingRow {
  uint32_t material;
  float side;         // longest side l of the leaf's box
  float dicingError;  // C of Patch::dicingErrorCoefficient (bound C / 4^level)
  uint32_t shadeRank; // shadeRanks(): its place in (material, leaf) order
};
static_assert(sizeof(LeafShadingRow) == 16);

struct ShadingScene {
  PerspectiveCamera camera;
  int width = 1, height = 1, samplesPerPixel = 1;
  IntegratorSettings integrator;
  std::vector<Material> materials;
  // Per leaf: in memory (the JSON route, tests), or, for a compiled scene, the rows below read
  // in place through the mapping (these three vectors then stay empty). Read them through the
  // accessors.
  std::vector<uint32_t> leafMaterial;
  std::vector<float> leafSide;         // longest side l of the leaf's box
  std::vector<float> leafDicingError;  // C of Patch::dicingErrorCoefficient (bound C / 4^level)
  GatedSpan<LeafShadingRow> leafRows;
  size_t leafCount() const { return leafRows.gated() ? leafRows.size() : leafMaterial.size(); }
  uint32_t materialOf(uint32_t leaf) const { return leafRows.gated() ? leafRows[leaf].material : leafMaterial[leaf]; }
  float sideOf(uint32_t leaf) const { return leafRows.gated() ? leafRows[leaf].side : leafSide[leaf]; }
  float dicingErrorOf(uint32_t leaf) const { return leafRows.gated() ? leafRows[leaf].dicingError : leafDicingError[leaf]; }
  LightSampler lights;
  // The leaves' uv sets (null: no leaf has one; textures read the patch parameters).
  std::shared_ptr<const TexCoordSource> texCoords;
  // Participating media (shading/medium.h; empty: rays travel in vacuum and no tracking runs).
  std::vector<std::shared_ptr<const Medium>> media;
  // The render's cache of the media's stored bricks (`--volume-memory`; null: no medium reads a
  // file). Shared, internally synchronised: its state never changes a value read through it.
  std::shared_ptr<BrickCache> volumeCache;
  bool mediaEmit = false;  // some medium has an emission or temperature grid
  // The media's bricks numbered across the list, and the top-level leaf of brick 0: brick g is
  // leaf firstBrickLeaf + g (core/medium_leaves.h; after the patch leaves).
  BrickNumbering bricks;
  uint32_t firstBrickLeaf = kNoLeaf;
};

// Where a hit's material reads its textures: the patch parameters, the leaf's uv set when it
// has one, and the footprint of `ray`'s cone there (shading/footprint.h) -- its width at the hit
// times `widthScale` (a camera ray's: cameraFootprintScale(spp); others 1), solved against the
// surface derivatives `dpd` (RayBatch::derivativesOf; null: a point sample). Every method's
// shading asks this (or the point sample below).
TextureQuery textureQueryAt(const ShadingScene& scene, const Ray& ray, const RayHit& h, const HitDerivatives* dpd,
                            float widthScale);
// The same as a point sample, no footprint: the light-side hits of lt, pm and ppm's photons and
// lbt's beam corners, whose cones stand for no pixel (their estimates are averaged over a pixel
// by the film, or over a gather's kernel, not by a texture filter).
TextureQuery textureQueryAt(const ShadingScene& scene, const RayHit& h);

// Per leaf, its place in (material, leaf) order: the key that groups a generation's hits by
// material and leaf for shading (PathTracer) in one 32-bit word. O(leaves + materials).
std::vector<uint32_t> shadeRanks(const std::vector<uint32_t>& leafMaterial);

}  // namespace rayes
