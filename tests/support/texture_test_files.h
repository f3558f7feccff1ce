// Images for texture tests, written with OpenImageIO: plain float RGB EXRs of known texels (the
// texture cache converts them to tiled MIP-mapped files), and a cache whose conversions go to a
// test's own folder.
#pragma once
#include <filesystem>
#include <memory>
#include <string>
#include <vector>
#include <OpenImageIO/imageio.h>
#include "core/vec.h"
#include "texture/texture_cache.h"

namespace rayes::testing {

// A scanline float EXR of w x h RGB texels (row-major, row 0 at the top).
inline void writeRgbExr(const std::filesystem::path& path, int w, int h, const std::vector<Rgb>& texels) {
  auto out = OIIO::ImageOutput::create(path.string());
  if (!out) throw std::runtime_error("no EXR writer");
  const OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::FLOAT);
  if (!out->open(path.string(), spec)) throw std::runtime_error(out->geterror());
  std::vector<float> data;
  for (const Rgb& c : texels) data.insert(data.end(), {c.x, c.y, c.z});
  out->write_image(OIIO::TypeDesc::FLOAT, data.data());
  out->close();
}

// A cache of `bytes` whose conversions go to `dir`, telling nothing.
inline std::shared_ptr<TextureCache> quietCache(const std::filesystem::path& dir, uint64_t bytes = kDefaultTextureMemoryBytes) {
  TextureCacheOptions o;
  o.memoryBytes = bytes;
  o.conversionDir = dir;
  o.notice = [](const std::string&) {};
  return TextureCache::make(o);
}

}  // namespace rayes::testing
