// What every fuzz target shares. A target feeds one input to one reader; bad input must end in
// InputError (which the target swallows) and nothing else: any other exception, a crash, a
// sanitizer report, a leak, a huge allocation or a hang is a finding (scripts/fuzz).
#pragma once
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace rayes::fuzz {

inline std::string asText(const uint8_t* data, size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

// Readers that only take a path (OpenImageIO and the .bpt reader read files) get the input
// through one file per process, rewritten for every input; `extension` picks the reader.
inline std::filesystem::path writeInputFile(const uint8_t* data, size_t size, const std::string& extension) {
  static const std::filesystem::path file = std::filesystem::temp_directory_path() /
      ("rayes-fuzz-" + std::to_string(getpid()) + extension);
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  return file;
}

}  // namespace rayes::fuzz
