#include "scene/scene_loader.h"
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include "core/text_file.h"
#include "scene/json_document.h"
#include "scene/scene_sections.h"

namespace rayes {
namespace {

void readCamera(const JsonReader& r, const json& j, Scene& scene) {
  const std::string p = "/camera";
  r.object(j, p, {"position", "look_at", "up", "fov", "aperture_radius", "focus_distance", "shutter"});
  CameraDesc& c = scene.camera;
  // The camera's position is the render frame's origin: everything read after it is placed
  // relative to it, in double (RenderFrame).
  const Vec3d position = r.vec3d(r.member(j, p, "position"), p + "/position");
  const Vec3d lookAt = r.vec3d(r.member(j, p, "look_at"), p + "/look_at");
  scene.frame.origin = position;
  c.position = {0, 0, 0};
  c.lookAt = scene.frame.point(lookAt);
  if (j.contains("up")) c.up = r.vec3(j["up"], p + "/up");
  if (j.contains("fov")) c.fovYDegrees = float(r.number(j["fov"], p + "/fov"));
  if (!(c.fovYDegrees > 0 && c.fovYDegrees < 180)) r.fail(p + "/fov", "the field of view must be in (0, 180) degrees");
  const Vec3 forward = c.lookAt - c.position;
  if (!(length(lookAt - position) > 0) || !(length(forward) > 0))
    r.fail(p + "/look_at", "look_at equals position: the camera has no direction");
  if (!(length(c.up) > 0)) r.fail(p + "/up", "the up vector must not be zero");
  const Vec3 side = cross(normalize(forward), normalize(c.up));
  if (!(length(side) > 1e-6f)) r.fail(p + "/up", "the camera looks along its up vector");
  c.focusDistance = length(forward);
  if (j.contains("aperture_radius")) {
    c.apertureRadius = float(r.number(j["aperture_radius"], p + "/aperture_radius"));
    if (c.apertureRadius < 0) r.fail(p + "/aperture_radius", "the aperture radius must not be negative");
  }
  if (j.contains("focus_distance")) {
    c.focusDistance = float(r.number(j["focus_distance"], p + "/focus_distance"));
    if (!(c.focusDistance > 0)) r.fail(p + "/focus_distance", "the focus distance must be positive");
  }
  if (j.contains("shutter")) {
    const json& sh = j["shutter"];
    if (!sh.is_array() || sh.size() != 2) r.fail(p + "/shutter", "expected [open, close]");
    c.shutterOpen = float(r.number(sh[0], p + "/shutter/0"));
    c.shutterClose = float(r.number(sh[1], p + "/shutter/1"));
    if (c.shutterClose < c.shutterOpen) r.fail(p + "/shutter", "the shutter closes before it opens");
  }
}

void readFilm(const JsonReader& r, const json& j, Scene& scene) {
  const std::string p = "/film";
  r.object(j, p, {"resolution", "spp"});
  if (j.contains("resolution")) {
    const json& res = j["resolution"];
    if (!res.is_array() || res.size() != 2) r.fail(p + "/resolution", "expected [width, height]");
    scene.width = r.integer(res[0], p + "/resolution/0");
    scene.height = r.integer(res[1], p + "/resolution/1");
    if (scene.width <= 0 || scene.height <= 0) r.fail(p + "/resolution", "width and height must be positive");
    if (int64_t(scene.width) * scene.height > (int64_t(1) << 28)) r.fail(p + "/resolution", "more than 2^28 pixels");
  }
  if (j.contains("spp")) {
    scene.samplesPerPixel = r.integer(j["spp"], p + "/spp");
    if (scene.samplesPerPixel <= 0) r.fail(p + "/spp", "samples per pixel must be positive");
  }
}

void readIntegrator(const JsonReader& r, const json& j, Scene& scene) {
  const std::string p = "/integrator";
  r.object(j, p, {"max_depth", "seed", "roulette_depth", "transmittance"});
  if (j.contains("transmittance")) {
    const std::string t = r.string(j["transmittance"], p + "/transmittance");
    if (t != "ratio" && t != "delta") r.fail(p + "/transmittance", "must be \"ratio\" or \"delta\"");
    scene.integrator.deltaTransmittance = t == "delta";
  }
  if (j.contains("max_depth")) {
    scene.integrator.maxDepth = r.integer(j["max_depth"], p + "/max_depth");
    if (scene.integrator.maxDepth < 0 || scene.integrator.maxDepth > 1000) r.fail(p + "/max_depth", "must be in [0, 1000]");
  }
  if (j.contains("roulette_depth")) {
    scene.integrator.rouletteDepth = r.integer(j["roulette_depth"], p + "/roulette_depth");
    if (scene.integrator.rouletteDepth < 0) r.fail(p + "/roulette_depth", "must not be negative");
  }
  if (j.contains("seed")) {
    const int s = r.integer(j["seed"], p + "/seed");
    if (s < 0) r.fail(p + "/seed", "must not be negative");
    scene.integrator.seed = uint64_t(s);
  }
}

}  // namespace

namespace {

// parseScene's body; `shapes` null: the "/shapes" section is read, else it becomes the shapes.
Scene parseSceneText(const std::string& fileText, const std::string& path, LeafSourcePtr shapes,
                     std::vector<uint32_t> shapeMaterial, const TextureCacheOptions& textures) {
  const std::string_view text = withoutByteOrderMark(fileText);
  const json doc = parseJsonDocument(text, path);
  JsonReader r(path, text);
  r.object(doc, "", {"camera", "film", "integrator", "materials", "lights", "shapes"});
  Scene scene;
  scene.path = path;
  scene.textureOptions = textures;
  readCamera(r, r.member(doc, "", "camera"), scene);
  if (doc.contains("film")) readFilm(r, doc["film"], scene);
  if (doc.contains("integrator")) readIntegrator(r, doc["integrator"], scene);
  const auto materials = readMaterials(r, r.member(doc, "", "materials"), scene);
  const auto dir = std::filesystem::path(path).parent_path();
  if (shapes) {
    if (shapeMaterial.size() != shapes->size()) throw std::logic_error("one material per shape leaf");
    for (uint32_t m : shapeMaterial)
      if (m >= scene.materials.size()) r.fail("/materials", "a compiled leaf names material " + std::to_string(m) + " of " + std::to_string(scene.materials.size()));
    scene.leaves.add(std::move(shapes));
    scene.leafMaterial = std::move(shapeMaterial);
  } else {
    readShapes(r, r.member(doc, "", "shapes"), scene, materials, dir);
  }
  scene.shapeLeaves = scene.leaves.size();
  if (doc.contains("lights")) readLights(r, doc["lights"], scene);
  if (scene.leaves.empty()) r.fail("/shapes", "the scene has no shapes");
  // Uv sets no texture reads cost memory and nothing else: leave them out.
  const auto readsUv = [](const ColorParam& c) { return c.texture && c.texture->coordinates == Texture::Coordinates::Uv; };
  if (scene.uvs && std::none_of(scene.materials.begin(), scene.materials.end(), [&](const Material& m) {
        return readsUv(m.albedo) || readsUv(m.specular);
      })) {
    scene.uvs.reset();
    scene.uvSetsDropped = true;
  }
  return scene;
}

}  // namespace

Scene parseScene(const std::string& fileText, const std::string& path, const TextureCacheOptions& textures) {
  return parseSceneText(fileText, path, nullptr, {}, textures);
}

Scene parseSceneWithShapes(const std::string& text, const std::string& path, LeafSourcePtr shapes,
                           std::vector<uint32_t> shapeMaterial, const TextureCacheOptions& textures) {
  return parseSceneText(text, path, std::move(shapes), std::move(shapeMaterial), textures);
}

Scene loadScene(const std::string& path, const TextureCacheOptions& textures) {
  return parseScene(readTextFile(path, "scene file"), path, textures);
}

}  // namespace rayes
