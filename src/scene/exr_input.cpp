#include "scene/exr_input.h"
#include <cstdint>
#include <fstream>
#include <ImfHeader.h>
#include "core/error.h"
#include "core/text_file.h"

namespace rayes {
namespace {

// How many value bytes OpenEXR 3.1's reader of a known attribute type consumes, whatever size
// the attribute declares; 0 for the types read by their declared size (strings, vectors, and
// unknown types, which it keeps as opaque bytes).
int fixedValueBytes(const std::string& type) {
  static const std::pair<const char*, int> kFixed[] = {
      {"box2i", 16}, {"box2f", 16}, {"chromaticities", 32}, {"compression", 1}, {"double", 8},
      {"envmap", 1}, {"float", 4}, {"int", 4}, {"keycode", 28}, {"lineOrder", 1}, {"m33f", 36},
      {"m33d", 72}, {"m44f", 64}, {"m44d", 128}, {"rational", 8}, {"tiledesc", 9}, {"timecode", 8},
      {"v2i", 8}, {"v2f", 8}, {"v2d", 16}, {"v3i", 12}, {"v3f", 12}, {"v3d", 24}, {"deepImageState", 1}};
  for (const auto& [name, bytes] : kFixed)
    if (type == name) return bytes;
  return 0;
}

// OpenEXR 3.1 allocates what a header attribute declares before reading it (an attribute of an
// unknown type claiming 1.9 GB in a 4 KB file, a preview image of 2^32 pixels; found by
// fuzz/exr_fuzz.cpp), so the headers are walked here first, consuming each value as OpenEXR's
// reader for its type does, and every allocation must fit in what is left of the file. Only
// that is checked: anything else malformed is left to OpenEXR, which throws.
void checkAttributeSizes(const std::string& path, const std::string& what, uint64_t fileSize) {
  std::ifstream in(path, std::ios::binary);
  unsigned char start[8];
  if (!in.read(reinterpret_cast<char*>(start), 8)) return;
  const bool multiPart = (start[5] & 0x10) != 0;  // version flags, bit 12
  auto readString = [&](std::string& s) {
    s.clear();
    for (char c; in.get(c);) {
      if (c == 0) return true;
      if (s.size() == 255) return false;  // longer than any name OpenEXR accepts: its error
      s += c;
    }
    return false;
  };
  auto readInt = [&](int64_t& v) {
    unsigned char b[4];
    if (!in.read(reinterpret_cast<char*>(b), 4)) return false;
    v = int32_t(uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16 | uint32_t(b[3]) << 24);
    return true;
  };
  auto fits = [&](const std::string& name, int64_t bytes) {
    const int64_t left = int64_t(fileSize) - int64_t(in.tellg());
    if (bytes < 0 || bytes > left)
      throw InputError(path, "", what + " is corrupt: header attribute '" + name + "' claims " +
                                     std::to_string(bytes) + " bytes, the file has " + std::to_string(left) + " left");
  };
  std::string name, type, channel;
  for (;;) {
    bool empty = true;
    while (readString(name) && !name.empty()) {
      empty = false;
      int64_t size;
      if (!readString(type) || !readInt(size)) return;
      if (const int fixed = fixedValueBytes(type)) {
        in.seekg(fixed, std::ios::cur);
      } else if (type == "chlist") {  // channels until an empty name, 16 bytes each after it
        while (readString(channel) && !channel.empty()) in.seekg(16, std::ios::cur);
      } else if (type == "preview") {  // width, height, then 4 bytes a pixel
        int64_t w, h;
        if (!readInt(w) || !readInt(h)) return;
        const uint64_t pixels = uint64_t(uint32_t(w)) * uint32_t(h);
        const int64_t bytes = pixels > (uint64_t(1) << 60) ? INT64_MAX : int64_t(4 * pixels);
        fits(name, bytes);
        in.seekg(bytes, std::ios::cur);
      } else {
        fits(name, size);
        in.seekg(size, std::ios::cur);
      }
    }
    if (!in || !multiPart || empty) return;  // a multi-part file ends its headers with an empty one
  }
}

}  // namespace

std::unique_ptr<Imf::InputFile> openExrInput(const std::filesystem::path& file, const std::string& what) {
  const std::string path = file.string();
  checkAttributeSizes(path, what, checkInputFile(path, what));
  constexpr int kMaxSide = 65536;
  Imf::Header::setMaxImageSize(kMaxSide, kMaxSide);
  std::unique_ptr<Imf::InputFile> in;
  try {
    in = std::make_unique<Imf::InputFile>(path.c_str());
  } catch (const std::exception& e) {
    throw InputError(path, "", "cannot read " + what + " (OpenEXR): " + e.what());
  }
  const Imath::Box2i dw = in->header().dataWindow();
  const int64_t w = int64_t(dw.max.x) - dw.min.x + 1, h = int64_t(dw.max.y) - dw.min.y + 1;
  if (w <= 0 || h <= 0 || w > kMaxSide || h > kMaxSide || w * h > (int64_t(1) << 28))
    throw InputError(path, "", what + " has an empty or unsupported data window (" + std::to_string(w) + "x" +
                                   std::to_string(h) + "; at most 2^28 pixels, 65536 on a side)");
  if (!in->isComplete())
    throw InputError(path, "", what + " is truncated: the file lacks pixels its header promises (" +
                                   std::to_string(w) + "x" + std::to_string(h) + ")");
  return in;
}

}  // namespace rayes
