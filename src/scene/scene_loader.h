// Loads a scene file (JSON, docs/scene-format.md). Every problem with the input -- a missing
// file, a syntax error, an unknown key, a wrong type, an impossible value, a bad patch file --
// throws InputError naming the file and the place (line:column and JSON pointer). Nothing is
// written anywhere.
#pragma once
#include <string>
#include "scene/scene.h"

namespace rayes {

// `textures`: how the scene's texture cache is made if it names an image (its memory bound and
// conversion folder, texture/texture_cache.h).
Scene loadScene(const std::string& path, const TextureCacheOptions& textures = {});
// The same from text in memory (tests); `path` names it in messages and anchors relative files.
Scene parseScene(const std::string& text, const std::string& path, const TextureCacheOptions& textures = {});
// The same with the shapes given instead of read (a compiled scene, scene/compiled_scene.h):
// `shapes` become leaves [0, shapes.size()) with `shapeMaterial`, in place of what "/shapes"
// would build; everything else (camera, film, integrator, materials, lights, whose rectangles
// and disks become the leaves after them) is read from `text` as parseScene reads it.
Scene parseSceneWithShapes(const std::string& text, const std::string& path, LeafSourcePtr shapes,
                           std::vector<uint32_t> shapeMaterial, const TextureCacheOptions& textures = {});

}  // namespace rayes
