#include "app/methods.h"
#include <algorithm>
#include "core/error.h"
#include "shading/light_tracer.h"
#include "shading/material.h"
#include "shading/path_tracer.h"

namespace rayes {
namespace {

enum class Method { PathTracing, LightTracing, PhotonMapping, ProgressivePhotonMapping, LightBeams };

Method methodOf(const std::string& name) {
  const auto& names = methodNames();
  const auto at = std::find(names.begin(), names.end(), name);
  if (at == names.end())
    throw InputError("--method", "", "unknown method '" + name + "' (use pt: path tracing, lt: light tracing, pm: photon "
                                     "mapping, ppm: progressive photon mapping, lbt: light beams)");
  return Method(at - names.begin());
}

// Light beams: the caustic scatterer leaves' surfaces (their patches live until the beams are
// seeded) and the lights that send beams.
std::unique_ptr<Integrator> makeBeamIntegrator(const MethodOptions& options, const Scene& scene, const RenderData& data) {
  const ShadingScene& shading = data.shading;
  std::vector<ScattererSurface> scatterers;
  for (size_t l = 0; l < data.top.leafBoxes().size(); ++l)
    if (isCausticScatterer(shading.materials[shading.materialOf(uint32_t(l))]) && !data.top.leafBoxes()[l].empty()) {
      PatchPtr patch = scene.leaves.patch(l);
      scatterers.push_back({uint32_t(l), [patch](float u, float v) { return patch->evaluate(u, v).p; }});
    }
  BeamLights lights{scene.pointLights, scene.moreLights.spots, scene.moreLights.distants,
                    options.beams.areaSamples > 0 ? patchLightsOf(scene) : std::vector<PatchLight>{},
                    options.beams.areaSamples};
  return std::make_unique<BeamIntegrator>(shading, data.top, data.top.leafBoxes(), std::move(scatterers), std::move(lights),
                                          options.beams, options.causticPaths, options.laterGatherProbability);
}

}  // namespace

const std::vector<std::string>& methodNames() {
  static const std::vector<std::string> names{"pt", "lt", "pm", "ppm", "lbt"};
  return names;
}

size_t methodBudgetBytes(const MethodOptions& options) {
  return methodOf(options.name) == Method::LightBeams ? options.beams.memoryBytes : 0;
}

void checkMethodOptions(const MethodOptions& options) {
  const Method method = methodOf(options.name);
  const bool causticMethod = method == Method::LightBeams || method == Method::PhotonMapping ||
                             method == Method::ProgressivePhotonMapping;
  if (causticMethod && options.causticPaths == CausticPaths::Without)
    throw InputError("--caustic-paths", "", "lbt, pm and ppm take all or only: without their caustic estimate they "
                                            "are pt --caustic-paths without");
}

std::unique_ptr<Integrator> makeMethod(const MethodOptions& options, const Scene& scene, const RenderData& data) {
  checkMethodOptions(options);
  const Method method = methodOf(options.name);
  // Only the path tracer carries media so far (docs/design.md, "Volumes").
  if (!scene.media.empty() && method != Method::PathTracing)
    throw InputError("--method", "", "--method " + options.name + " does not render volumes yet; the scene " +
                                         scene.path + " has " + std::to_string(scene.media.size()) +
                                         " volume shape(s): use --method pt");
  switch (method) {
    case Method::PathTracing:
      return std::make_unique<PathTracer>(data.shading, PathTracer::Options{.causticPaths = options.causticPaths});
    case Method::LightTracing:
      return std::make_unique<LightTracer>(data.shading, options.causticPaths);
    case Method::PhotonMapping:
    case Method::ProgressivePhotonMapping: {
      PhotonOptions photons = options.photons;
      photons.progressive = method == Method::ProgressivePhotonMapping;
      photons.causticPaths = options.causticPaths;
      photons.laterGatherProbability = options.laterGatherProbability;
      return makePhotonMapper(data.shading, photons);
    }
    case Method::LightBeams:
      return makeBeamIntegrator(options, scene, data);
  }
  return nullptr;
}

}  // namespace rayes
