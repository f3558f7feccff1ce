#include "scene/texture_reader.h"
#include <cmath>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <png.h>
#include "core/text_file.h"
#include "scene/exr_input.h"

namespace rayes {
namespace {

std::shared_ptr<const Image> readExr(const std::filesystem::path& file) {
  const auto in = openExrInput(file, "image");
  try {
    const Imath::Box2i dw = in->header().dataWindow();
    auto im = std::make_shared<Image>();
    im->width = dw.max.x - dw.min.x + 1;
    im->height = dw.max.y - dw.min.y + 1;
    std::vector<float> rgb(size_t(im->width) * im->height * 3, 0.0f);
    const size_t f = sizeof(float);
    Imf::FrameBuffer fb;
    const Imf::ChannelList& ch = in->header().channels();
    const bool hasR = ch.findChannel("R"), hasG = ch.findChannel("G"), hasB = ch.findChannel("B"), hasY = ch.findChannel("Y");
    if (!hasR && !hasY) throw InputError(file.string(), "", "image has neither an R nor a Y channel");
    // Slice::Make places the data window's origin at rgb[c] (OpenEXR does the pointer arithmetic:
    // moving a pointer outside the vector here, for a window not at 0, is undefined behaviour;
    // found by exr_fuzz).
    auto slice = [&](int c) { return Imf::Slice::Make(Imf::FLOAT, rgb.data() + c, dw, 3 * f, 3 * f * size_t(im->width)); };
    fb.insert(hasR ? "R" : "Y", slice(0));
    if (hasG) fb.insert("G", slice(1));
    if (hasB) fb.insert("B", slice(2));
    in->setFrameBuffer(fb);
    in->readPixels(dw.min.y, dw.max.y);
    // Missing G or B repeat the first channel (grey images).
    im->texels.resize(size_t(im->width) * im->height);
    for (size_t p = 0; p < im->texels.size(); ++p) {
      Rgb c{rgb[3 * p], rgb[3 * p + 1], rgb[3 * p + 2]};
      if (!hasG) c.y = c.x;
      if (!hasB) c.z = c.x;
      for (int k = 0; k < 3; ++k)
        if (!std::isfinite(c[k]) || c[k] < 0) c[k] = 0;  // bad texels become black, never NaN
      im->texels[p] = c;
    }
    return im;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(file.string(), "", std::string("cannot read EXR image: ") + e.what());
  }
}

float srgbToLinear(uint8_t v) {
  const float s = v / 255.0f;
  return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f);
}

// libpng reports errors by longjmp. The functions holding a setjmp below keep only trivially
// destructible locals, so no C++ destructor is ever skipped; the error text is kept for the
// message and nothing is printed.
struct PngErrorState {
  char message[200] = "";
};

void pngError(png_structp png, png_const_charp msg) {
  auto* state = static_cast<PngErrorState*>(png_get_error_ptr(png));
  std::snprintf(state->message, sizeof state->message, "%s", msg);
  png_longjmp(png, 1);
}
void pngWarning(png_structp, png_const_charp) {}

// Reads the header and sets up the conversion to 8-bit RGBA. False on a libpng error.
bool readPngHeader(png_structp png, png_infop info, FILE* fp, png_uint_32* width, png_uint_32* height) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_init_io(png, fp);
  png_read_info(png, info);
  png_set_strip_16(png);
  png_set_palette_to_rgb(png);
  png_set_expand_gray_1_2_4_to_8(png);
  png_set_tRNS_to_alpha(png);
  png_set_gray_to_rgb(png);
  png_set_filler(png, 0xff, PNG_FILLER_AFTER);
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  *width = png_get_image_width(png, info);
  *height = png_get_image_height(png, info);
  return true;
}

// Reads every row (all interlace passes) into `rows` (height rows of width * 4 bytes).
bool readPngRows(png_structp png, png_infop info, uint8_t* rows, png_uint_32 width, png_uint_32 height) {
  if (setjmp(png_jmpbuf(png))) return false;
  const int passes = png_set_interlace_handling(png);
  for (int pass = 0; pass < passes; ++pass)
    for (png_uint_32 y = 0; y < height; ++y) png_read_row(png, rows + size_t(y) * width * 4, nullptr);
  png_read_end(png, nullptr);
  return true;
}

std::shared_ptr<const Image> readPng(const std::filesystem::path& file) {
  const std::string path = file.string();
  const uint64_t fileBytes = checkInputFile(path, "image");
  FILE* fp = std::fopen(path.c_str(), "rb");
  if (!fp) throw InputError(path, "", std::string("cannot open image: ") + std::strerror(errno));
  PngErrorState error;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &error, pngError, pngWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  png_uint_32 width = 0, height = 0;
  bool ok = png && info && readPngHeader(png, info, fp, &width, &height);
  std::string problem = error.message;
  std::vector<uint8_t> rows;
  if (ok) {
    // Deflate expands at most 1032:1, so a header claiming more pixels than the file can hold
    // is a lie: refuse it before allocating.
    const uint64_t rawBytes = uint64_t(height) * (uint64_t(width) * 8 + 1);
    if (width == 0 || height == 0 || uint64_t(width) * height > (uint64_t(1) << 28)) {
      ok = false;
      problem = "unsupported size " + std::to_string(width) + "x" + std::to_string(height) + " (at most 2^28 pixels)";
    } else if (rawBytes > 1032 * fileBytes + 65536) {
      ok = false;
      problem = "the header claims " + std::to_string(width) + "x" + std::to_string(height) + " pixels, more than its " +
                std::to_string(fileBytes) + " bytes can hold";
    } else {
      rows.resize(size_t(width) * height * 4);
      ok = readPngRows(png, info, rows.data(), width, height);
      problem = error.message;
    }
  }
  if (png) png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
  std::fclose(fp);
  if (!ok) throw InputError(path, "", "cannot read PNG image: " + (problem.empty() ? "not a PNG file" : problem));
  auto im = std::make_shared<Image>();
  im->width = int(width);
  im->height = int(height);
  im->texels.resize(size_t(width) * height);
  for (size_t p = 0; p < im->texels.size(); ++p)
    im->texels[p] = {srgbToLinear(rows[4 * p]), srgbToLinear(rows[4 * p + 1]), srgbToLinear(rows[4 * p + 2])};
  return im;
}

std::string lowerExtension(const std::filesystem::path& f) {
  std::string e = f.extension().string();
  for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

}  // namespace

std::shared_ptr<const Image> readImageFile(const std::filesystem::path& file) {
  checkInputFile(file.string(), "image");
  const std::string ext = lowerExtension(file);
  if (ext == ".exr") return readExr(file);
  if (ext == ".png") return readPng(file);
  throw InputError(file.string(), "", "unknown image format '" + ext + "' (expected .exr or .png)");
}

ColorParam readColorParam(const JsonReader& r, const json& j, const std::string& ptr,
                          const std::filesystem::path& sceneDir, bool reflectance) {
  if (!j.is_object()) return ColorParam(r.color(j, ptr, reflectance));
  const std::string type = r.string(r.member(j, ptr, "type"), ptr + "/type");
  auto tex = std::make_shared<Texture>();
  ColorParam c(Rgb{1, 1, 1});
  if (j.contains("scale")) {
    tex->scale = float(r.number(j["scale"], ptr + "/scale"));
    if (!(tex->scale > 0)) r.fail(ptr + "/scale", "the texture scale must be positive");
  }
  if (j.contains("coordinates")) {  // "patch" (the default) or "uv"
    const std::string coords = r.string(j["coordinates"], ptr + "/coordinates");
    if (coords == "uv") tex->coordinates = Texture::Coordinates::Uv;
    else if (coords != "patch") r.fail(ptr + "/coordinates", "unknown coordinates '" + coords + "' (expected patch or uv)");
  }
  if (type == "image") {
    r.object(j, ptr, {"type", "file", "scale", "tint", "coordinates"});
    const std::string f = r.string(r.member(j, ptr, "file"), ptr + "/file");
    const std::filesystem::path fp = std::filesystem::path(f).is_absolute() ? std::filesystem::path(f) : sceneDir / f;
    tex->kind = Texture::Kind::Image;
    try {
      auto im = readImageFile(fp);
      if (reflectance) {
        auto clamped = std::make_shared<Image>(*im);
        for (Rgb& t : clamped->texels) t = vmin(t, Rgb{1, 1, 1});
        im = clamped;
      }
      tex->image = im;
    } catch (const InputError& e) {
      r.fail(ptr + "/file", e.message());
    }
    if (j.contains("tint")) c.value = r.color(j["tint"], ptr + "/tint", reflectance);
  } else if (type == "checker" || type == "noise") {
    if (type == "checker") r.object(j, ptr, {"type", "colors", "scale", "coordinates"});
    else r.object(j, ptr, {"type", "colors", "scale", "octaves", "coordinates"});
    tex->kind = type == "checker" ? Texture::Kind::Checker : Texture::Kind::Noise;
    const json& cs = r.member(j, ptr, "colors");
    if (!cs.is_array() || cs.size() != 2) r.fail(ptr + "/colors", "expected two colours");
    tex->color0 = r.color(cs[0], ptr + "/colors/0", reflectance);
    tex->color1 = r.color(cs[1], ptr + "/colors/1", reflectance);
    if (j.contains("octaves")) {
      tex->octaves = r.integer(j["octaves"], ptr + "/octaves");
      if (tex->octaves < 1 || tex->octaves > 16) r.fail(ptr + "/octaves", "must be in [1, 16]");
    }
  } else {
    r.fail(ptr + "/type", "unknown texture type '" + type + "' (expected image, checker or noise)");
  }
  c.texture = tex;
  return c;
}

}  // namespace rayes
