// Scenes shared by the light beam tests (tests/lbt).
#pragma once
#include <string>

namespace rayes::testing {

// A small rect light (radiance 40, 0.3 × 0.3 at z = 1) facing down onto a 2×2 mirror (ρ = 0.9, σ
// below the delta limit) at z = 0, a diffuse ceiling at z = 2 lit only through the mirror.
inline std::string rectLightOverMirrorJson(int width, int height, int spp) {
  return R"({
    "camera": {"position": [0, -5, 0.5], "look_at": [0, 0, 2], "up": [0, 0, 1], "fov": 50},
    "film": {"resolution": [)" + std::to_string(width) + ", " + std::to_string(height) + R"(], "spp": )" +
         std::to_string(spp) + R"(},
    "integrator": {"max_depth": 4, "seed": 0},
    "materials": {"mirror": {"type": "glossy", "specular": [0.9, 0.9, 0.9], "sigma": 0.0001},
      "ceiling": {"type": "diffuse", "albedo": [0.8, 0.8, 0.8]}},
    "shapes": [
      {"type": "bilinear", "material": "mirror", "quads": [[[-1, -1, 0], [1, -1, 0], [-1, 1, 0], [1, 1, 0]]]},
      {"type": "bilinear", "material": "ceiling", "quads": [[[-4, -4, 2], [4, -4, 2], [-4, 4, 2], [4, 4, 2]]]}],
    "lights": [{"type": "rect", "corner": [-0.15, -0.15, 1], "edge_u": [0, 0.3, 0], "edge_v": [0.3, 0, 0],
                "radiance": [40, 40, 40]}]})";
}

}  // namespace rayes::testing
