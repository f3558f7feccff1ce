// The kinds of shape a scene file can hold, and the modifiers every shape can carry.
// A kind's reader checks its own keys and returns a ShapeSource: a function that builds the
// shape's patches under a given transform (one call per time sample when the shape moves).
// shape_reader.cpp owns the table of kinds and applies the modifiers in a fixed order.
#pragma once
#include <filesystem>
#include <functional>
#include <string>
#include <vector>
#include "core/transform.h"
#include "geometry/displacement.h"
#include "geometry/patch.h"
#include "scene/leaf_uv_table.h"
#include "scene/json_reader.h"
#include "scene/scene.h"

namespace rayes {

struct ShapeContext {
  const JsonReader& reader;
  const json& shape;
  std::string ptr;                 // JSON pointer of the shape, for messages
  std::filesystem::path sceneDir;  // relative files are relative to the scene file

  // A file named by the shape, resolved and checked to exist.
  std::filesystem::path file(const char* key) const;
};

struct ShapeSource {
  std::vector<const char*> keys;  // the kind's own keys, besides the common ones
  std::function<std::vector<PatchPtr>(const TransformD&)> build;
  std::shared_ptr<const ShapeUvs> uvs;  // the patches' uv sets (null: none)
};

// A shape's optional "uvs" for `patches` Bézier or bilinear patches: one [[s, t] x 4] per
// patch, at (u, v) = (0, 0), (1, 0), (0, 1), (1, 1). Null when the shape has no "uvs".
std::shared_ptr<const ShapeUvs> readCornerUvs(const ShapeContext& ctx, size_t patches);

ShapeSource readBezierShape(const ShapeContext& ctx);
ShapeSource readBilinearShape(const ShapeContext& ctx);
ShapeSource readSubdivShape(const ShapeContext& ctx);

// The "transform" modifier: an array of steps (docs/scene-format.md).
TransformD readTransform(const JsonReader& r, const json& j, const std::string& ptr);

// The "motion" modifier of ctx.shape (motion_reader.cpp; the shape must have it): K >= 2
// strictly increasing times and one transform keyframe per time; a count that disagrees
// between the two is an InputError naming the file, line and JSON pointer.
struct Motion {
  std::vector<float> times;
  std::vector<TransformD> keyframes;  // applied after the shape's own transform
};
Motion readMotion(const ShapeContext& ctx);
// The shape built once per keyframe (build(keyframe * xf)), patch i of every sample wrapped in
// one MovingPatch. Keyframes that are all equal give the static patches (one time sample).
std::vector<PatchPtr> movingPatches(const Motion& m, const TransformD& xf,
                                    const std::function<std::vector<PatchPtr>(const TransformD&)>& build);

// The "displacement" modifier of ctx.shape (displacement_reader.cpp; the shape must have it).
// A height map is opened in scene.textureCache().
DisplacementPtr readDisplacement(const ShapeContext& ctx, Scene& scene);
// A height map's image (an EXR, read through the scene's texture cache) and its channel:
// `channel` as named, or chosen (Y, R, or the only one) and set when empty. Problems call
// fail("file" | "channel", why), which must throw (the JSON route names the pointer, a
// compiled scene its section).
std::shared_ptr<const HeightMap> openHeightMap(const std::filesystem::path& path, std::string& channel, Scene& scene,
                                               const std::function<void(const char*, const std::string&)>& fail);
// `patches` = source.build(xf), each wrapped in a DisplacedPatch when `d` is not null. The
// displacement is a function of the object-space surface (source.build of the identity), so
// the pattern moves with the shape's transform and is the same at every time sample.
std::vector<PatchPtr> displacePatches(const DisplacementPtr& d, const ShapeSource& source, const TransformD& xf,
                                      std::vector<PatchPtr> patches);

}  // namespace rayes
