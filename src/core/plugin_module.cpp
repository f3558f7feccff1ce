#include "core/plugin_module.h"
#include <cstdlib>
#include <filesystem>
#include <map>
#include <mutex>
#include <vector>
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
  std::vector<std::filesystem::path> places;
  if (const char* dir = std::getenv("RAYES_MODULE_DIR"); dir && *dir) {
    places.push_back(std::filesystem::path(dir) / file);
  } else {
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) places.push_back(exe.parent_path() / file);
  }
  Loaded out;
  for (const auto& place : places) {
    if (!std::filesystem::exists(place)) {
      out.failure += (out.failure.empty() ? "" : "; ") + place.string() + ": no such file";
      continue;
    }
    // RTLD_LOCAL: the module's libraries stay out of the program's symbol lookups.
    if ((out.handle = dlopen(place.c_str(), RTLD_NOW | RTLD_LOCAL))) return out;
    const char* why = dlerror();
    out.failure += (out.failure.empty() ? "" : "; ") + (why ? std::string(why) : place.string());
  }
  if (places.empty()) out.failure = "the program's folder is unknown (no /proc/self/exe) and RAYES_MODULE_DIR is not set";
  return out;
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

bool moduleLoaded(const char* file) {
  std::lock_guard<std::mutex> lock(gMutex);
  const auto it = gModules.find(file);
  return it != gModules.end() && it->second.handle;
}

}  // namespace rayes
