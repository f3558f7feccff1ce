#include "scene/scene_sections.h"
#include "dicing/bilinear_patch.h"

namespace rayes {

void readLights(const JsonReader& r, const json& j, Scene& scene) {
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

}  // namespace rayes
