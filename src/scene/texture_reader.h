// Textures in a scene file (docs/scene-format.md, "textures"): image files, read through the
// scene's texture cache (texture/texture_cache.h: tiled MIP-mapped files in place, plain
// images converted once; float formats linear, 8/16-bit ones sRGB-decoded to linear), inline
// texture objects, and colour parameters that may be either a constant or a texture. Every
// failure is an InputError that names the scene file and the JSON pointer (an unreadable image
// also names the image).
#pragma once
#include <filesystem>
#include <memory>
#include <string>
#include "scene/json_reader.h"
#include "scene/scene.h"
#include "shading/material.h"
#include "shading/texture.h"

namespace rayes {

// A colour parameter: a number, [r, g, b], or a texture object. reflectance: values must be
// in [0, 1] (an image's filtered values are clamped to [0, 1]); otherwise only non-negative.
// An image texture opens its file in scene.textureCache().
ColorParam readColorParam(const JsonReader& r, const json& j, const std::string& ptr,
                          const std::filesystem::path& sceneDir, bool reflectance, Scene& scene);

}  // namespace rayes
