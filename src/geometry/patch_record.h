// A Patch as a flat byte record, and back: what a compiled scene (geometry/compiled_file.h)
// stores per leaf. A record holds exactly the values the patch's constructor was given
// (control points, corners, the displacement's parameters, the motion's times and samples),
// so decoding rebuilds the same patch bit for bit through the same constructors, and the
// compiled render equals the JSON render.
//
// Kinds encoded: Bézier, bilinear, and the decorators over them as far as they are data:
// noise displacement (with its reference surface) and motion. Not encoded (encodePatch says
// which, naming the kind): subdivision faces (their mesh is shared by every face), height-map
// displacement (an image) and disks (only lights make them, and lights are not leaves of the
// compiled shapes).
//
// Format (little-endian, floats as IEEE bits): a one-byte tag, then the kind's fields;
// decorators nest the records of the patches they wrap. Pure functions, thread-safe.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>
#include "geometry/patch.h"

namespace rayes {

// Appends `patch`'s record to `out`. Returns "" on success, else why it cannot be encoded
// (out is then unspecified).
std::string encodePatch(const Patch& patch, std::vector<uint8_t>& out);

// The patch of a record of exactly `bytes` bytes. Throws std::invalid_argument naming what is
// wrong (an unknown tag, a record shorter or longer than its fields, a value its constructor
// refuses); the caller names the file and the leaf.
PatchPtr decodePatch(const uint8_t* data, size_t bytes);

}  // namespace rayes
