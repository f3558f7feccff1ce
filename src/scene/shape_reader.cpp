#include "scene/scene_sections.h"
#include <array>
#include "core/transform.h"
#include "dicing/bezier_patch.h"
#include "dicing/bilinear_patch.h"

namespace rayes {

namespace {

Transform readTransform(const JsonReader& r, const json& j, const std::string& ptr) {
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

}  // namespace

uint32_t materialRef(const JsonReader& r, const json& shape, const std::string& p,
                     const MaterialIndex& materials) {
  const std::string name = r.string(r.member(shape, p, "material"), p + "/material");
  auto it = materials.find(name);
  if (it == materials.end()) r.fail(p + "/material", "no material named '" + name + "'");
  return it->second;
}

void addPatch(Scene& scene, PatchPtr patch, uint32_t material) {
  scene.patches.push_back(std::move(patch));
  scene.patchMaterial.push_back(material);
}

namespace {

std::array<Vec3, 4> readQuad(const JsonReader& r, const json& q, const std::string& p) {
  if (!q.is_array() || q.size() != 4) r.fail(p, "expected 4 corners [p00, p10, p01, p11]");
  return {r.vec3(q[0], p + "/0"), r.vec3(q[1], p + "/1"), r.vec3(q[2], p + "/2"), r.vec3(q[3], p + "/3")};
}

}  // namespace

void readShapes(const JsonReader& r, const json& j, Scene& scene, const MaterialIndex& materials,
                const std::filesystem::path& sceneDir) {
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
        const std::filesystem::path fp = std::filesystem::path(f).is_absolute() ? std::filesystem::path(f) : sceneDir / f;
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

}  // namespace rayes
