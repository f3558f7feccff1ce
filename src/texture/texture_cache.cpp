// The program's side of the texture cache: what needs no OpenImageIO, and loading the module
// that does (core/plugin_module.h says why it is a module).
#include "texture/texture_cache.h"
#include "core/error.h"
#include "core/plugin_module.h"

namespace rayes {

int TextureImage::channelIndex(const std::string& name) const {
  const auto it = std::find(channelNames_.begin(), channelNames_.end(), name);
  return it == channelNames_.end() ? -1 : int(it - channelNames_.begin());
}

std::vector<Rgb> TextureImage::levelRgb(int level) const {
  const int w = levelWidth(level), h = levelHeight(level);
  std::vector<Rgb> out(size_t(w) * size_t(h));
  std::vector<float> row(static_cast<size_t>(w));
  const int n = channels_ >= 3 ? 3 : 1;
  for (int c = 0; c < n; ++c)
    for (int y = 0; y < h; ++y) {
      texels(level, 0, w, y, y + 1, c, row.data());
      for (int x = 0; x < w; ++x) {
        const float v = cleanedTexel(row[size_t(x)]);
        Rgb& o = out[size_t(y) * w + x];
        if (n == 1) o = {v, v, v};
        else o[c] = v;
      }
    }
  return out;
}

std::shared_ptr<TextureCache> TextureCache::make(TextureCacheOptions options) {
  const auto fn = reinterpret_cast<MakeTextureCacheFn>(
      moduleSymbol(kTextureModuleName, kMakeTextureCacheSymbol, "the scene reads images (OpenImageIO)"));
  std::string error;
  TextureCache* cache = fn(&options, &error);
  if (!cache) throw InputError(kTextureModuleName, "", "cannot make the texture cache: " + error);
  return std::shared_ptr<TextureCache>(cache);
}

}  // namespace rayes
