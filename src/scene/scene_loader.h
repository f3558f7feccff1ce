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

}  // namespace rayes
