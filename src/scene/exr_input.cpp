#include "scene/exr_input.h"
#include <ImfHeader.h>
#include "core/error.h"
#include "core/text_file.h"

namespace rayes {

std::unique_ptr<Imf::InputFile> openExrInput(const std::filesystem::path& file, const std::string& what) {
  const std::string path = file.string();
  checkInputFile(path, what);
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
