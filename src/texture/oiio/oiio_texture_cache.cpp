// The OpenImageIO module (librayes_oiio.so): the TextureCache and TextureImage of
// texture/texture_cache.h over one OIIO TextureSystem, and its one exported entry point. Only
// the module links OpenImageIO; the program loads it when a scene names an image.
#include <cmath>
#include <iostream>
#include <map>
#include <mutex>
#include <OpenImageIO/imagecache.h>
#include <OpenImageIO/texture.h>
#include <tbb/enumerable_thread_specific.h>
#include "core/error.h"
#include "texture/oiio/texture_file.h"
#include "texture/texture_cache.h"

namespace rayes {
namespace {

using OIIO::TextureOpt;
using OIIO::TextureSystem;

// The first three channels, or the first one three times.
Rgb rgbOf(const float* c, int channels) {
  return channels >= 3 ? Rgb{cleanedTexel(c[0]), cleanedTexel(c[1]), cleanedTexel(c[2])}
                       : Rgb{cleanedTexel(c[0]), cleanedTexel(c[0]), cleanedTexel(c[0])};
}

int64_t statOf(const TextureSystem& ts, const char* name) {
  long long v64 = 0;
  if (ts.getattribute(name, OIIO::TypeDesc::INT64, &v64)) return v64;
  int v = 0;
  if (ts.getattribute(name, OIIO::TypeDesc::INT, &v)) return v;
  return 0;
}

float statSeconds(const TextureSystem& ts, const char* name) {
  float v = 0;
  return ts.getattribute(name, OIIO::TypeDesc::FLOAT, &v) ? v : 0.0f;
}

class OiioTextureCache;

class OiioTextureImage final : public TextureImage {
 public:
  Rgb filtered(float s, float t, float dsdx, float dtdx, float dsdy, float dtdy, TextureWrap wrap) const override;
  Rgb closest(float s, float t) const override;
  void texels(int level, int x0, int x1, int y0, int y1, int channel, float* out) const override;

 private:
  friend class OiioTextureCache;
  [[noreturn]] void fail(const std::string& what) const;
  std::shared_ptr<OiioTextureCache> cache_;  // keeps the TextureSystem alive
  TextureSystem* system_ = nullptr;
  TextureSystem::TextureHandle* handle_ = nullptr;
};

class OiioTextureCache final : public TextureCache {
 public:
  explicit OiioTextureCache(TextureCacheOptions options);
  ~OiioTextureCache() override;
  std::shared_ptr<const TextureImage> open(const std::filesystem::path& source) override;
  void setMemoryBytes(uint64_t bytes) override;
  TextureCacheStats stats() const override;
  TextureSystem::Perthread* perthread() const;  // the calling thread's

 private:
  TextureSystem* system_ = nullptr;  // made with shared = false
  mutable tbb::enumerable_thread_specific<TextureSystem::Perthread*> perthread_{nullptr};
  std::function<void(const std::string&)> notice_;
  mutable std::mutex mutex_;
  std::map<std::string, std::weak_ptr<const TextureImage>> open_;  // by the path read
  uint64_t files_ = 0, conversions_ = 0;
};

}  // namespace

void OiioTextureImage::fail(const std::string& what) const {
  std::string why = system_->geterror();
  throw InputError(source_, "", what + (why.empty() ? "" : ": " + why));
}

Rgb OiioTextureImage::filtered(float s, float t, float dsdx, float dtdx, float dsdy, float dtdy, TextureWrap wrap) const {
  if (!std::isfinite(s) || !std::isfinite(t)) return {};
  // A non-finite axis would make OIIO's level selection meaningless: a point sample instead.
  if (!std::isfinite(dsdx) || !std::isfinite(dtdx) || !std::isfinite(dsdy) || !std::isfinite(dtdy)) dsdx = dtdx = dsdy = dtdy = 0;
  TextureOpt opt;
  opt.swrap = opt.twrap = wrap == TextureWrap::Periodic ? TextureOpt::WrapPeriodic : TextureOpt::WrapClamp;
  opt.mipmode = TextureOpt::MipModeAniso;
  opt.interpmode = TextureOpt::InterpBilinear;
  float c[3] = {0, 0, 0};
  const int n = channels_ >= 3 ? 3 : 1;
  TextureSystem* ts = system_;
  if (!ts->texture(handle_, cache_->perthread(), opt, s, t, dsdx, dtdx, dsdy, dtdy, n, c))
    fail("cannot read texture tiles");
  return rgbOf(c, n);
}

Rgb OiioTextureImage::closest(float s, float t) const {
  if (!std::isfinite(s) || !std::isfinite(t)) return {};
  TextureOpt opt;
  opt.swrap = opt.twrap = TextureOpt::WrapClamp;
  opt.mipmode = TextureOpt::MipModeNoMIP;
  opt.interpmode = TextureOpt::InterpClosest;
  float c[3] = {0, 0, 0};
  const int n = channels_ >= 3 ? 3 : 1;
  TextureSystem* ts = system_;
  if (!ts->texture(handle_, cache_->perthread(), opt, s, t, 0, 0, 0, 0, n, c))
    fail("cannot read texture tiles");
  return rgbOf(c, n);
}

void OiioTextureImage::texels(int level, int x0, int x1, int y0, int y1, int channel, float* out) const {
  if (x1 <= x0 || y1 <= y0) return;
  channel = std::clamp(channel, 0, channels_ - 1);
  TextureOpt opt;
  TextureSystem* ts = system_;
  if (!ts->get_texels(handle_, cache_->perthread(), opt, level, x0, x1, y0, y1, 0, 1, channel,
                      channel + 1, OIIO::TypeDesc::FLOAT, out))
    fail("cannot read texels of MIP level " + std::to_string(level));
}

OiioTextureCache::OiioTextureCache(TextureCacheOptions options) : notice_(std::move(options.notice)) {
  conversionDir_ = options.conversionDir.empty() ? defaultTextureCacheDir() : options.conversionDir;
  TextureSystem* ts = TextureSystem::create(/*shared=*/false);
  system_ = ts;
  // Only tiled, MIP-mapped files reach the cache (prepareTextureFile converts the others), so
  // OIIO never tiles or MIP-maps a whole image in memory behind the bound's back.
  ts->attribute("autotile", 0);
  ts->attribute("automip", 0);
  ts->attribute("accept_untiled", 0);
  ts->attribute("accept_unmipped", 0);
  setMemoryBytes(options.memoryBytes);
  if (!notice_) notice_ = [](const std::string& s) { std::cerr << "rayes: " << s << "\n"; };
}

OiioTextureCache::~OiioTextureCache() {
  for (TextureSystem::Perthread* p : perthread_)
    if (p) system_->destroy_thread_info(p);
  TextureSystem::destroy(system_, /*teardown_imagecache=*/true);
}

TextureSystem::Perthread* OiioTextureCache::perthread() const {
  TextureSystem::Perthread*& p = perthread_.local();
  if (!p) p = system_->create_thread_info();
  return p;
}

void OiioTextureCache::setMemoryBytes(uint64_t bytes) {
  memoryBytes_ = bytes;
  system_->attribute("max_memory_MB", float(double(bytes) / double(1 << 20)));
}

std::shared_ptr<const TextureImage> OiioTextureCache::open(const std::filesystem::path& source) {
  std::lock_guard<std::mutex> lock(mutex_);
  const PreparedTextureFile prepared = prepareTextureFile(source, conversionDir_, notice_);
  if (prepared.converted) ++conversions_;
  const std::string path = prepared.path.string();
  if (auto it = open_.find(path); it != open_.end())
    if (auto kept = it->second.lock()) return kept;
  TextureSystem* ts = system_;
  const OIIO::ustring name(path);
  auto image = std::make_shared<OiioTextureImage>();
  image->cache_ = std::static_pointer_cast<OiioTextureCache>(shared_from_this());
  image->system_ = ts;
  image->source_ = source.string();
  image->path_ = path;
  image->handle_ = ts->get_texture_handle(name, perthread());
  int resolution[2] = {0, 0}, channels = 0;
  if (!image->handle_ || !ts->get_texture_info(image->handle_, perthread(), 0, OIIO::ustring("resolution"),
                                                OIIO::TypeDesc(OIIO::TypeDesc::INT, 2), resolution) ||
      !ts->get_texture_info(image->handle_, perthread(), 0, OIIO::ustring("channels"),
                            OIIO::TypeDesc::INT, &channels))
    image->fail("cannot open texture '" + path + "'");
  image->width_ = resolution[0];
  image->height_ = resolution[1];
  image->channels_ = channels;
  if (image->width_ <= 0 || image->height_ <= 0 || channels <= 0) throw InputError(source.string(), "", "the image has no pixels");
  OIIO::ImageSpec spec;
  if (ts->imagecache()->get_imagespec(name, spec, 0, 0)) image->channelNames_ = spec.channelnames;
  int levels = 1;
  while (ts->imagecache()->get_imagespec(name, spec, 0, levels)) ++levels;
  image->levels_ = levels;
  open_[path] = image;
  ++files_;
  return image;
}

TextureCacheStats OiioTextureCache::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  const TextureSystem& ts = *system_;
  TextureCacheStats s;
  s.files = files_;
  s.conversions = conversions_;
  s.imageBytes = uint64_t(statOf(ts, "stat:image_size"));
  s.tilesRead = uint64_t(statOf(ts, "stat:tiles_created"));
  s.bytesRead = uint64_t(statOf(ts, "stat:bytes_read"));
  s.tileLookups = uint64_t(statOf(ts, "stat:find_tile_calls"));
  s.hitRate = s.tileLookups > 0 ? 1.0 - double(std::min(s.tilesRead, s.tileLookups)) / double(s.tileLookups) : 1.0;
  s.peakTiles = uint64_t(statOf(ts, "stat:tiles_peak"));
  s.memoryBytes = uint64_t(statOf(ts, "stat:cache_memory_used"));
  s.memoryLimitBytes = memoryBytes_;
  s.ioSeconds = statSeconds(ts, "stat:fileio_time");
  return s;
}

}  // namespace rayes

// The module's entry point (texture/texture_cache.h, MakeTextureCacheFn): exceptions stay inside.
extern "C" __attribute__((visibility("default"))) rayes::TextureCache* rayes_oiio_make_texture_cache(
    const rayes::TextureCacheOptions* options, std::string* error) {
  try {
    return new rayes::OiioTextureCache(*options);
  } catch (const std::exception& e) {
    *error = e.what();
    return nullptr;
  }
}
