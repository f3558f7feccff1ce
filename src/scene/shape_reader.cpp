#include <algorithm>
#include <map>
#include "scene/scene_sections.h"
#include "scene/shape_kinds.h"

namespace rayes {

std::filesystem::path ShapeContext::file(const char* key) const {
  const std::string f = reader.string(reader.member(shape, ptr, key), ptr + "/" + key);
  const std::filesystem::path fp = std::filesystem::path(f).is_absolute() ? std::filesystem::path(f) : sceneDir / f;
  if (!std::filesystem::exists(fp)) reader.fail(ptr + "/" + key, "cannot open file '" + fp.string() + "'");
  if (std::filesystem::is_directory(fp)) reader.fail(ptr + "/" + key, "'" + fp.string() + "' is a directory");
  return fp;
}

uint32_t materialRef(const JsonReader& r, const json& obj, const std::string& p, const MaterialIndex& materials,
                     const char* key) {
  const std::string at = p + "/" + key;
  const std::string name = r.string(r.member(obj, p, key), at);
  auto it = materials.find(name);
  if (it == materials.end()) r.fail(at, "no material named '" + name + "'");
  return it->second;
}

std::shared_ptr<const ShapeUvs> readCornerUvs(const ShapeContext& ctx, size_t patches) {
  const JsonReader& r = ctx.reader;
  if (!ctx.shape.contains("uvs")) return nullptr;
  const std::string p = ctx.ptr + "/uvs";
  const json& us = ctx.shape["uvs"];
  if (!us.is_array()) r.fail(p, "expected an array with one [[s, t] x 4] per patch, got " + JsonReader::typeName(us));
  if (us.size() != patches)
    r.fail(p, "expected one uv entry per patch: " + std::to_string(patches) + " patches, " +
                  std::to_string(us.size()) + " entries");
  auto out = std::make_shared<ShapeUvs>();
  out->corners.resize(patches);
  for (size_t k = 0; k < patches; ++k) {
    const std::string pk = p + "/" + std::to_string(k);
    if (!us[k].is_array() || us[k].size() != 4) r.fail(pk, "expected 4 corners [st00, st10, st01, st11]");
    for (size_t c = 0; c < 4; ++c) {
      const std::string pc = pk + "/" + std::to_string(c);
      if (!us[k][c].is_array() || us[k][c].size() != 2) r.fail(pc, "expected [s, t]");
      for (size_t x = 0; x < 2; ++x) out->corners[k][c][x] = float(r.number(us[k][c][x], pc + "/" + std::to_string(x)));
    }
  }
  return out;
}

namespace {

// Leaf `leaf` is patch k of a shape with uv sets.
void addLeafUvs(Scene& scene, uint32_t leaf, const ShapeUvs& uvs, size_t k) {
  if (!scene.uvs) scene.uvs = std::make_shared<LeafUvTable>();
  if (uvs.subdiv) scene.uvs->setSubdiv(leaf, uvs.subdiv, uint32_t(k));
  else scene.uvs->setCorners(leaf, uvs.corners[k]);
}

using KindReader = ShapeSource (*)(const ShapeContext&);
const std::map<std::string, KindReader>& shapeKinds() {
  static const std::map<std::string, KindReader> kinds = {
      {"bezier", readBezierShape},
      {"bilinear", readBilinearShape},
      {"subdiv", readSubdivShape},
  };
  return kinds;
}

// Keys every shape may carry, whatever its kind.
const std::vector<const char*> kCommonKeys = {"type", "material", "transform", "displacement", "motion"};

}  // namespace

void readShapes(const JsonReader& r, const json& j, Scene& scene, const MaterialIndex& materials,
                const std::filesystem::path& sceneDir) {
  if (!j.is_array()) r.fail("/shapes", "expected an array of shapes");
  for (size_t s = 0; s < j.size(); ++s) {
    const std::string p = "/shapes/" + std::to_string(s);
    const json& shape = j[s];
    if (!shape.is_object()) r.fail(p, "expected an object");
    const std::string type = r.string(r.member(shape, p, "type"), p + "/type");
    if (type == "forest") {  // generated leaves, not a ShapeSource of patches
      readForestShape(r, shape, p, scene, materials);
      continue;
    }
    if (type == "volume") {  // a medium, not leaves
      readVolumeShape(r, shape, p, scene, sceneDir);
      continue;
    }
    const auto kind = shapeKinds().find(type);
    if (kind == shapeKinds().end()) {
      std::string known;
      for (const auto& [name, _] : shapeKinds()) known += (known.empty() ? "" : ", ") + name;
      known += ", forest, volume";
      r.fail(p + "/type", "unknown shape type '" + type + "' (expected " + known + ")");
    }
    const ShapeContext ctx{r, shape, p, sceneDir};
    const ShapeSource source = kind->second(ctx);
    std::set<std::string> allowed(kCommonKeys.begin(), kCommonKeys.end());
    allowed.insert(source.keys.begin(), source.keys.end());
    r.objectKeys(shape, p, allowed);
    const uint32_t mat = materialRef(r, shape, p, materials);
    const TransformD xf = shape.contains("transform") ? readTransform(r, shape["transform"], p + "/transform") : TransformD{};
    const DisplacementPtr disp = shape.contains("displacement") ? readDisplacement(ctx, scene) : nullptr;
    // The shape's world transform (per keyframe), then the move into the render frame, composed
    // in double: only the result is rounded to float (RenderFrame).
    const TransformD toFrame = scene.frame.fromWorld();
    const auto build = [&](const TransformD& t) {
      const TransformD placed = toFrame * t;
      return displacePatches(disp, source, placed, source.build(placed));
    };
    // With "motion": one set of patches per time sample, each patch a MovingPatch of its versions.
    std::vector<PatchPtr> patches = shape.contains("motion") ? movingPatches(readMotion(ctx), xf, build) : build(xf);
    for (size_t k = 0; k < patches.size(); ++k) {
      const uint32_t leaf = uint32_t(scene.leaves.size());
      addPatch(r, p, scene, std::move(patches[k]), mat);
      if (source.uvs) addLeafUvs(scene, leaf, *source.uvs, k);
    }
  }
}

}  // namespace rayes
