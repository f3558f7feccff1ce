// The BSDF at a shading point: one of the models of src/shading, chosen by the material and
// filled with its parameters (textures already evaluated). A closed set, so a std::variant:
// no virtual calls, no allocation per hit. Everything is in the local frame (bsdf_common.h);
// ShadingFrame maps to and from world space.
#pragma once
#include <variant>
#include "shading/conductor.h"
#include "shading/dielectric.h"
#include "shading/gaussian_lobe.h"
#include "shading/lambert.h"
#include "shading/phong.h"
#include "shading/plastic.h"

namespace rayes {

class Bsdf {
 public:
  using Model = std::variant<Lambert, Conductor, Dielectric, Plastic, Phong, GaussianLobe>;
  Bsdf() : m_(Lambert{}) {}
  template <class M> Bsdf(M m) : m_(std::move(m)) {}

  Rgb eval(Vec3 wo, Vec3 wi) const { return std::visit([&](const auto& b) { return b.eval(wo, wi); }, m_); }
  float pdf(Vec3 wo, Vec3 wi) const { return std::visit([&](const auto& b) { return b.pdf(wo, wi); }, m_); }
  bool sample(Vec3 wo, float u1, float u2, float uc, BsdfSample& s) const {
    return std::visit([&](const auto& b) { return b.sample(wo, u1, u2, uc, s); }, m_);
  }
  // The adjoint, for paths traced from the lights (shading/light_path.h): light arriving along
  // `in` (toward where it came from) leaves along s.wi with weight f(s.wi, in) |cos θ(s.wi)| /
  // pdf. For the reciprocal models (f(a, b) = f(b, a), refraction's η² in etaRel as for
  // sample) that is sample() with the slots swapped; the glossy lobe is not reciprocal and
  // samples its own (GaussianLobe::sampleAdjoint).
  bool sampleAdjoint(Vec3 in, float u1, float u2, float uc, BsdfSample& s) const {
    return std::visit(
        [&](const auto& b) {
          if constexpr (requires { b.sampleAdjoint(in, u1, u2, uc, s); }) return b.sampleAdjoint(in, u1, u2, uc, s);
          else return b.sample(in, u1, u2, uc, s);
        },
        m_);
  }
  // A colour for the albedo AOV (the model's characteristic reflectance).
  Rgb reflectance() const { return std::visit([](const auto& b) { return b.reflectance(); }, m_); }
  // Only delta lobes: next-event estimation cannot help.
  bool isDelta() const { return std::visit([](const auto& b) { return b.isDelta(); }, m_); }
  // Scatters into both hemispheres: the frame must keep +z = outside.
  bool transmits() const { return std::visit([](const auto& b) { return b.transmits(); }, m_); }
  const Model& model() const { return m_; }

 private:
  Model m_;
};

// An orthonormal frame about a unit normal.
struct ShadingFrame {
  Vec3 t, b, n;
  explicit ShadingFrame(Vec3 normal) : n(normal) { orthonormalBasis(n, t, b); }
  Vec3 toLocal(Vec3 w) const { return {dot(w, t), dot(w, b), dot(w, n)}; }
  Vec3 toWorld(Vec3 w) const { return t * w.x + b * w.y + n * w.z; }
};

}  // namespace rayes
