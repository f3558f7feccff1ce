// The scene loader on arbitrary text. The scene is placed in scenes/, so the seeds' relative
// files (teapot.bpt, creature.obj, sky-small.exr) resolve and the fuzzer reaches the shape,
// modifier, material, texture and light readers behind them.
#include "core/error.h"
#include "fuzz/fuzz_input.h"
#include "scene/scene_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    rayes::parseScene(rayes::fuzz::asText(data, size), RAYES_SOURCE_DIR "/scenes/fuzz-input.json");
  } catch (const rayes::InputError&) {
  }
  return 0;
}
