#include "shading/integrator.h"
#include "core/error.h"
#include "shading/light_tracer.h"
#include "shading/path_tracer.h"

namespace rayes {

const std::vector<std::string>& integratorMethodNames() {
  static const std::vector<std::string> names{"pt", "lt", "pm", "ppm", "lbt"};
  return names;
}

IntegratorMethod integratorMethodFromName(const std::string& name, const std::string& where) {
  const auto& names = integratorMethodNames();
  for (size_t i = 0; i < names.size(); ++i)
    if (name == names[i]) return IntegratorMethod(i);
  throw InputError(where, "", "unknown method '" + name + "' (use pt: path tracing, lt: light tracing, pm: photon "
                              "mapping, ppm: progressive photon mapping, lbt: light beams)");
}

const char* integratorMethodName(IntegratorMethod method) {
  return integratorMethodNames()[size_t(method)].c_str();
}

CausticPaths causticPathsFromName(const std::string& name, const std::string& where) {
  if (name == "all") return CausticPaths::All;
  if (name == "without") return CausticPaths::Without;
  if (name == "only") return CausticPaths::Only;
  throw InputError(where, "", "unknown choice '" + name + "' (use all, without or only)");
}

const char* causticPathsName(CausticPaths which) {
  return which == CausticPaths::Without ? "without" : which == CausticPaths::Only ? "only" : "all";
}

std::unique_ptr<Integrator> makeIntegrator(IntegratorMethod method, const ShadingScene& scene,
                                           const IntegratorOptions& options) {
  if (method == IntegratorMethod::LightTracing) return std::make_unique<LightTracer>(scene, options.causticPaths);
  // lbt's path tracer, until beams are built (and for good when none are): its bytes per path
  // hold the gathers the beams will post.
  return std::make_unique<PathTracer>(
      scene, PathTracer::Options{.causticPaths = options.causticPaths,
                                  .gathersAsLeafQueries = method == IntegratorMethod::LightBeams});
}

}  // namespace rayes
