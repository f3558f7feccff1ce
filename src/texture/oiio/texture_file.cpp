#include "texture/oiio/texture_file.h"
#include <cstdio>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <system_error>
#include <vector>
#include <fcntl.h>
#include <unistd.h>
#include <OpenImageIO/hash.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include "core/error.h"
#include "core/memory.h"
#include "core/text_file.h"

namespace rayes {
namespace {

// Part of every conversion's name: a change of the settings below must change it, so old
// conversions are not read as new ones.
constexpr const char* kConversionVersion = "rayes-texture-1";

bool isFloatFormat(OIIO::TypeDesc t) {
  return t.basetype == OIIO::TypeDesc::FLOAT || t.basetype == OIIO::TypeDesc::HALF || t.basetype == OIIO::TypeDesc::DOUBLE;
}

std::string hex16(uint64_t h) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

float srgbToLinear(float s) {
  return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f);
}

// `decoded`: `encoded` with its colour channels (all but alpha) taken from sRGB to linear.
bool srgbDecoded(const OIIO::ImageBuf& encoded, OIIO::ImageBuf& decoded) {
  OIIO::ImageSpec spec = encoded.spec();
  spec.set_format(OIIO::TypeDesc::HALF);
  decoded.reset(spec);
  const int n = spec.nchannels;
  std::vector<float> row(size_t(spec.width) * size_t(n));
  for (int y = spec.y; y < spec.y + spec.height; ++y) {
    const OIIO::ROI roi(spec.x, spec.x + spec.width, y, y + 1, 0, 1, 0, n);
    if (!encoded.get_pixels(roi, OIIO::TypeDesc::FLOAT, row.data())) return false;
    for (size_t i = 0; i < row.size(); ++i)
      if (int(i % size_t(n)) != spec.alpha_channel) row[i] = srgbToLinear(row[i]);
    if (!decoded.set_pixels(roi, OIIO::TypeDesc::FLOAT, row.data())) return false;
  }
  return true;
}

// OIIO's error text on one line (the program prints one line per error).
std::string oneLine(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ';';
  while (!s.empty() && (s.back() == ';' || s.back() == ' ')) s.pop_back();
  return s;
}

// While it lives, file descriptor 2 goes to /dev/null: libpng, under OIIO's PNG reader, prints
// its errors on stderr itself before OIIO reports them; the program reports each problem once,
// as an InputError. Only used while a file is read at scene load, when nothing else prints.
class QuietStderr {
 public:
  QuietStderr() : saved_(::dup(2)) {
    const int null = ::open("/dev/null", O_WRONLY);
    if (saved_ >= 0 && null >= 0) ::dup2(null, 2);
    if (null >= 0) ::close(null);
  }
  ~QuietStderr() {
    if (saved_ >= 0) {
      ::dup2(saved_, 2);
      ::close(saved_);
    }
  }
  QuietStderr(const QuietStderr&) = delete;
  QuietStderr& operator=(const QuietStderr&) = delete;

 private:
  int saved_;
};

}  // namespace

std::filesystem::path defaultTextureCacheDir() {
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return std::filesystem::path(x) / "rayes" / "textures";
  if (const char* h = std::getenv("HOME"); h && *h) return std::filesystem::path(h) / ".cache" / "rayes" / "textures";
  return std::filesystem::temp_directory_path() / "rayes-textures";
}

std::string fileContentHash(const std::filesystem::path& file, uint64_t seed) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string(), "", "cannot open image");
  // Block by block, each block's hash seeded with the previous one: memory stays one block
  // however large the image.
  std::vector<char> block(size_t(1) << 20);
  uint64_t h = seed;
  while (in) {
    in.read(block.data(), std::streamsize(block.size()));
    const std::streamsize n = in.gcount();
    if (n <= 0) break;
    h = OIIO::xxhash::XXH64(block.data(), size_t(n), h);
  }
  if (in.bad()) throw InputError(file.string(), "", "cannot read image");
  return hex16(h);
}

namespace {

// The source's pixels, read with ImageInput into a buffer of this call. Not through an ImageBuf
// that names the file: that reads through OpenImageIO's shared ImageCache, which keeps what it
// learnt of a path across calls, so a file rewritten under the same name (the fuzzers do it on
// every input) was read with the old file's layout and OpenImageIO's own buffers were corrupted.
bool readPixels(OIIO::ImageInput& in, const OIIO::ImageSpec& spec, OIIO::ImageBuf& pixels) {
  OIIO::ImageSpec layout = spec;
  layout.set_format(spec.format);  // one format for every channel (an EXR may mix half and float)
  pixels.reset(layout);
  return in.read_image(0, 0, 0, spec.nchannels, spec.format, pixels.localpixels());
}

PreparedTextureFile prepared(const std::filesystem::path& source, const std::filesystem::path& cacheDir,
                             uint64_t conversionMemoryBytes) {
  const std::string name = source.string();
  std::error_code ec;
  // Missing, a folder, a FIFO or a device: refused before any reader opens it (a FIFO would block).
  const uint64_t fileBytes = checkInputFile(name, "image");
  auto in = OIIO::ImageInput::open(name);
  if (!in) throw InputError(name, "", "not an image OpenImageIO can read: " + oneLine(OIIO::geterror()));
  const OIIO::ImageSpec spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    throw InputError(name, "", "the image has no pixels");
  // In double: width x height x channels can pass 2^64 bytes. A PNG is deflated, which expands at
  // most 1032:1: a header claiming more pixels than the file can hold is a lie, refused before
  // the conversion allocates them.
  const double texels = double(spec.width) * double(spec.height) * double(spec.nchannels);
  const double rawBytes = texels * double(spec.format.size());
  if (std::string(in->format_name()) == "png" && rawBytes > 1032.0 * double(fileBytes) + 65536.0)
    throw InputError(name, "", "the header claims " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                                   " pixels, more than its " + std::to_string(fileBytes) + " bytes can hold");
  if (spec.depth > 1) throw InputError(name, "", "a volume image is not a surface texture");
  const bool tiled = spec.tile_width > 0;
  const bool mipmapped = in->seek_subimage(0, 1) || (spec.width == 1 && spec.height == 1);
  const bool linear = isFloatFormat(spec.format);
  if (tiled && mipmapped) return {source, false, true};
  if (!in->seek_subimage(0, 0)) throw InputError(name, "", "cannot read image: " + oneLine(in->geterror()));

  // What the conversion depends on: the source's bytes and the settings, so an edited file or
  // new settings give a new name.
  const std::string hash = fileContentHash(source, OIIO::Strutil::strhash(kConversionVersion));
  const std::filesystem::path target = cacheDir / (source.stem().string() + "-" + hash + ".exr");
  if (std::filesystem::exists(target, ec)) return {target, false, false};
  // The conversion holds the source's pixels, the reader's staging buffer (OpenImageIO 2.4 reads
  // scanlines in chunks of at least 256 rows or 64 MiB, whatever the image's height), a half-float
  // copy of an sRGB image, and make_texture's float pyramid (4/3 of a float copy). Any format but PNG can claim pixels its
  // bytes do not hold (an EXR's compression has no such bound), so this is checked before anything
  // is allocated; a file read in place, or converted by an earlier run, needs none of it.
  const uint64_t conversionBytes =
      uint64_t(std::min(rawBytes + std::max(0x1p26, 256.0 * double(spec.width) * double(spec.pixel_bytes(true))) +
                            (linear ? 0.0 : texels * 2) + texels * 4 * 4 / 3,
                        0x1p62));
  const std::string what = "converting '" + name + "' (" + std::to_string(spec.width) + "x" +
                           std::to_string(spec.height) + ", " + std::to_string(spec.nchannels) +
                           " channels) to a tiled MIP-mapped file";
  const std::string advice =
      "convert it beforehand with OpenImageIO's maketx (maketx --tile 64 64 -o image.exr image), which a render "
      "reads in place through the texture cache without holding it";
  if (conversionMemoryBytes != 0) {
    if (conversionBytes > conversionMemoryBytes)
      throw ResourceError(name, what + " needs about " + readableBytes(conversionBytes) + ", more than the " +
                                    readableBytes(conversionMemoryBytes) + " allowed; " + advice);
  } else {
    checkMemoryFits(conversionBytes, name, what, advice);
  }

  std::filesystem::create_directories(cacheDir, ec);
  if (ec || !std::filesystem::is_directory(cacheDir))
    throw InputError("--texture-cache-dir", "", "cannot create the texture conversion folder '" + cacheDir.string() +
                                                    "'" + (ec ? ": " + ec.message() : ""));

  OIIO::ImageSpec config;
  config.tile_width = config.tile_height = 64;
  config.attribute("compression", "zip");
  config.attribute("maketx:fileformatname", "openexr");
  config.attribute("maketx:filtername", "box");
  config.attribute("maketx:fixnan", "black");
  config.attribute("maketx:set_full_to_pixels", 1);  // [0, 1] spans the pixels, whatever the display window
  // Unique per process and call, in the target's folder so the rename is atomic.
  static std::atomic<uint64_t> counter{0};
  const std::filesystem::path temp =
      target.string() + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter.fetch_add(1));
  OIIO::ImageBuf pixels;
  bool made = readPixels(*in, spec, pixels);
  std::string why = made ? "" : in->geterror();
  in->close();
  if (made && linear) {
    made = OIIO::ImageBufAlgo::make_texture(OIIO::ImageBufAlgo::MakeTxTexture, pixels, temp.string(), config);
  } else if (made) {
    // OIIO's colour conversion needs an OpenColorIO config, which a render must not depend on:
    // the sRGB curve is applied here, row by row, into a half-float copy.
    OIIO::ImageBuf decoded;
    made = srgbDecoded(pixels, decoded);
    pixels.reset();
    if (made) {
      config.format = OIIO::TypeDesc::HALF;
      made = OIIO::ImageBufAlgo::make_texture(OIIO::ImageBufAlgo::MakeTxTexture, decoded, temp.string(), config);
    } else {
      why = decoded.geterror();
    }
  }
  if (!made) {
    std::filesystem::remove(temp, ec);
    if (why.empty()) why = OIIO::geterror();
    if (why.empty()) why = "conversion failed";
    throw InputError(name, "", "cannot convert the image to a tiled MIP-mapped texture: " + oneLine(why));
  }
  std::filesystem::rename(temp, target, ec);
  if (ec) {
    std::filesystem::remove(temp, ec);
    throw InputError("--texture-cache-dir", "", "cannot write '" + target.string() + "': " + ec.message());
  }
  return {target, true, false};
}

}  // namespace

PreparedTextureFile prepareTextureFile(const std::filesystem::path& source, const std::filesystem::path& cacheDir,
                                       const std::function<void(const std::string&)>& notice,
                                       uint64_t conversionMemoryBytes) {
  std::string failure;
  try {
    PreparedTextureFile result;
    {
      const QuietStderr quiet;
      result = prepared(source, cacheDir, conversionMemoryBytes);
    }
    if (result.converted && notice)
      notice("converted texture '" + source.string() + "' to a tiled MIP-mapped file '" + result.path.string() + "'");
    return result;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    // A reader of a damaged file may throw (OIIO's GIF reader: a length error).
    failure = e.what();
  }
  throw InputError(source.string(), "", "not an image OpenImageIO can read: " + oneLine(failure));
}

}  // namespace rayes
