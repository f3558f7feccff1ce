#include "scene/vdb_grid.h"
#include "core/plugin_module.h"

namespace rayes {

VdbGridRead readVdbGrid(const std::filesystem::path& file, const std::string& name) {
  const auto fn = reinterpret_cast<ReadVdbGridFn>(
      moduleSymbol(kVdbModuleName, kReadVdbGridSymbol, "the scene has a volume (OpenVDB)"));
  VdbGridRead out;
  const std::string path = file.string();
  fn(&path, &name, &out);
  return out;
}

}  // namespace rayes
