#include "shading/integrator.h"
#include "core/error.h"
#include "shading/light_tracer.h"
#include "shading/path_tracer.h"

namespace rayes {

const std::vector<std::string>& integratorMethodNames() {
  static const std::vector<std::string> names{"pt", "lt", "lbt"};
  return names;
}

IntegratorMethod integratorMethodFromName(const std::string& name, const std::string& where) {
  if (name == "pt") return IntegratorMethod::PathTracing;
  if (name == "lt") return IntegratorMethod::LightTracing;
  if (name == "lbt") return IntegratorMethod::LightBeams;
  throw InputError(where, "", "unknown method '" + name +
                   "' (use pt: path tracing, lt: light tracing, or lbt: path tracing with light beams for caustics)");
}

const char* integratorMethodName(IntegratorMethod method) {
  return method == IntegratorMethod::LightTracing ? "lt" : method == IntegratorMethod::LightBeams ? "lbt" : "pt";
}

std::unique_ptr<Integrator> makeIntegrator(IntegratorMethod method, const ShadingScene& scene) {
  if (method == IntegratorMethod::LightTracing) return std::make_unique<LightTracer>(scene);
  return std::make_unique<PathTracer>(scene);
}

}  // namespace rayes
