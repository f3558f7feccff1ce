// Reads a whole input file into memory. A missing or unreadable file is bad input: an
// InputError naming the file (what = "scene file", "OBJ file", ...).
#pragma once
#include <fstream>
#include <sstream>
#include <string>
#include "core/error.h"

namespace rayes {

inline std::string readTextFile(const std::string& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "", "cannot open " + what);
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError(path, "", "cannot read " + what);
  return ss.str();
}

}  // namespace rayes
