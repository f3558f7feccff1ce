#include "shading/integrator.h"
#include "core/error.h"

namespace rayes {

CausticPaths causticPathsFromName(const std::string& name, const std::string& where) {
  if (name == "all") return CausticPaths::All;
  if (name == "without") return CausticPaths::Without;
  if (name == "only") return CausticPaths::Only;
  throw InputError(where, "", "unknown choice '" + name + "' (use all, without or only)");
}

const char* causticPathsName(CausticPaths which) {
  return which == CausticPaths::Without ? "without" : which == CausticPaths::Only ? "only" : "all";
}

}  // namespace rayes
