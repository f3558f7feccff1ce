// The EXR texture loader on arbitrary bytes.
#include "core/error.h"
#include "fuzz/fuzz_input.h"
#include "scene/texture_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    rayes::readImageFile(rayes::fuzz::writeInputFile(data, size, ".exr"));
  } catch (const rayes::InputError&) {
  }
  return 0;
}
