#include <algorithm>
#include <cmath>
#include <optional>
#include <numbers>
#include "geometry/bilinear_patch.h"
#include "geometry/disk_patch.h"
#include "scene/scene_sections.h"
#include "scene/texture_reader.h"
#include "shading/sampling.h"

namespace rayes {
namespace {

float degrees(const JsonReader& r, const json& j, const std::string& ptr, float lo, float hi) {
  const float d = float(r.number(j, ptr));
  if (!(d >= lo && d <= hi)) r.fail(ptr, "must be in [" + std::to_string(int(lo)) + ", " + std::to_string(int(hi)) + "] degrees");
  return d * std::numbers::pi_v<float> / 180;
}

Vec3 unitVector(const JsonReader& r, const json& j, const std::string& ptr) {
  const Vec3 v = r.vec3(j, ptr);
  if (!(length(v) > 0)) r.fail(ptr, "must not be the zero vector");
  return normalize(v);
}

uint32_t emissiveMaterial(Scene& scene, const std::string& name, Rgb radiance, bool twoSided) {
  Material m;
  m.name = name;
  m.emission = radiance;
  m.twoSided = twoSided;
  scene.materials.push_back(m);
  return uint32_t(scene.materials.size() - 1);
}

// A one-sided area light at `center` emitting toward `normal` lights nothing of the scene when
// every corner of the shapes' box lies behind its plane (or on it): the usual cause is a rect
// light whose edges were given in the other order.
bool facesAwayFrom(const Box3& shapes, Vec3 center, Vec3 normal) {
  if (shapes.empty()) return false;
  const Vec3 e = shapes.extent();
  // Leaf boxes are grown by a few ulps of their coordinates (up to γ(8) + 2^-24 of their
  // magnitude: a bilinear patch's), which in the render frame is their distance from the camera.
  const float tolerance = 1e-6f * std::max({e.x, e.y, e.z, length(center - shapes.center()), shapes.magnitude()});
  for (int k = 0; k < 8; ++k) {
    const Vec3 corner{k & 1 ? shapes.hi.x : shapes.lo.x, k & 2 ? shapes.hi.y : shapes.lo.y, k & 4 ? shapes.hi.z : shapes.lo.z};
    if (dot(corner - center, normal) > tolerance) return false;
  }
  return true;
}

}  // namespace

void readLights(const JsonReader& r, const json& j, Scene& scene) {
  if (!j.is_array()) r.fail("/lights", "expected an array of lights");
  const std::filesystem::path dir = std::filesystem::path(scene.path).parent_path();
  // The box of the shapes (read before the lights; lights do not count), made when first needed.
  const size_t shapeLeaves = scene.leaves.size();
  std::optional<Box3> shapes;
  auto warnIfFacingAway = [&](const std::string& p, const char* type, Vec3 center, Vec3 normal, const char* hint) {
    if (!shapes) {
      shapes.emplace();
      for (size_t i = 0; i < shapeLeaves; ++i) shapes->extend(scene.leaves.bounds(i));
    }
    if (facesAwayFrom(*shapes, center, normal))
      scene.warnings.push_back(scene.path + ":" + r.place(p) + ": " + p + ": this " + type +
                               " light emits away from every shape of the scene (their whole bounding box lies "
                               "behind it), so it lights nothing; " + hint);
  };
  for (size_t l = 0; l < j.size(); ++l) {
    const std::string p = "/lights/" + std::to_string(l);
    const json& light = j[l];
    if (!light.is_object()) r.fail(p, "expected an object");
    const std::string type = r.string(r.member(light, p, "type"), p + "/type");
    auto twoSided = [&] { return light.contains("two_sided") && r.boolean(light["two_sided"], p + "/two_sided"); };
    if (type == "point") {
      r.object(light, p, {"type", "position", "intensity"});
      scene.pointLights.push_back({scene.frame.point(r.vec3d(r.member(light, p, "position"), p + "/position")),
                                   r.color(r.member(light, p, "intensity"), p + "/intensity", false)});
    } else if (type == "spot") {
      r.object(light, p, {"type", "position", "direction", "look_at", "intensity", "cone_angle", "falloff_start"});
      SpotLight s;
      const Vec3d position = r.vec3d(r.member(light, p, "position"), p + "/position");
      s.position = scene.frame.point(position);
      if (light.contains("direction") == light.contains("look_at")) r.fail(p, "give exactly one of 'direction' and 'look_at'");
      if (light.contains("direction")) {
        s.direction = unitVector(r, light["direction"], p + "/direction");
      } else {
        const Vec3d d = r.vec3d(light["look_at"], p + "/look_at") - position;
        if (!(length(d) > 0)) r.fail(p + "/look_at", "look_at equals position");
        s.direction = normalize(d.toFloat());
      }
      s.intensity = r.color(r.member(light, p, "intensity"), p + "/intensity", false);
      const float outer = degrees(r, r.member(light, p, "cone_angle"), p + "/cone_angle", 0, 180);
      if (!(outer > 0)) r.fail(p + "/cone_angle", "the cone angle must be positive");
      const float inner = light.contains("falloff_start")
                              ? degrees(r, light["falloff_start"], p + "/falloff_start", 0, 180) : outer;
      if (inner > outer) r.fail(p + "/falloff_start", "the falloff must start inside the cone");
      s.cosFalloffEnd = std::cos(outer);
      s.cosFalloffStart = std::cos(inner);
      if (s.cosFalloffStart <= s.cosFalloffEnd) s.cosFalloffStart = std::nextafter(s.cosFalloffEnd, 2.0f);
      scene.moreLights.spots.push_back(s);
    } else if (type == "rect") {
      r.object(light, p, {"type", "corner", "edge_u", "edge_v", "radiance", "two_sided"});
      const Vec3d cd = r.vec3d(r.member(light, p, "corner"), p + "/corner");
      const Vec3d eud = r.vec3d(r.member(light, p, "edge_u"), p + "/edge_u");
      const Vec3d evd = r.vec3d(r.member(light, p, "edge_v"), p + "/edge_v");
      const Vec3 c = scene.frame.point(cd), eu = eud.toFloat(), ev = evd.toFloat();
      if (!(length(cross(eu, ev)) > 0)) r.fail(p, "edge_u and edge_v span no area");
      const Rgb le = r.color(r.member(light, p, "radiance"), p + "/radiance", false);
      const bool both = twoSided();
      const uint32_t m = emissiveMaterial(scene, "rect light " + std::to_string(l), le, both);
      if (!both)
        warnIfFacingAway(p, "rect", c + (eu + ev) * 0.5f, normalize(cross(eu, ev)),
                         "it emits toward edge_u x edge_v: swap edge_u and edge_v, or set \"two_sided\": true");
      // The corners summed in double, then moved into the render frame and rounded once.
      addPatch(r, p, scene,
               std::make_shared<BilinearPatch>(c, scene.frame.point(cd + eud), scene.frame.point(cd + evd),
                                               scene.frame.point(cd + eud + evd)),
               m);
    } else if (type == "disk") {
      r.object(light, p, {"type", "center", "normal", "radius", "radiance", "two_sided"});
      const Vec3 c = scene.frame.point(r.vec3d(r.member(light, p, "center"), p + "/center"));
      const Vec3 n = unitVector(r, r.member(light, p, "normal"), p + "/normal");
      const float radius = float(r.number(r.member(light, p, "radius"), p + "/radius"));
      if (!(radius > 0)) r.fail(p + "/radius", "the radius must be positive");
      const Rgb le = r.color(r.member(light, p, "radiance"), p + "/radiance", false);
      const bool both = twoSided();
      const uint32_t m = emissiveMaterial(scene, "disk light " + std::to_string(l), le, both);
      if (!both) warnIfFacingAway(p, "disk", c, n, "it emits toward its normal: negate it, or set \"two_sided\": true");
      addPatch(r, p, scene, std::make_shared<DiskPatch>(c, n, radius), m);
    } else if (type == "distant") {
      r.object(light, p, {"type", "direction", "irradiance", "angular_radius"});
      DistantLight d;
      d.direction = unitVector(r, r.member(light, p, "direction"), p + "/direction");
      d.irradiance = r.color(r.member(light, p, "irradiance"), p + "/irradiance", false);
      if (light.contains("angular_radius")) {
        const double a = degrees(r, light["angular_radius"], p + "/angular_radius", 0, 90);
        const double s = std::sin(0.5 * a);
        d.oneMinusCos = 2 * s * s;  // 1 - cos a without cancellation (the sun's is 1e-5)
      }
      scene.moreLights.distants.push_back(d);
    } else if (type == "environment") {
      r.object(light, p, {"type", "radiance", "file", "scale"});
      if (light.contains("radiance") == light.contains("file")) r.fail(p, "give exactly one of 'radiance' and 'file'");
      if (scene.moreLights.environment) r.fail(p, "a scene has at most one environment");
      if (light.contains("radiance")) {
        if (light.contains("scale")) r.fail(p + "/scale", "'scale' goes with 'file'");
        scene.moreLights.environment =
            std::make_shared<Environment>(r.color(light["radiance"], p + "/radiance", false));
      } else {
        const std::string f = r.string(light["file"], p + "/file");
        const std::filesystem::path fp = std::filesystem::path(f).is_absolute() ? std::filesystem::path(f) : dir / f;
        const Rgb scale = light.contains("scale") ? r.color(light["scale"], p + "/scale", false) : Rgb{1, 1, 1};
        try {
          // Opening reads the header (a plain image is converted first); the sampling
          // distribution reads a coarse MIP level.
          scene.moreLights.environment = std::make_shared<Environment>(scene.textureCache().open(fp), scale);
        } catch (const ResourceError&) {
          throw;
        } catch (const InputError& e) {
          r.fail(p + "/file", e.message());
        }
      }
    } else {
      r.fail(p + "/type", "unknown light type '" + type +
                              "' (expected point, spot, rect, disk, distant or environment)");
    }
  }
}

}  // namespace rayes
