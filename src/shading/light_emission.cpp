// LightSampler::sampleEmission: the first ray of a light path (light tracing). Densities are
// the product of the pick probability (by power, the same choice next-event estimation makes),
// the position's and the direction's; the weight is what the path carries out of the light.
#include <cmath>
#include <numbers>
#include "shading/light.h"
#include "shading/sampling.h"

namespace rayes {
namespace {
constexpr float kPiF = std::numbers::pi_v<float>;

}  // namespace

bool LightSampler::sampleEmission(float u0, float u1, float u2, float u3, float u4, EmissionSample& out) const {
  if (cdf_.empty()) return false;
  const size_t k = pickIndex(u0);
  const float pk = pick(k);
  if (!(pk > 0)) return false;
  out = EmissionSample{};
  if (k < patch0_) {  // point or spot: a delta position, directions in a cone
    const bool spot = k >= spot0_;
    if (!spot) {
      out.org = points_[k].position;
      out.dir = sampleUniformCone({0, 0, 1}, 2.0, u3, u4);  // the whole sphere
      out.weight = points_[k].intensity * (4 * kPiF / pk);
      return true;
    }
    const SpotLight& l = more_.spots[k - spot0_];
    const double oneMinusCos = 1.0 - double(l.cosFalloffEnd);
    if (!(oneMinusCos > 0)) return false;
    out.org = l.position;
    out.dir = sampleUniformCone(l.direction, oneMinusCos, u3, u4);
    out.weight = l.intensity * (l.falloff(dot(out.dir, l.direction)) * float(2.0 * std::numbers::pi * oneMinusCos) / pk);
    return true;
  }
  if (k < distant0_) {  // emissive patch: uniform in (u, v), cosine-weighted about the normal
    const PatchLight& l = patches_[k - patch0_];
    Vec3 p, n;
    l.evaluate(u1, u2, p, n);
    const float jacobian = length(n);
    if (!(jacobian > 0) || !std::isfinite(jacobian)) return false;
    Vec3 nrm = n * (1.0f / jacobian);
    float sides = 1;
    if (l.twoSided) {  // either side with probability 1/2: u3 is reused, rescaled
      sides = 2;
      if (u3 < 0.5f) { u3 = 2 * u3; } else { u3 = std::min(2 * u3 - 1, 0.99999994f); nrm = -nrm; }
    }
    out.org = p;
    out.dir = normalize(toWorld(sampleCosineHemisphere(u3, u4), nrm));
    // Le cos / (pk / J · cos / π) per side chosen with probability 1 / sides.
    out.weight = l.radiance * (kPiF * jacobian * sides / pk);
    out.onSurface = true;
    out.normal = n * (1.0f / jacobian);
    out.radiance = l.radiance;
    out.twoSided = l.twoSided;
    out.pdfArea = pk / jacobian;
    out.leaf = l.leaf;
    return isFinite(out.weight) && isFinite(out.dir);
  }
  // At infinity: a direction w toward the light, then an origin uniform on the disk of the
  // scene's radius centred on the scene, pushed out along w, so every ray crossing the scene
  // can be produced (position density 1 / (π R²)).
  Vec3 w;
  Rgb le;
  float pdfDir = 0;
  if (k < env_) {
    const DistantLight& l = more_.distants[k - distant0_];
    if (!(l.oneMinusCos > 0)) {  // a delta direction: irradiance over the disk
      w = l.direction;
      le = l.irradiance;
      pdfDir = 1;
    } else {
      w = sampleUniformCone(l.direction, l.oneMinusCos, u3, u4);
      le = l.radiance();
      pdfDir = float(1.0 / (2.0 * std::numbers::pi * l.oneMinusCos));
    }
  } else {
    if (!more_.environment->sample(u3, u4, w, pdfDir)) return false;
    le = more_.environment->eval(w);
  }
  float dx, dy;
  concentricDisk(u1, u2, dx, dy);
  Vec3 t, b;
  orthonormalBasis(w, t, b);
  out.org = center_ + (w + t * dx + b * dy) * radius_;
  out.dir = -w;
  out.weight = le * (kPiF * radius_ * radius_ / (pk * pdfDir));
  return pdfDir > 0 && isFinite(out.weight) && isFinite(out.org);
}

}  // namespace rayes
