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

TextureQuery textureQueryAt(const ShadingScene& scene, const Ray& ray, const RayHit& h, const HitDerivatives* dpd,
                            float widthScale) {
  TexCoordSample st;
  const bool hasUv = scene.texCoords && scene.texCoords->has(h.leaf);
  if (hasUv) st = scene.texCoords->at(h.leaf, h.u, h.v);
  // The cone may narrow toward a focus (negative spread): its width is never below zero.
  const float width = std::max(0.0f, ray.coneWidth + h.t * ray.coneSpread) * widthScale;
  return footprintQuery(h.u, h.v, ray.dir, h.ng(), width, dpd, hasUv ? &st : nullptr);
}

TextureQuery textureQueryAt(const ShadingScene& scene, const RayHit& h) {
  TextureQuery q = TextureQuery::at(h.u, h.v);
  if (scene.texCoords && scene.texCoords->has(h.leaf)) {
    const TexCoordSample st = scene.texCoords->at(h.leaf, h.u, h.v);
    q.hasUv = true;
    q.uv.x = st.s; q.uv.y = st.t;
  }
  return q;
}

}  // namespace rayes
