// A Scene to a compiled .rayes file and back (`rayes compile`, `rayes render SCENE.rayes`;
// docs/scene-format.md, "Compiled scenes"; the container: geometry/compiled_file.h).
//
// What is compiled: the "shapes" section's leaves (leaf ids [0, Scene::shapeLeaves)): each
// leaf's box, facts and material in the leaf table, its patch as a record (geometry/
// patch_record.h); what records share, once: subdivision topologies and meshes' control points
// (the Meshes section), height maps as the file and channel the scene named (in the Scene
// section, opened again at load relative to the source's folder); the leaves' uv sets (the
// UvSets section, read through the mapping: LeafUvTable::mapped); a forest's leaves as their
// forest's generator tables (the Forests section: parameters, branches, foliage, read in place
// by a ForestPatches, geometry/forest_patches.h) and a 13-byte record per leaf, not as patches
// (format version 4). What stays text: the rest of
// the scene JSON (camera, film, integrator, materials, lights), with "shapes" emptied, and the
// source file's absolute path, against which its relative file names (textures, environment
// maps, height maps) resolve. Loading a compiled scene reads that text as the JSON loader does
// and puts the mapped leaves first, so leaf ids, materials and lights are those of the JSON
// scene and the image is the same, bit for bit. The top level, built at compile time, is
// stored too (sections TopLevel and LeafBoxes): the render adopts it (app/render_data.cpp).
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include "scene/scene.h"

namespace rayes {

// Writes `scene`, loaded from `jsonPath` (whose text is `jsonText`), to `outPath`, with `top`:
// the top level over all of the scene's leaves (shapes' and lights'), built by the caller. Throws
// InputError(jsonPath, "leaf N", ...) for a leaf whose kind cannot be compiled (a disk; a height
// map made in memory), InputError / ResourceError for a file that cannot be written.
// `progress(done, total)`, when given, is called between chunks of leaves.
void writeCompiledScene(const Scene& scene, const std::string& jsonText, const std::string& jsonPath,
                        const std::string& outPath, const compiled::StoredTopLevel& top,
                        const std::function<void(size_t, size_t)>& progress = {});

// Maps `path` (a .rayes) and builds its Scene; residentBudget (--scene-memory) bounds the
// mapping's resident blocks (0: no bound). InputError naming the file and the place for a file
// that is not a .rayes, of another format version, truncated or corrupt, whose counts disagree
// (a mesh, a topology, the uv records), or whose height map cannot be opened. Subdivision
// meshes are built and height maps opened here, once.
Scene loadCompiledScene(const std::string& path, uint64_t residentBudget, const TextureCacheOptions& textures = {});

// True for a name ending in .rayes (any case): what `rayes render` loads as a compiled scene.
bool isCompiledSceneName(const std::string& path);

}  // namespace rayes
