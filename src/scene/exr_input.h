// Opening an OpenEXR input (a texture, a height map, a reference image) with the checks that
// must come before any pixel memory is allocated: the header's data window is at most
// 2^28 pixels (and 65536 on a side, which also bounds OpenEXR's own line-offset table), and
// the file holds every chunk the header promises (a truncated file is rejected, not read).
#pragma once
#include <filesystem>
#include <memory>
#include <string>
#include <ImfInputFile.h>

namespace rayes {

// Throws InputError(file, "", ...) naming `what` ("image", "height map", ...).
std::unique_ptr<Imf::InputFile> openExrInput(const std::filesystem::path& file, const std::string& what);

}  // namespace rayes
