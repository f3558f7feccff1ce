// START HERE for image textures. The TextureCache owns one OpenImageIO TextureSystem for a
// render (its own, not OIIO's shared one): every image a scene reads -- colour textures,
// environment maps, height maps -- is paged through its tile cache, whose memory is bounded by
// --texture-memory (OIIO's max_memory_MB). Files are opened once, at scene load
// (TextureCache::open: a plain image is converted first, texture/oiio/texture_file.h), and each
// becomes a TextureImage, which holds OIIO's handle and answers lookups.
//
// Loaded only when a scene names an image: the classes here are interfaces, implemented in the
// OpenImageIO module (texture/oiio/, librayes_oiio.so) that make() loads at its first call, so a
// scene without images never pays OpenImageIO's start-up (core/plugin_module.h).
//
// Ownership: the scene owns the cache (a shared_ptr, made only when the scene names an image);
// every TextureImage shares ownership of it, so a texture outlives nothing it reads. The module
// is never unloaded.
// Thread safety: open() is serialised by a mutex; lookups and stats() are thread-safe and may run
// on any thread. Each thread that looks up gets its own OIIO per-thread state (its micro-cache of
// tiles), made on its first lookup and owned by the cache, which destroys them all before the
// TextureSystem: OIIO's own per-thread state would outlive a cache destroyed while the TBB
// workers live on, and touch it at their exit.
// Determinism: a lookup is a pure function of the file and its arguments: the cache's size, the
// order of lookups and the thread count change which tiles are resident, never a value.
// Cost: a lookup touches at most a few tiles of two MIP levels (anisotropic: up to 32 probes,
// OIIO's default, along the footprint's long axis); a tile read from disk costs file I/O once
// until it is evicted (OIIO's clock: least recently used out first). The interface adds one
// virtual call per lookup.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>
#include "core/vec.h"

namespace rayes {

inline constexpr uint64_t kDefaultTextureMemoryBytes = uint64_t(256) << 20;

struct TextureCacheOptions {
  uint64_t memoryBytes = kDefaultTextureMemoryBytes;  // the tile cache's bound (> 0)
  std::filesystem::path conversionDir;                // empty: defaultTextureCacheDir()
  // Told once per conversion written (texture/oiio/texture_file.h); null: printed on stderr.
  std::function<void(const std::string&)> notice;
};

// What the cache did (the stats file's "textures" section, docs/stats.md).
struct TextureCacheStats {
  uint64_t files = 0;           // images opened
  uint64_t conversions = 0;     // plain images converted during this run (others were found converted)
  uint64_t imageBytes = 0;      // all MIP levels of every image, uncompressed: what "all resident" would hold
  uint64_t tilesRead = 0;       // tiles read from disk (a tile evicted and needed again counts again)
  uint64_t bytesRead = 0;       // their uncompressed bytes
  uint64_t tileLookups = 0;     // lookups of a tile in the shared cache (per-thread micro-cache hits excluded)
  double hitRate = 1;           // 1 - tilesRead / tileLookups: lookups that found the tile resident
  uint64_t peakTiles = 0;       // most tiles resident at once
  uint64_t memoryBytes = 0;     // the cache's memory at the end (OIIO frees tiles only over the bound)
  uint64_t memoryLimitBytes = 0;  // --texture-memory
  double ioSeconds = 0;         // time in file I/O, all threads
};

enum class TextureWrap : uint8_t { Periodic, Clamp };

// A texel value as lookups return it: non-finite and negative values are 0.
inline float cleanedTexel(float x) { return std::isfinite(x) && x > 0 ? x : 0.0f; }

// The OpenImageIO module's file (core/plugin_module.h).
inline constexpr const char* kTextureModuleName = "librayes_oiio.so";

// One image of the cache. Coordinates are OIIO's: s to the right, t down, [0, 1] over the image,
// texel centres at ((i + 0.5) / width, (j + 0.5) / height); image row 0 at t = 0. Images with
// fewer than three channels return their first channel in all three; non-finite or negative
// values are returned as 0. Throws InputError naming the file when a tile cannot be read (a file
// damaged after it was opened).
class TextureImage {
 public:
  virtual ~TextureImage() = default;
  int width() const { return width_; }
  int height() const { return height_; }
  int channels() const { return channels_; }
  int levels() const { return levels_; }  // MIP levels
  int levelWidth(int level) const { return std::max(1, width_ >> level); }
  int levelHeight(int level) const { return std::max(1, height_ >> level); }
  const std::string& file() const { return source_; }  // the file the scene names
  // The index of the channel named `name` (OIIO's order: R, G, B, A first), or -1.
  int channelIndex(const std::string& name) const;

  // A filtered lookup over the footprint with axes (dsdx, dtdx) and (dsdy, dtdy) about (s, t):
  // OIIO's anisotropic MIP filter with bilinear texel interpolation. Zero axes: a bilinear
  // sample of the finest level.
  virtual Rgb filtered(float s, float t, float dsdx, float dtdx, float dsdy, float dtdy, TextureWrap wrap) const = 0;
  // The texel of the finest level containing (s, t), clamped at the edges.
  virtual Rgb closest(float s, float t) const = 0;
  // Texels [x0, x1) x [y0, y1) of MIP level `level`, channel `channel` (clamped to the image's),
  // row-major into out ((x1 - x0) * (y1 - y0) floats). The only way to read many texels at once:
  // the environment's sampling distribution and the height maps' bounds stream them.
  virtual void texels(int level, int x0, int x1, int y0, int y1, int channel, float* out) const = 0;
  // RGB texels of a whole MIP level, row-major.
  std::vector<Rgb> levelRgb(int level) const;

 protected:
  TextureImage() = default;
  std::string source_, path_;
  std::vector<std::string> channelNames_;
  int width_ = 0, height_ = 0, channels_ = 0, levels_ = 1;
};

class TextureCache : public std::enable_shared_from_this<TextureCache> {
 public:
  // Loads the OpenImageIO module at the first call; throws InputError naming the module and
  // where it was looked for when it cannot be loaded (a program copied without it).
  static std::shared_ptr<TextureCache> make(TextureCacheOptions options);
  virtual ~TextureCache() = default;
  TextureCache(const TextureCache&) = delete;
  TextureCache& operator=(const TextureCache&) = delete;

  // The image of `source` (prepared by prepareTextureFile: in place or converted), opened once:
  // the same file again gives the same image. Throws InputError naming the file.
  virtual std::shared_ptr<const TextureImage> open(const std::filesystem::path& source) = 0;
  // The tile cache's bound; may be changed between renders.
  virtual void setMemoryBytes(uint64_t bytes) = 0;
  uint64_t memoryBytes() const { return memoryBytes_; }
  const std::filesystem::path& conversionDir() const { return conversionDir_; }
  virtual TextureCacheStats stats() const = 0;

 protected:
  TextureCache() = default;
  uint64_t memoryBytes_ = 0;
  std::filesystem::path conversionDir_;
};

// The module's one entry point (extern "C", looked up by name): a new cache, or null with `error`
// set. Defined in texture/oiio/oiio_texture_cache.cpp.
using MakeTextureCacheFn = TextureCache* (*)(const TextureCacheOptions* options, std::string* error);
inline constexpr const char* kMakeTextureCacheSymbol = "rayes_oiio_make_texture_cache";

}  // namespace rayes
