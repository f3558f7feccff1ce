// The OBJ reader on arbitrary text, and what the subdiv shape reader does next with what it
// accepts: the OpenSubdiv topology (whose complaints are SubdivInputError) and the patches.
#include "core/error.h"
#include "fuzz/fuzz_input.h"
#include "scene/obj_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace rayes;
  try {
    ObjMesh obj = parseObj(fuzz::asText(data, size), "fuzz-input.obj");
    for (SubdivScheme scheme : {SubdivScheme::CatmullClark, SubdivScheme::Loop}) {
      obj.mesh.scheme = scheme;
      try {
        auto topology = buildSubdivTopology(obj.mesh);
        SubdivMesh::build(topology, obj.mesh.positions)->patches();
      } catch (const SubdivInputError&) {
      }
    }
  } catch (const InputError&) {
  }
  return 0;
}
