#include "shading/shading_scene.h"
#include <algorithm>
#include "shading/footprint.h"

namespace rayes {

std::vector<uint32_t> shadeRanks(const std::vector<uint32_t>& leafMaterial) {
  // A counting sort of the leaves by material, stable: rank order is (material, leaf) order.
  const uint32_t materials =
      leafMaterial.empty() ? 0 : *std::max_element(leafMaterial.begin(), leafMaterial.end()) + 1;
  std::vector<uint32_t> start(size_t(materials) + 1, 0);
  for (const uint32_t m : leafMaterial) ++start[size_t(m) + 1];
  for (size_t m = 1; m < start.size(); ++m) start[m] += start[m - 1];
  std::vector<uint32_t> rank(leafMaterial.size());
  for (size_t l = 0; l < leafMaterial.size(); ++l) rank[l] = start[leafMaterial[l]]++;
  return rank;
}

namespace {
// The leaf's uv set at the hit, when a texture may read it: a material that reads no texture
// needs no query at all, so its hits skip the uv set's evaluation (a Bfr face-varying surface on
// subdivision leaves) and the footprint's solve.
bool needsQuery(const ShadingScene& scene, const RayHit& h) {
  return scene.materials[scene.materialOf(h.leaf)].textured();
}
bool uvAt(const ShadingScene& scene, const RayHit& h, TexCoordSample& st) {
  if (!scene.texCoords || !scene.texCoords->has(h.leaf)) return false;
  st = scene.texCoords->at(h.leaf, h.u, h.v);
  return true;
}
}  // namespace

TextureQuery textureQueryAt(const ShadingScene& scene, const Ray& ray, const RayHit& h, const HitDerivatives* dpd,
                            float widthScale) {
  if (!needsQuery(scene, h)) return TextureQuery::at(h.u, h.v);
  TexCoordSample st;
  const bool hasUv = uvAt(scene, h, st);
  // The cone may narrow toward a focus (negative spread): its width is never below zero.
  const float width = std::max(0.0f, ray.coneWidth + h.t * ray.coneSpread()) * widthScale;
  return footprintQuery(h.u, h.v, ray.dir(), h.ng(), width, dpd, hasUv ? &st : nullptr);
}

TextureQuery textureQueryAt(const ShadingScene& scene, const RayHit& h) {
  if (!needsQuery(scene, h)) return TextureQuery::at(h.u, h.v);
  TexCoordSample st;
  const bool hasUv = uvAt(scene, h, st);
  return footprintQuery(h.u, h.v, Vec3{}, Vec3{}, 0.0f, nullptr, hasUv ? &st : nullptr);
}

}  // namespace rayes
