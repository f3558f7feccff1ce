// Readers of the sections of a scene file. Each fills its part of the Scene and throws
// InputError for anything wrong (see json_reader.h). docs/scene-format.md is their reference.
#pragma once
#include <filesystem>
#include <map>
#include <string>
#include "scene/json_reader.h"
#include "scene/scene.h"

namespace rayes {

using MaterialIndex = std::map<std::string, uint32_t>;

// "materials": name -> material; returns the index of each name in scene.materials.
MaterialIndex readMaterials(const JsonReader& r, const json& j, Scene& scene);
// "shapes": every patch of every shape, transformed, into scene.leaves.
void readShapes(const JsonReader& r, const json& j, Scene& scene, const MaterialIndex& materials,
                const std::filesystem::path& sceneDir);
// "lights": point lights into scene.pointLights, rectangles as emissive patches.
void readLights(const JsonReader& r, const json& j, Scene& scene);

// Shared helpers of the section readers.
// The material named by obj[key].
uint32_t materialRef(const JsonReader& r, const json& obj, const std::string& ptr, const MaterialIndex& materials,
                     const char* key = "material");
// Adds a patch, or fails at ptr where float cannot hold it: a non-finite or overflowing box,
// or a patch too small for the float spacing at its position (representable.cpp).
void addPatch(const JsonReader& r, const std::string& ptr, Scene& scene, PatchPtr patch, uint32_t material);
// The same check for leaf `leaf` with box `b`.
void checkRepresentable(const JsonReader& r, const std::string& ptr, size_t leaf, const Box3& b);
// A {"type": "forest"} shape (forest_shape_reader.cpp): its leaves, generated on demand, and one
// material per part.
void readForestShape(const JsonReader& r, const json& shape, const std::string& ptr, Scene& scene,
                     const MaterialIndex& materials);
// A {"type": "volume"} shape (volume_shape_reader.cpp): a density grid of a .vdb file, read with
// OpenVDB into a Medium appended to scene.media; bad files, grids and values fail at ptr.
void readVolumeShape(const JsonReader& r, const json& shape, const std::string& ptr, Scene& scene,
                     const std::filesystem::path& sceneDir);

}  // namespace rayes
