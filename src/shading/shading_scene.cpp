#include "shading/shading_scene.h"
#include <algorithm>

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

}  // namespace rayes
