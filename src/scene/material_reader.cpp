#include <filesystem>
#include "scene/scene_sections.h"
#include "scene/texture_reader.h"
#include "shading/plastic.h"

namespace rayes {
namespace {

// Complex indices of refraction at roughly 650 / 550 / 450 nm (R, G, B).
struct Metal { const char* name; Rgb eta, k; };
constexpr Metal kMetals[] = {
    {"gold", {0.143f, 0.374f, 1.442f}, {3.983f, 2.386f, 1.603f}},
    {"silver", {0.155f, 0.117f, 0.138f}, {4.828f, 3.122f, 2.147f}},
    {"copper", {0.200f, 0.924f, 1.102f}, {3.912f, 2.452f, 2.142f}},
    {"aluminium", {1.657f, 0.880f, 0.521f}, {9.224f, 6.270f, 4.837f}},
};

float roughness(const JsonReader& r, const json& m, const std::string& mp) {
  if (!m.contains("roughness")) return 0;
  const float a = float(r.number(m["roughness"], mp + "/roughness"));
  if (a < 0) r.fail(mp + "/roughness", "roughness must not be negative");
  if (a > 1) r.fail(mp + "/roughness", "roughness (the GGX alpha) must be at most 1");
  return a;
}

}  // namespace

MaterialIndex readMaterials(const JsonReader& r, const json& j, Scene& scene) {
  const std::string p = "/materials";
  if (!j.is_object()) r.fail(p, "expected an object mapping names to materials");
  const std::filesystem::path dir = std::filesystem::path(scene.path).parent_path();
  MaterialIndex index;
  for (auto it = j.begin(); it != j.end(); ++it) {
    const std::string mp = p + "/" + it.key();
    const json& m = it.value();
    if (!m.is_object()) r.fail(mp, "expected an object");
    const std::string type = r.string(r.member(m, mp, "type"), mp + "/type");
    Material mat;
    mat.name = it.key();
    auto color = [&](const char* key, bool reflectance) {
      return readColorParam(r, r.member(m, mp, key), mp + "/" + key, dir, reflectance, scene);
    };
    auto optColor = [&](const char* key, Rgb dflt, bool reflectance) {
      return m.contains(key) ? color(key, reflectance) : ColorParam(dflt);
    };
    auto ior = [&](float dflt) {
      if (!m.contains("ior")) return dflt;
      const float v = float(r.number(m["ior"], mp + "/ior"));
      if (!(v > 0)) r.fail(mp + "/ior", "the index of refraction must be positive");
      if (v > 100) r.fail(mp + "/ior", "an index of refraction above 100 is not a dielectric");
      return v;
    };
    // Keys every material may carry besides its own.
    auto keys = [&](std::initializer_list<const char*> own) {
      std::set<std::string> k(own.begin(), own.end());
      k.insert({"type", "emission", "two_sided"});
      r.objectKeys(m, mp, k);
    };
    if (type == "diffuse") {
      keys({"albedo"});
      mat.type = MaterialType::Diffuse;
      mat.albedo = color("albedo", true);
    } else if (type == "emissive") {
      keys({"radiance", "albedo"});
      mat.type = MaterialType::Diffuse;
      mat.emission = r.color(r.member(m, mp, "radiance"), mp + "/radiance", false);
      mat.albedo = optColor("albedo", {0, 0, 0}, true);
    } else if (type == "conductor") {
      keys({"metal", "eta", "k", "roughness"});
      mat.type = MaterialType::Conductor;
      mat.roughness = roughness(r, m, mp);
      const bool named = m.contains("metal");
      if (named == (m.contains("eta") || m.contains("k")))
        r.fail(mp, "give either 'metal' or both 'eta' and 'k'");
      if (named) {
        const std::string name = r.string(m["metal"], mp + "/metal");
        const Metal* found = nullptr;
        for (const Metal& x : kMetals)
          if (name == x.name) found = &x;
        if (!found) r.fail(mp + "/metal", "unknown metal '" + name + "' (expected gold, silver, copper or aluminium)");
        mat.eta = found->eta;
        mat.k = found->k;
      } else {
        mat.eta = r.color(r.member(m, mp, "eta"), mp + "/eta", false);
        mat.k = r.color(r.member(m, mp, "k"), mp + "/k", false);
        if (!(mat.eta.x > 0 && mat.eta.y > 0 && mat.eta.z > 0)) r.fail(mp + "/eta", "eta must be positive");
      }
    } else if (type == "dielectric") {
      keys({"ior", "roughness"});
      mat.type = MaterialType::Dielectric;
      const float e = ior(1.5f);
      mat.eta = {e, e, e};
      mat.roughness = roughness(r, m, mp);
    } else if (type == "plastic") {
      keys({"albedo", "ior"});
      mat.type = MaterialType::Plastic;
      mat.albedo = color("albedo", true);
      const float e = ior(1.5f);
      mat.eta = {e, e, e};
      mat.plasticFdrIn = Plastic::internalDiffuseReflectance(e);
    } else if (type == "phong") {
      keys({"diffuse", "specular", "exponent"});
      mat.type = MaterialType::Phong;
      mat.albedo = optColor("diffuse", {0, 0, 0}, true);
      mat.specular = color("specular", true);
      mat.exponent = float(r.number(r.member(m, mp, "exponent"), mp + "/exponent"));
      if (mat.exponent < 0 || mat.exponent > 1e6f) r.fail(mp + "/exponent", "the exponent must be in [0, 1e6]");
      const Rgb sum = mat.albedo.value + mat.specular.value;
      if (sum.x > 1 || sum.y > 1 || sum.z > 1) r.fail(mp, "diffuse + specular above 1 would create energy");
    } else if (type == "glossy") {
      keys({"specular", "sigma"});
      mat.type = MaterialType::Glossy;
      mat.specular = color("specular", true);
      mat.sigma = float(r.number(r.member(m, mp, "sigma"), mp + "/sigma"));
      if (mat.sigma < 0) r.fail(mp + "/sigma", "the lobe width must not be negative");
      if (mat.sigma > 1) r.fail(mp + "/sigma", "the lobe width must be at most 1 radian (valid for sigma << pi/4)");
    } else {
      r.fail(mp + "/type", "unknown material type '" + type +
                               "' (expected diffuse, emissive, conductor, dielectric, plastic, phong or glossy)");
    }
    if (m.contains("emission")) mat.emission = r.color(m["emission"], mp + "/emission", false);
    if (m.contains("two_sided")) mat.twoSided = r.boolean(m["two_sided"], mp + "/two_sided");
    index[it.key()] = uint32_t(scene.materials.size());
    scene.materials.push_back(mat);
  }
  return index;
}

}  // namespace rayes
