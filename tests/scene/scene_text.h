// The smallest valid scene file, for tests that change one piece of it, and the message a
// scene text (or an OBJ text) is rejected with.
#pragma once
#include <string>
#include "core/error.h"
#include "scene/obj_reader.h"
#include "scene/scene_loader.h"

namespace rayes::test {

// One bilinear quad with material "m"; `shapeExtra` is spliced into the shape's object
// (e.g. R"(, "displacement": {...})").
inline std::string minimalScene(const std::string& shapeExtra = "") {
  return R"({
  "camera": {"position": [0, -3, 1], "look_at": [0, 0, 0], "up": [0, 0, 1], "fov": 40},
  "film": {"resolution": [32, 24], "spp": 4},
  "materials": {"m": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
  "shapes": [{"type": "bilinear", "material": "m", "quads": [[[-1,-1,0],[1,-1,0],[-1,1,0],[1,1,0]]])" +
         shapeExtra + R"(}]
})";
}

// The InputError message parsing `text` (named bad.json) gives, or "no error".
inline std::string errorOf(const std::string& text) {
  try {
    parseScene(text, "bad.json");
  } catch (const InputError& e) {
    return e.message();
  }
  return "no error";
}

// The InputError message parsing `text` as an OBJ file (named bad.obj) gives, or "no error".
inline std::string objError(const std::string& text) {
  try {
    parseObj(text, "bad.obj");
  } catch (const InputError& e) {
    return e.message();
  }
  return "no error";
}

}  // namespace rayes::test
