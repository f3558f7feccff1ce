// Opening and reading input files: the one check every input file of the program goes through
// (scene, OBJ, .bpt, textures, height maps, reference images). A missing, unreadable or directory
// path is bad input: an InputError naming the file (what = "scene file", "OBJ file", ...) with the
// system's reason. So is anything but a regular file (a FIFO, a device, a socket): opening a FIFO
// blocks until someone writes to it and /dev/zero never ends, so inputs must be regular files,
// as outputs are; this is checked before the file is opened.
#pragma once
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include "core/error.h"

namespace rayes {

// Throws unless `path` is a file that can be opened for reading; returns its size in bytes
// (so that counts claimed by a header can be checked against it before allocating).
inline uint64_t checkInputFile(const std::string& path, const std::string& what) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (std::filesystem::is_directory(status)) throw InputError(path, "", what + " is a directory");
  if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status))
    throw InputError(path, "", what + " is not a regular file (a FIFO, a device or a socket): inputs must be regular files");
  std::ifstream probe(path, std::ios::binary);
  const int err = errno;
  if (!probe) throw InputError(path, "", "cannot open " + what + ": " + std::strerror(err));
  const auto size = std::filesystem::file_size(path, ec);
  return ec ? 0 : uint64_t(size);
}

inline std::string readTextFile(const std::string& path, const std::string& what) {
  checkInputFile(path, what);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "", "cannot open " + what);
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError(path, "", "cannot read " + what);
  return ss.str();
}

}  // namespace rayes
