#include "scene/scene_loader.h"
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <nlohmann/json.hpp>
#include "core/error.h"
#include "core/transform.h"
#include "dicing/bezier_patch.h"
#include "dicing/bilinear_patch.h"
#include "scene/json_positions.h"

namespace rayes {
namespace {
using json = nlohmann::json;

// Typed, checked access to the parsed document; every failure names file, line:column and
// the JSON pointer of the offending value.
class Reader {
 public:
  Reader(std::string file, const std::string& text) : file_(std::move(file)), pos_(text) {}

  [[noreturn]] void fail(const std::string& ptr, const std::string& msg) const {
    throw InputError(file_, pos_.place(ptr), (ptr.empty() ? "/" : ptr) + ": " + msg);
  }
  static std::string typeName(const json& j) { return j.type_name(); }

  void object(const json& j, const std::string& ptr, std::initializer_list<const char*> allowed) const {
    if (!j.is_object()) fail(ptr, "expected an object, got " + typeName(j));
    const std::set<std::string> ok(allowed.begin(), allowed.end());
    for (auto it = j.begin(); it != j.end(); ++it)
      if (!ok.count(it.key())) {
        std::string list;
        for (const auto& k : ok) list += (list.empty() ? "" : ", ") + k;
        fail(ptr + "/" + it.key(), "unknown key '" + it.key() + "' (expected one of: " + list + ")");
      }
  }
  const json& member(const json& j, const std::string& ptr, const char* key) const {
    if (!j.contains(key)) fail(ptr, std::string("missing required key '") + key + "'");
    return j.at(key);
  }
  double number(const json& j, const std::string& ptr) const {
    if (!j.is_number()) fail(ptr, "expected a number, got " + typeName(j));
    const double v = j.get<double>();
    if (!std::isfinite(v) || std::fabs(v) > 3.0e38) fail(ptr, "number out of range");
    return v;
  }
  int integer(const json& j, const std::string& ptr) const {
    if (!j.is_number_integer()) fail(ptr, "expected an integer, got " + typeName(j));
    const auto v = j.get<int64_t>();
    if (v < -(int64_t(1) << 30) || v > (int64_t(1) << 30)) fail(ptr, "integer out of range");
    return static_cast<int>(v);
  }
  bool boolean(const json& j, const std::string& ptr) const {
    if (!j.is_boolean()) fail(ptr, "expected true or false, got " + typeName(j));
    return j.get<bool>();
  }
  std::string string(const json& j, const std::string& ptr) const {
    if (!j.is_string()) fail(ptr, "expected a string, got " + typeName(j));
    return j.get<std::string>();
  }
  Vec3 vec3(const json& j, const std::string& ptr) const {
    if (!j.is_array() || j.size() != 3) fail(ptr, "expected an array of 3 numbers");
    return {float(number(j[0], ptr + "/0")), float(number(j[1], ptr + "/1")), float(number(j[2], ptr + "/2"))};
  }
  Rgb color(const json& j, const std::string& ptr, bool atMostOne) const {
    const Rgb c = j.is_number() ? Rgb{float(number(j, ptr)), float(number(j, ptr)), float(number(j, ptr))}
                                : vec3(j, ptr);
    if (c.x < 0 || c.y < 0 || c.z < 0) fail(ptr, "must not be negative");
    if (atMostOne && (c.x > 1 || c.y > 1 || c.z > 1))
      fail(ptr, "a reflectance above 1 would create energy");
    return c;
  }
  const std::string& file() const { return file_; }

 private:
  std::string file_;
  JsonPositions pos_;
};

Transform readTransform(const Reader& r, const json& j, const std::string& ptr) {
  if (!j.is_array()) r.fail(ptr, "expected an array of transform steps");
  Transform t;
  for (size_t i = 0; i < j.size(); ++i) {
    const std::string p = ptr + "/" + std::to_string(i);
    const json& step = j[i];
    r.object(step, p, {"translate", "rotate", "scale", "matrix"});
    if (step.size() != 1) r.fail(p, "each transform step has exactly one of translate, rotate, scale, matrix");
    Transform s;
    if (step.contains("translate")) {
      s = Transform::translate(r.vec3(step["translate"], p + "/translate"));
    } else if (step.contains("scale")) {
      const json& sc = step["scale"];
      const Vec3 v = sc.is_number() ? Vec3{1, 1, 1} * float(r.number(sc, p + "/scale")) : r.vec3(sc, p + "/scale");
      if (v.x == 0 || v.y == 0 || v.z == 0) r.fail(p + "/scale", "a zero scale collapses the shape");
      s = Transform::scale(v);
    } else if (step.contains("rotate")) {
      const json& ro = step["rotate"];
      r.object(ro, p + "/rotate", {"axis", "degrees"});
      const Vec3 axis = r.vec3(r.member(ro, p + "/rotate", "axis"), p + "/rotate/axis");
      if (!(length(axis) > 0)) r.fail(p + "/rotate/axis", "the rotation axis must not be zero");
      s = Transform::rotate(axis, float(r.number(r.member(ro, p + "/rotate", "degrees"), p + "/rotate/degrees")));
    } else {
      const json& m = step["matrix"];
      if (!m.is_array() || (m.size() != 12 && m.size() != 16))
        r.fail(p + "/matrix", "expected 12 or 16 numbers (row-major)");
      for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 4; ++col)
          s.m[row][col] = float(r.number(m[row * 4 + col], p + "/matrix/" + std::to_string(row * 4 + col)));
      if (m.size() == 16) {
        const double w[4] = {r.number(m[12], p + "/matrix/12"), r.number(m[13], p + "/matrix/13"),
                             r.number(m[14], p + "/matrix/14"), r.number(m[15], p + "/matrix/15")};
        if (w[0] != 0 || w[1] != 0 || w[2] != 0 || w[3] != 1)
          r.fail(p + "/matrix", "the last row must be 0 0 0 1 (affine transforms only)");
      }
      if (!(std::fabs(s.determinant()) > 0)) r.fail(p + "/matrix", "the matrix is singular");
    }
    t = s * t;  // steps apply in the order listed
  }
  return t;
}

void readCamera(const Reader& r, const json& j, Scene& scene) {
  const std::string p = "/camera";
  r.object(j, p, {"position", "look_at", "up", "fov"});
  CameraDesc& c = scene.camera;
  c.position = r.vec3(r.member(j, p, "position"), p + "/position");
  c.lookAt = r.vec3(r.member(j, p, "look_at"), p + "/look_at");
  if (j.contains("up")) c.up = r.vec3(j["up"], p + "/up");
  if (j.contains("fov")) c.fovYDegrees = float(r.number(j["fov"], p + "/fov"));
  if (!(c.fovYDegrees > 0 && c.fovYDegrees < 180)) r.fail(p + "/fov", "the field of view must be in (0, 180) degrees");
  const Vec3 forward = c.lookAt - c.position;
  if (!(length(forward) > 0)) r.fail(p + "/look_at", "look_at equals position: the camera has no direction");
  if (!(length(c.up) > 0)) r.fail(p + "/up", "the up vector must not be zero");
  const Vec3 side = cross(normalize(forward), normalize(c.up));
  if (!(length(side) > 1e-6f)) r.fail(p + "/up", "the camera looks along its up vector");
}

void readFilm(const Reader& r, const json& j, Scene& scene) {
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

void readIntegrator(const Reader& r, const json& j, Scene& scene) {
  const std::string p = "/integrator";
  r.object(j, p, {"max_depth", "seed", "roulette_depth"});
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

std::map<std::string, uint32_t> readMaterials(const Reader& r, const json& j, Scene& scene) {
  const std::string p = "/materials";
  if (!j.is_object()) r.fail(p, "expected an object mapping names to materials");
  std::map<std::string, uint32_t> index;
  for (auto it = j.begin(); it != j.end(); ++it) {
    const std::string mp = p + "/" + it.key();
    const json& m = it.value();
    if (!m.is_object()) r.fail(mp, "expected an object");
    const std::string type = r.string(r.member(m, mp, "type"), mp + "/type");
    Material mat;
    mat.name = it.key();
    if (type == "diffuse") {
      r.object(m, mp, {"type", "albedo"});
      mat.albedo = r.color(r.member(m, mp, "albedo"), mp + "/albedo", true);
    } else if (type == "emissive") {
      r.object(m, mp, {"type", "radiance", "albedo", "two_sided"});
      mat.emission = r.color(r.member(m, mp, "radiance"), mp + "/radiance", false);
      if (m.contains("albedo")) mat.albedo = r.color(m["albedo"], mp + "/albedo", true);
      if (m.contains("two_sided")) mat.twoSided = r.boolean(m["two_sided"], mp + "/two_sided");
    } else {
      r.fail(mp + "/type", "unknown material type '" + type + "' (expected diffuse or emissive)");
    }
    index[it.key()] = uint32_t(scene.materials.size());
    scene.materials.push_back(mat);
  }
  return index;
}

uint32_t materialRef(const Reader& r, const json& shape, const std::string& p,
                     const std::map<std::string, uint32_t>& materials) {
  const std::string name = r.string(r.member(shape, p, "material"), p + "/material");
  auto it = materials.find(name);
  if (it == materials.end()) r.fail(p + "/material", "no material named '" + name + "'");
  return it->second;
}

void addPatch(Scene& scene, PatchPtr patch, uint32_t material) {
  scene.patches.push_back(std::move(patch));
  scene.patchMaterial.push_back(material);
}

std::array<Vec3, 4> readQuad(const Reader& r, const json& q, const std::string& p) {
  if (!q.is_array() || q.size() != 4) r.fail(p, "expected 4 corners [p00, p10, p01, p11]");
  return {r.vec3(q[0], p + "/0"), r.vec3(q[1], p + "/1"), r.vec3(q[2], p + "/2"), r.vec3(q[3], p + "/3")};
}

void readShapes(const Reader& r, const json& j, Scene& scene, const std::map<std::string, uint32_t>& materials,
                const std::filesystem::path& dir) {
  if (!j.is_array()) r.fail("/shapes", "expected an array of shapes");
  for (size_t s = 0; s < j.size(); ++s) {
    const std::string p = "/shapes/" + std::to_string(s);
    const json& shape = j[s];
    if (!shape.is_object()) r.fail(p, "expected an object");
    const std::string type = r.string(r.member(shape, p, "type"), p + "/type");
    const Transform xf = shape.contains("transform") ? readTransform(r, shape["transform"], p + "/transform") : Transform{};
    if (type == "bezier") {
      r.object(shape, p, {"type", "file", "patches", "material", "transform"});
      const uint32_t mat = materialRef(r, shape, p, materials);
      std::vector<std::array<Vec3, 16>> patches;
      if (shape.contains("file") == shape.contains("patches"))
        r.fail(p, "a bezier shape needs exactly one of 'file' and 'patches'");
      if (shape.contains("file")) {
        const std::string f = r.string(shape["file"], p + "/file");
        const std::filesystem::path fp = std::filesystem::path(f).is_absolute() ? std::filesystem::path(f) : dir / f;
        if (!std::filesystem::exists(fp)) r.fail(p + "/file", "cannot open patch file '" + fp.string() + "'");
        patches = loadBezierPatchFile(fp.string());
      } else {
        const json& ps = shape["patches"];
        if (!ps.is_array() || ps.empty()) r.fail(p + "/patches", "expected a non-empty array of patches");
        for (size_t k = 0; k < ps.size(); ++k) {
          const std::string pp = p + "/patches/" + std::to_string(k);
          if (!ps[k].is_array() || ps[k].size() != 16) r.fail(pp, "expected 16 control points (4x4, row by row)");
          std::array<Vec3, 16> cp;
          for (int c = 0; c < 16; ++c) cp[c] = r.vec3(ps[k][c], pp + "/" + std::to_string(c));
          patches.push_back(cp);
        }
      }
      for (auto& cp : patches) {
        for (auto& v : cp) v = xf.point(v);
        addPatch(scene, std::make_shared<BezierPatch>(cp), mat);
      }
    } else if (type == "bilinear") {
      r.object(shape, p, {"type", "quads", "material", "transform"});
      const uint32_t mat = materialRef(r, shape, p, materials);
      const json& qs = r.member(shape, p, "quads");
      if (!qs.is_array() || qs.empty()) r.fail(p + "/quads", "expected a non-empty array of quads");
      for (size_t k = 0; k < qs.size(); ++k) {
        auto q = readQuad(r, qs[k], p + "/quads/" + std::to_string(k));
        for (auto& v : q) v = xf.point(v);
        addPatch(scene, std::make_shared<BilinearPatch>(q[0], q[1], q[2], q[3]), mat);
      }
    } else {
      r.fail(p + "/type", "unknown shape type '" + type + "' (expected bezier or bilinear)");
    }
  }
}

void readLights(const Reader& r, const json& j, Scene& scene) {
  if (!j.is_array()) r.fail("/lights", "expected an array of lights");
  for (size_t l = 0; l < j.size(); ++l) {
    const std::string p = "/lights/" + std::to_string(l);
    const json& light = j[l];
    if (!light.is_object()) r.fail(p, "expected an object");
    const std::string type = r.string(r.member(light, p, "type"), p + "/type");
    if (type == "point") {
      r.object(light, p, {"type", "position", "intensity"});
      scene.pointLights.push_back({r.vec3(r.member(light, p, "position"), p + "/position"),
                                   r.color(r.member(light, p, "intensity"), p + "/intensity", false)});
    } else if (type == "rect") {
      r.object(light, p, {"type", "corner", "edge_u", "edge_v", "radiance", "two_sided"});
      const Vec3 c = r.vec3(r.member(light, p, "corner"), p + "/corner");
      const Vec3 eu = r.vec3(r.member(light, p, "edge_u"), p + "/edge_u");
      const Vec3 ev = r.vec3(r.member(light, p, "edge_v"), p + "/edge_v");
      if (!(length(cross(eu, ev)) > 0)) r.fail(p, "edge_u and edge_v span no area");
      Material m;
      m.name = "rect light " + std::to_string(l);
      m.emission = r.color(r.member(light, p, "radiance"), p + "/radiance", false);
      if (light.contains("two_sided")) m.twoSided = r.boolean(light["two_sided"], p + "/two_sided");
      scene.materials.push_back(m);
      addPatch(scene, std::make_shared<BilinearPatch>(c, c + eu, c + ev, c + eu + ev),
               uint32_t(scene.materials.size() - 1));
    } else {
      r.fail(p + "/type", "unknown light type '" + type + "' (expected point or rect)");
    }
  }
}

}  // namespace

Scene parseScene(const std::string& text, const std::string& path) {
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::parse_error& e) {
    // e.byte is 1-based: the offset just past where the parser stopped.
    size_t line = 1, col = 1;
    for (size_t i = 0; i + 1 < e.byte && i < text.size(); ++i) {
      if (text[i] == '\n') { ++line; col = 1; } else { ++col; }
    }
    std::string msg = e.what();
    const auto at = msg.find("syntax error");
    throw InputError(path, std::to_string(line) + ":" + std::to_string(col),
                     "JSON " + (at == std::string::npos ? msg : msg.substr(at)));
  }
  Reader r(path, text);
  r.object(doc, "", {"camera", "film", "integrator", "materials", "lights", "shapes"});
  Scene scene;
  scene.path = path;
  readCamera(r, r.member(doc, "", "camera"), scene);
  if (doc.contains("film")) readFilm(r, doc["film"], scene);
  if (doc.contains("integrator")) readIntegrator(r, doc["integrator"], scene);
  const auto materials = readMaterials(r, r.member(doc, "", "materials"), scene);
  const auto dir = std::filesystem::path(path).parent_path();
  readShapes(r, r.member(doc, "", "shapes"), scene, materials, dir);
  if (doc.contains("lights")) readLights(r, doc["lights"], scene);
  if (scene.patches.empty()) r.fail("/shapes", "the scene has no shapes");
  return scene;
}

Scene loadScene(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "", "cannot open scene file");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError(path, "", "cannot read scene file");
  return parseScene(ss.str(), path);
}

}  // namespace rayes
