#include "texture/texture_cache.h"
#include <cmath>
#include <iostream>
#include <OpenImageIO/imagecache.h>
#include <OpenImageIO/texture.h>
#include "core/error.h"
#include "texture/texture_file.h"

namespace rayes {
namespace {

using OIIO::TextureOpt;
using OIIO::TextureSystem;

TextureSystem* sys(void* p) { return static_cast<TextureSystem*>(p); }
TextureSystem::Perthread* threadOf(void* p) { return static_cast<TextureSystem::Perthread*>(p); }
TextureSystem::TextureHandle* handleOf(void* p) { return static_cast<TextureSystem::TextureHandle*>(p); }

float cleaned(float x) { return std::isfinite(x) && x > 0 ? x : 0.0f; }

// The first three channels, or the first one three times.
Rgb rgbOf(const float* c, int channels) {
  return channels >= 3 ? Rgb{cleaned(c[0]), cleaned(c[1]), cleaned(c[2])} : Rgb{cleaned(c[0]), cleaned(c[0]), cleaned(c[0])};
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

}  // namespace

void TextureImage::fail(const std::string& what) const {
  std::string why = sys(system_)->geterror();
  throw InputError(source_, "", what + (why.empty() ? "" : ": " + why));
}

Rgb TextureImage::filtered(float s, float t, float dsdx, float dtdx, float dsdy, float dtdy, TextureWrap wrap) const {
  if (!std::isfinite(s) || !std::isfinite(t)) return {};
  // A non-finite axis would make OIIO's level selection meaningless: a point sample instead.
  if (!std::isfinite(dsdx) || !std::isfinite(dtdx) || !std::isfinite(dsdy) || !std::isfinite(dtdy)) dsdx = dtdx = dsdy = dtdy = 0;
  TextureOpt opt;
  opt.swrap = opt.twrap = wrap == TextureWrap::Periodic ? TextureOpt::WrapPeriodic : TextureOpt::WrapClamp;
  opt.mipmode = TextureOpt::MipModeAniso;
  opt.interpmode = TextureOpt::InterpBilinear;
  float c[3] = {0, 0, 0};
  const int n = channels_ >= 3 ? 3 : 1;
  TextureSystem* ts = sys(system_);
  if (!ts->texture(handleOf(handle_), threadOf(cache_->perthread()), opt, s, t, dsdx, dtdx, dsdy, dtdy, n, c))
    fail("cannot read texture tiles");
  return rgbOf(c, n);
}

Rgb TextureImage::closest(float s, float t) const {
  if (!std::isfinite(s) || !std::isfinite(t)) return {};
  TextureOpt opt;
  opt.swrap = opt.twrap = TextureOpt::WrapClamp;
  opt.mipmode = TextureOpt::MipModeNoMIP;
  opt.interpmode = TextureOpt::InterpClosest;
  float c[3] = {0, 0, 0};
  const int n = channels_ >= 3 ? 3 : 1;
  TextureSystem* ts = sys(system_);
  if (!ts->texture(handleOf(handle_), threadOf(cache_->perthread()), opt, s, t, 0, 0, 0, 0, n, c))
    fail("cannot read texture tiles");
  return rgbOf(c, n);
}

void TextureImage::texels(int level, int x0, int x1, int y0, int y1, int channel, float* out) const {
  if (x1 <= x0 || y1 <= y0) return;
  channel = std::clamp(channel, 0, channels_ - 1);
  TextureOpt opt;
  TextureSystem* ts = sys(system_);
  if (!ts->get_texels(handleOf(handle_), threadOf(cache_->perthread()), opt, level, x0, x1, y0, y1, 0, 1, channel,
                      channel + 1, OIIO::TypeDesc::FLOAT, out))
    fail("cannot read texels of MIP level " + std::to_string(level));
}

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
        const float v = cleaned(row[size_t(x)]);
        Rgb& o = out[size_t(y) * w + x];
        if (n == 1) o = {v, v, v};
        else o[c] = v;
      }
    }
  return out;
}

std::shared_ptr<TextureCache> TextureCache::make(TextureCacheOptions options) {
  return std::shared_ptr<TextureCache>(new TextureCache(std::move(options)));
}

TextureCache::TextureCache(TextureCacheOptions options)
    : conversionDir_(options.conversionDir.empty() ? defaultTextureCacheDir() : options.conversionDir),
      notice_(std::move(options.notice)) {
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

TextureCache::~TextureCache() {
  for (void* p : perthread_)
    if (p) sys(system_)->destroy_thread_info(static_cast<TextureSystem::Perthread*>(p));
  TextureSystem::destroy(sys(system_), /*teardown_imagecache=*/true);
}

void* TextureCache::perthread() const {
  void*& p = perthread_.local();
  if (!p) p = sys(system_)->create_thread_info();
  return p;
}

void TextureCache::setMemoryBytes(uint64_t bytes) {
  memoryBytes_ = bytes;
  sys(system_)->attribute("max_memory_MB", float(double(bytes) / double(1 << 20)));
}

std::shared_ptr<const TextureImage> TextureCache::open(const std::filesystem::path& source) {
  std::lock_guard<std::mutex> lock(mutex_);
  const PreparedTextureFile prepared = prepareTextureFile(source, conversionDir_, notice_);
  if (prepared.converted) ++conversions_;
  const std::string path = prepared.path.string();
  if (auto it = open_.find(path); it != open_.end())
    if (auto kept = it->second.lock()) return kept;
  TextureSystem* ts = sys(system_);
  const OIIO::ustring name(path);
  auto image = std::shared_ptr<TextureImage>(new TextureImage());
  image->cache_ = shared_from_this();
  image->system_ = ts;
  image->source_ = source.string();
  image->path_ = path;
  image->handle_ = ts->get_texture_handle(name, threadOf(perthread()));
  int resolution[2] = {0, 0}, channels = 0;
  if (!image->handle_ || !ts->get_texture_info(handleOf(image->handle_), threadOf(perthread()), 0, OIIO::ustring("resolution"),
                                                OIIO::TypeDesc(OIIO::TypeDesc::INT, 2), resolution) ||
      !ts->get_texture_info(handleOf(image->handle_), threadOf(perthread()), 0, OIIO::ustring("channels"),
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

TextureCacheStats TextureCache::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  const TextureSystem& ts = *sys(system_);
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
