// Which file the texture cache reads for an image the scene names (docs/scene-format.md,
// "Texture files"). OpenImageIO's TextureSystem pages tiles of MIP-mapped files; a file that is
// already tiled and MIP-mapped (maketx output, any format OIIO reads) is read in place. A plain
// image (PNG, scanline EXR, ...) is converted once, with ImageBufAlgo::make_texture, into a
// tiled, MIP-mapped OpenEXR file in the conversion folder, named by a hash of the source's
// bytes and of the conversion's settings, so scenes share conversions and an edited file is
// converted again. The conversion is written to a temporary name and renamed: a crashed or
// concurrent conversion never leaves a partial file under the final name.
//
// Colour: PNG and other 8/16-bit formats hold sRGB-encoded values and are decoded to linear
// (half-float output); float formats (EXR, HDR) are linear and kept as they are. A file read in
// place is taken as linear whatever its format (make such files from float images, or give the
// renderer the PNG itself). NaN texels
// become black. MIP levels are box-filtered (so a level's texels never leave the range of the
// texels below them: the environment's sampling distribution relies on it). Height maps use
// only the finest level (geometry/displacement.h: their bounds are a pyramid of their own).
//
// Functions here are thread-compatible (one conversion per file at a time; a second process
// converting the same file writes its own temporary and renames it over the same bytes).
#pragma once
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

namespace rayes {

// The default conversion folder: $XDG_CACHE_HOME/rayes/textures, else ~/.cache/rayes/textures,
// else (no HOME) a folder under the system's temporary directory.
std::filesystem::path defaultTextureCacheDir();

struct PreparedTextureFile {
  std::filesystem::path path;  // what the cache reads: the source, or its conversion
  bool converted = false;      // a conversion was written now (not found from an earlier run)
  bool inPlace = false;        // the source is tiled and MIP-mapped and is read as it is
};

// The file to read for `source`. Throws InputError(source, "", why) when `source` is missing,
// is not an image OpenImageIO can read (not an image, truncated), or cannot be converted; and
// InputError("--texture-cache-dir", ...) when the conversion folder cannot be written; and
// ResourceError(source, ...) (exit code 3) when converting would need more memory than
// `conversionMemoryBytes` allows (0: what this process may use, core/memory.h), checked from the
// header before any pixel is read. `notice` is told once per conversion written ("converted X to Y").
PreparedTextureFile prepareTextureFile(const std::filesystem::path& source, const std::filesystem::path& cacheDir,
                                       const std::function<void(const std::string&)>& notice,
                                       uint64_t conversionMemoryBytes = 0);

// A hash of the file's bytes and `seed` (hex, 16 digits), read in blocks of 1 MiB.
std::string fileContentHash(const std::filesystem::path& file, uint64_t seed);

}  // namespace rayes
