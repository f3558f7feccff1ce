// The .bpt (Bézier patch) reader on arbitrary bytes.
#include "core/error.h"
#include "fuzz/fuzz_input.h"
#include "geometry/bezier_patch.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    rayes::loadBezierPatchFile(rayes::fuzz::writeInputFile(data, size, ".bpt").string());
  } catch (const rayes::InputError&) {
  }
  return 0;
}
