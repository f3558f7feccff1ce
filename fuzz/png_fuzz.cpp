// An image file as the scene's textures read it, on arbitrary bytes: OpenImageIO's PNG reader
// and the conversion to a tiled MIP-mapped file (texture/oiio/texture_file.h), into a folder of this
// process that is emptied after every input.
#include <unistd.h>
#include "core/error.h"
#include "fuzz/fuzz_input.h"
#include "texture/oiio/texture_file.h"

// Under libFuzzer's -malloc_limit_mb=2048 an allocation beyond 2 GB is a finding: a header that
// claims more pixels than that is refused by the conversion's memory check instead.
constexpr uint64_t kConversionMemory = uint64_t(1) << 30;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("rayes-fuzz-textures-" + std::to_string(getpid()));
  try {
    rayes::prepareTextureFile(rayes::fuzz::writeInputFile(data, size, ".png"), dir, {}, kConversionMemory);
  } catch (const rayes::InputError&) {  // a ResourceError too
  }
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
  return 0;
}
