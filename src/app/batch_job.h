// What a render's .film files (parts, checkpoints, app/film_file.h) say about the render, and
// the checks that a film belongs to it: the fingerprint (the scene file's bytes and every
// setting that changes the image), the program version, the size, the crop and the part.
// Settings that never change the image (threads, --ray-memory, --grid-cache,
// --candidates-per-ray, --trace-mode, --dice-cache, --memory-limit, the checkpoint period, the
// time limit: docs/design.md, invariant 2) are not in it, so a render may resume or a part be
// rendered with other values of them. Files the scene file names (OBJ, height maps, textures)
// are not in it either: change them and a checkpoint is still taken as this render's.
#pragma once
#include <string>
#include <vector>
#include <nlohmann/json.hpp>
#include "app/film_file.h"
#include "app/renderer.h"
#include "scene/scene.h"

namespace rayes {

// The settings that change the image, by name (as in the stats file where it has them).
nlohmann::json imageSettings(const Scene& scene, const RenderOptions& options);
// A hex digest of the scene file's bytes and `settings`. Throws InputError if the scene file
// cannot be read.
std::string fingerprintOf(const std::string& scenePath, const nlohmann::json& settings);

// The header of a film of this render (kind "part", "checkpoint" or "film"), position and
// stats left for the caller.
FilmFileHeader filmHeader(const std::string& kind, const std::string& scenePath, const Scene& scene,
                          const RenderOptions& options, const Renderer& renderer);

// Throws InputError naming `path` when the film `found` is not of the render `expected`
// describes: another program version, another scene or setting (named), another size, crop,
// part or method. `use` says what it was meant for ("resume from", "merge"), `expectedName`
// whose the expected values are ("this render", the first part's file).
void checkSameRender(const std::string& path, const FilmFileHeader& found, const FilmFileHeader& expected,
                     const std::string& use, const std::string& expectedName);

// Combines the stats of the parts of a split (docs/stats.md, "Merged parts"): counters and
// times summed over the parts, bytes and peaks the largest part's, what every part shares
// (scene, settings, features) the first part's; generations listed part by part.
nlohmann::json combinedStats(const std::vector<nlohmann::json>& parts);

}  // namespace rayes
