#include "app/image_io.h"
#include <cerrno>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <png.h>
#include "core/error.h"
#include "scene/exr_input.h"

namespace rayes {
namespace {

uint8_t toSrgb8(float v) {
  if (!(v > 0)) return 0;
  if (v >= 1) return 255;
  const float s = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
  return static_cast<uint8_t>(std::lround(s * 255.0f));
}

}  // namespace

void writeExr(const std::string& path, const Film& film, const PixelCost* cost) {
  const int w = film.width(), h = film.height();
  const std::vector<float> rgba = film.beautyRgba(), depth = film.depth(), normal = film.normal(), lod = film.lod();
  const std::vector<float> albedo = film.albedo(), material = film.materialId(), samples = film.sampleCount();
  // A window of the image (--crop): its pixels are the data window, the full image the display
  // window, as production renderers write crops (compositors place them by it).
  const PixelWindow& win = film.window();
  const Imath::Box2i display(Imath::V2i(0, 0), Imath::V2i(film.fullWidth() - 1, film.fullHeight() - 1));
  const Imath::Box2i data(Imath::V2i(win.x0, win.y0), Imath::V2i(win.x1 - 1, win.y1 - 1));
  Imf::Header header(display, data);
  const char* names[] = {"R", "G", "B", "A", "depth.Z", "normal.X", "normal.Y", "normal.Z", "lod.Y",
                         "albedo.R", "albedo.G", "albedo.B", "materialId.Y", "samples.Y"};
  for (const char* c : names) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
  Imf::FrameBuffer fb;
  const size_t f = sizeof(float);
  // OpenEXR addresses a slice by absolute coordinates: the buffer's origin is the data window's.
  const ptrdiff_t origin = ptrdiff_t(win.x0) + ptrdiff_t(win.y0) * ptrdiff_t(w);
  auto slice = [&](const float* base, size_t stride) {
    return Imf::Slice(Imf::FLOAT, (char*)(base - origin * ptrdiff_t(stride)), f * stride, f * stride * size_t(w));
  };
  fb.insert("R", slice(rgba.data() + 0, 4));
  fb.insert("G", slice(rgba.data() + 1, 4));
  fb.insert("B", slice(rgba.data() + 2, 4));
  fb.insert("A", slice(rgba.data() + 3, 4));
  fb.insert("depth.Z", slice(depth.data(), 1));
  fb.insert("normal.X", slice(normal.data() + 0, 3));
  fb.insert("normal.Y", slice(normal.data() + 1, 3));
  fb.insert("normal.Z", slice(normal.data() + 2, 3));
  fb.insert("lod.Y", slice(lod.data(), 1));
  fb.insert("albedo.R", slice(albedo.data() + 0, 3));
  fb.insert("albedo.G", slice(albedo.data() + 1, 3));
  fb.insert("albedo.B", slice(albedo.data() + 2, 3));
  fb.insert("materialId.Y", slice(material.data(), 1));
  fb.insert("samples.Y", slice(samples.data(), 1));
  const std::vector<float> dicings = cost ? cost->dicings() : std::vector<float>{};
  const std::vector<float> seconds = cost ? cost->seconds() : std::vector<float>{};
  if (cost) {
    for (const char* c : {"dicings.Y", "time.Y"}) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
    fb.insert("dicings.Y", slice(dicings.data(), 1));
    fb.insert("time.Y", slice(seconds.data(), 1));
  }
  Imf::OutputFile file(path.c_str(), header);
  file.setFrameBuffer(fb);
  if (h > 0) file.writePixels(h);
}

namespace {

struct PngErrorText {
  char message[200] = "";
};
void pngError(png_structp png, png_const_charp msg) {
  std::snprintf(static_cast<PngErrorText*>(png_get_error_ptr(png))->message, sizeof(PngErrorText::message), "%s", msg);
  png_longjmp(png, 1);
}
void pngWarning(png_structp, png_const_charp) {}

// Holds libpng's setjmp: only trivially destructible locals here, so its longjmp skips no
// C++ destructor.
bool writePngRows(png_structp png, png_infop info, FILE* fp, const uint8_t* rgb, int w, int h) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_init_io(png, fp);
  png_set_IHDR(png, info, png_uint_32(w), png_uint_32(h), 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_sRGB(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
  png_write_info(png, info);
  for (int y = 0; y < h; ++y) png_write_row(png, rgb + size_t(y) * size_t(w) * 3);
  png_write_end(png, nullptr);
  return true;
}

}  // namespace

void writePngPreview(const std::string& path, const Film& film) {
  const int w = film.width(), h = film.height();
  const std::vector<float> rgba = film.beautyRgba();
  std::vector<uint8_t> rgb(size_t(w) * h * 3);
  for (size_t p = 0; p < size_t(w) * h; ++p)
    for (int c = 0; c < 3; ++c) rgb[3 * p + c] = toSrgb8(rgba[4 * p + c]);
  FILE* fp = std::fopen(path.c_str(), "wb");
  if (!fp) throw std::runtime_error(std::strerror(errno));
  PngErrorText error;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &error, pngError, pngWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  const bool ok = png && info && writePngRows(png, info, fp, rgb.data(), w, h);
  if (png) png_destroy_write_struct(&png, info ? &info : nullptr);
  int err = std::ferror(fp) ? errno : 0;
  if (std::fclose(fp) != 0 && err == 0) err = errno;
  if (err) throw std::runtime_error(std::strerror(err));
  if (!ok) throw std::runtime_error(std::string("PNG: ") + (error.message[0] ? error.message : "libpng failed"));
}

namespace {

// The header's data window, as a size.
void dataWindowSize(const Imf::InputFile& file, int& width, int& height) {
  const Imath::Box2i dw = file.header().dataWindow();
  width = dw.max.x - dw.min.x + 1;
  height = dw.max.y - dw.min.y + 1;
}

void checkRgbChannels(const Imf::InputFile& file, const std::string& path, const std::string& what) {
  for (const char* name : {"R", "G", "B"})
    if (!file.header().channels().findChannel(name)) throw InputError(path, "", what + " has no channel " + name);
}

// R, G and B of an opened file whose header has them (openExrInput has bounded its data window).
std::vector<float> readRgb(Imf::InputFile& file, const std::string& path) {
  try {
    const Imath::Box2i dw = file.header().dataWindow();
    int width = 0, height = 0;
    dataWindowSize(file, width, height);
    std::vector<float> rgb(size_t(width) * height * 3, 0.0f);
    Imf::FrameBuffer fb;
    const size_t f = sizeof(float);
    char* base = (char*)(rgb.data()) - (size_t(dw.min.x) + size_t(dw.min.y) * width) * 3 * f;
    for (int c = 0; c < 3; ++c)
      fb.insert(c == 0 ? "R" : (c == 1 ? "G" : "B"), Imf::Slice(Imf::FLOAT, base + c * f, 3 * f, 3 * f * size_t(width)));
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    return rgb;
  } catch (const std::exception& e) {
    throw InputError(path, "", std::string("cannot read EXR: ") + e.what());
  }
}

}  // namespace

std::vector<float> readExrRgb(const std::string& path, int& width, int& height) {
  const auto in = openExrInput(path, "reference image");
  dataWindowSize(*in, width, height);
  checkRgbChannels(*in, path, "reference image");
  return readRgb(*in, path);
}

ExrChannels readExrChannels(const std::string& path, const std::vector<std::string>& names, const std::string& what) {
  const auto in = openExrInput(path, what);
  ExrChannels out;
  dataWindowSize(*in, out.width, out.height);
  out.channels.resize(names.size());
  try {
    const Imath::Box2i dw = in->header().dataWindow();
    const size_t w = size_t(out.width), f = sizeof(float);
    Imf::FrameBuffer fb;
    for (size_t c = 0; c < names.size(); ++c) {
      if (!in->header().channels().findChannel(names[c])) continue;
      out.channels[c].assign(w * size_t(out.height), 0.0f);
      char* base = (char*)(out.channels[c].data()) - (ptrdiff_t(dw.min.x) + ptrdiff_t(dw.min.y) * ptrdiff_t(w)) * ptrdiff_t(f);
      fb.insert(names[c], Imf::Slice(Imf::FLOAT, base, f, f * w));
    }
    in->setFrameBuffer(fb);
    if (out.height > 0) in->readPixels(dw.min.y, dw.max.y);
  } catch (const std::exception& e) {
    throw InputError(path, "", std::string("cannot read EXR: ") + e.what());
  }
  return out;
}

std::vector<float> readExrRgbOfSize(const std::string& path, const std::string& what, int width, int height) {
  const auto in = openExrInput(path, what);
  checkRgbChannels(*in, path, what);
  int w = 0, h = 0;
  dataWindowSize(*in, w, h);
  if (w != width || h != height)
    throw InputError(path, "", what + " is " + std::to_string(w) + "x" + std::to_string(h) + ", the render " +
                                   std::to_string(width) + "x" + std::to_string(height));
  std::vector<float> rgb = readRgb(*in, path);
  // A NaN or an infinity would make every error NaN (or infinite), and a mask's NaN counts as
  // non-zero: refused rather than measured against.
  size_t bad = 0, first = 0;
  for (size_t i = 0; i < rgb.size(); ++i)
    if (!std::isfinite(rgb[i]) && bad++ == 0) first = i;
  if (bad > 0) {
    const size_t pixel = first / 3;
    const char* kind = std::isnan(rgb[first]) ? "NaN" : "infinite";
    throw InputError(path, "", what + " has " + std::to_string(bad) + (bad == 1 ? " value that is" : " values that are") +
                                   " NaN or infinite, the first at pixel (" + std::to_string(pixel % size_t(w)) +
                                   ", " + std::to_string(pixel / size_t(w)) + ") channel " + "RGB"[first % 3] + " (" +
                                   kind + ")");
  }
  return rgb;
}

}  // namespace rayes
