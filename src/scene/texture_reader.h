// Textures and images in a scene file (docs/scene-format.md, "textures"): image files
// (OpenEXR, linear; PNG, sRGB-decoded to linear) and inline texture objects, and colour
// parameters that may be either a constant or a texture. Every failure is an InputError that
// names the scene file and the JSON pointer (an unreadable image also names the image).
#pragma once
#include <filesystem>
#include <memory>
#include <string>
#include "scene/json_reader.h"
#include "shading/material.h"
#include "shading/texture.h"

namespace rayes {

// Reads an .exr (R, G, B channels; a missing G/B copies R) or .png into linear RGB.
// Throws InputError(file, "", ...) when the file cannot be read.
std::shared_ptr<const Image> readImageFile(const std::filesystem::path& file);

// A colour parameter: a number, [r, g, b], or a texture object. reflectance: values must be
// in [0, 1] (image texels are clamped to [0, 1]); otherwise only non-negative.
ColorParam readColorParam(const JsonReader& r, const json& j, const std::string& ptr,
                          const std::filesystem::path& sceneDir, bool reflectance);

}  // namespace rayes
