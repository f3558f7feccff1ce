#include "core/plugin_module.h"
#include <cstdlib>
#include <filesystem>
#include <map>
#include <mutex>
#include <dlfcn.h>
#include "core/error.h"

namespace rayes {
namespace {

struct Loaded {
  void* handle = nullptr;
  std::string failure;  // why it could not be loaded (handle null)
};

std::mutex gMutex;
std::map<std::string, Loaded> gModules;  // by file name; entries never removed

Loaded load(const std::string& file) {
  std::filesystem::path dir;
  if (const char* named = std::getenv("RAYES_MODULE_DIR"); named && *named) {
    dir = named;
  } else {
    std::error_code ec;
    dir = std::filesystem::read_symlink("/proc/self/exe", ec).parent_path();
    if (ec) return {nullptr, "the program's folder is unknown (no /proc/self/exe) and RAYES_MODULE_DIR is not set"};
  }
  const std::filesystem::path place = dir / file;
  if (!std::filesystem::exists(place)) return {nullptr, place.string() + ": no such file"};
  // RTLD_LOCAL: the module's libraries stay out of the program's symbol lookups.
  if (void* handle = dlopen(place.c_str(), RTLD_NOW | RTLD_LOCAL)) return {handle, ""};
  const char* why = dlerror();
  return {nullptr, why ? std::string(why) : place.string()};
}

}  // namespace

void* moduleSymbol(const char* file, const char* symbol, const std::string& what) {
  std::unique_lock<std::mutex> lock(gMutex);
  auto it = gModules.find(file);
  if (it == gModules.end()) it = gModules.emplace(file, load(file)).first;
  const Loaded& m = it->second;
  lock.unlock();
  void* address = m.handle ? dlsym(m.handle, symbol) : nullptr;
  if (!address)
    throw InputError(file, "",
                     what + ", and its module cannot be loaded (" +
                         (m.handle ? std::string(file) + " has no " + symbol : m.failure) +
                         "); it is built with the program (scripts/build) and must sit beside it, or in the folder "
                         "RAYES_MODULE_DIR names");
  return address;
}

}  // namespace rayes
