#include "scene/scene_sections.h"

namespace rayes {

MaterialIndex readMaterials(const JsonReader& r, const json& j, Scene& scene) {
  const std::string p = "/materials";
  if (!j.is_object()) r.fail(p, "expected an object mapping names to materials");
  MaterialIndex index;
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

}  // namespace rayes
