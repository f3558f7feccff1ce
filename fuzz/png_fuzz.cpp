// An image file as the scene's textures read it, on arbitrary bytes: OpenImageIO's PNG reader
// and the conversion to a tiled MIP-mapped file (texture/texture_file.h), into a folder of this
// process that is emptied after every input.
#include <unistd.h>
#include "core/error.h"
#include "fuzz/fuzz_input.h"
#include "texture/texture_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("rayes-fuzz-textures-" + std::to_string(getpid()));
  try {
    rayes::prepareTextureFile(rayes::fuzz::writeInputFile(data, size, ".png"), dir, {});
  } catch (const rayes::InputError&) {
  }
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
  return 0;
}
