// Materials are data: a model name and its parameters, each colour optionally a texture of
// the hit, read at a TextureQuery (shading/texture_query.h). bsdfAt() turns one into a Bsdf at a hit. Any material may also emit
// (emission radiance, leaving the side the patch normal dP/du x dP/dv points to, or both
// sides when twoSided). Parameter meanings and units: docs/scene-format.md, "materials".
#pragma once
#include <memory>
#include <string>
#include "core/vec.h"
#include "shading/bsdf.h"
#include "shading/texture.h"

namespace rayes {

// A colour parameter: value, times the texture when there is one.
struct ColorParam {
  Rgb value{0, 0, 0};
  std::shared_ptr<const Texture> texture;
  ColorParam() = default;
  ColorParam(Rgb v) : value(v) {}
  Rgb at(const TextureQuery& q) const { return texture ? value * texture->eval(q) : value; }
  Rgb at(float u, float v) const { return at(TextureQuery::at(u, v)); }
};

enum class MaterialType : uint8_t { Diffuse, Conductor, Dielectric, Plastic, Phong, Glossy };

struct Material {
  std::string name;
  MaterialType type = MaterialType::Diffuse;
  ColorParam albedo;         // diffuse: reflectance; plastic: base; phong: kd
  ColorParam specular;       // phong: ks; glossy: ρs
  Rgb eta{1.5f, 1.5f, 1.5f};  // conductor: real part per channel; dielectric, plastic: eta.x
  Rgb k{0, 0, 0};            // conductor: imaginary part
  float roughness = 0;       // GGX alpha (conductor, dielectric)
  float exponent = 20;       // phong
  float sigma = 0.1f;        // glossy lobe width, radians
  float plasticFdrIn = 0;    // precomputed by Plastic::internalDiffuseReflectance(eta.x)
  Rgb emission{0, 0, 0};     // radiance, W / (m^2 sr) per channel
  bool twoSided = false;
  bool emits() const { return emission.x > 0 || emission.y > 0 || emission.z > 0; }

  Bsdf bsdfAt(const TextureQuery& q) const {
    switch (type) {
      case MaterialType::Diffuse: return Lambert{albedo.at(q)};
      case MaterialType::Conductor: return Conductor{eta, k, roughness};
      case MaterialType::Dielectric: return Dielectric{eta.x, roughness};
      case MaterialType::Plastic: return Plastic{albedo.at(q), eta.x, plasticFdrIn};
      case MaterialType::Phong: return Phong{albedo.at(q), specular.at(q), exponent};
      case MaterialType::Glossy: return GaussianLobe{specular.at(q), sigma};
    }
    return Lambert{};
  }
  Bsdf bsdfAt(float u, float v) const { return bsdfAt(TextureQuery::at(u, v)); }
  // Whether any parameter reads a texture (a hit on it needs a TextureQuery worth the name).
  bool textured() const { return albedo.texture || specular.texture; }
  // A black diffuse material reflects nothing: no BSDF work at all.
  bool reflectsNothing() const {
    return type == MaterialType::Diffuse && !albedo.texture && isBlack(albedo.value);
  }
};

// The surfaces that carry caustics (docs/design.md, "Caustic paths"): smooth mirrors and glass
// (delta lobes) and the glossy Gaussian lobe, whose narrow lobes path tracing from the camera
// cannot aim at a small light. Beams and photons travel light -> (caustic scatterer)+ -> the
// first other surface; `--method lbt|pm|ppm` estimate exactly those paths and the path tracer
// excludes them (--caustic-paths without: CausticPaths in integrator.h). Every other reflecting material
// (diffuse, plastic, Phong, rough GGX) is a "diffuse" vertex: where caustics are gathered.
// Delta-ness is the BSDF's own test (smooth GGX widths, index-matched glass), so the two never
// disagree; neither model reads a texture, so this costs no texture lookup per vertex.
inline bool isCausticScatterer(const Material& m) {
  switch (m.type) {
    case MaterialType::Glossy: return true;
    case MaterialType::Conductor: return Conductor{m.eta, m.k, m.roughness}.isDelta();
    case MaterialType::Dielectric: return Dielectric{m.eta.x, m.roughness}.isDelta();
    default: return false;
  }
}

}  // namespace rayes
