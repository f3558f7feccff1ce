#include "scene/texture_reader.h"
#include <cmath>
#include <cstdio>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <png.h>

namespace rayes {
namespace {

std::shared_ptr<const Image> readExr(const std::filesystem::path& file) {
  try {
    Imf::InputFile in(file.string().c_str());
    const Imath::Box2i dw = in.header().dataWindow();
    auto im = std::make_shared<Image>();
    im->width = dw.max.x - dw.min.x + 1;
    im->height = dw.max.y - dw.min.y + 1;
    if (im->width <= 0 || im->height <= 0 || int64_t(im->width) * im->height > (int64_t(1) << 28))
      throw InputError(file.string(), "", "image has an empty or huge data window");
    std::vector<float> rgb(size_t(im->width) * im->height * 3, 0.0f);
    const size_t f = sizeof(float);
    char* base = (char*)rgb.data() - (size_t(dw.min.x) + size_t(dw.min.y) * im->width) * 3 * f;
    Imf::FrameBuffer fb;
    const Imf::ChannelList& ch = in.header().channels();
    const bool hasR = ch.findChannel("R"), hasG = ch.findChannel("G"), hasB = ch.findChannel("B"), hasY = ch.findChannel("Y");
    if (!hasR && !hasY) throw InputError(file.string(), "", "image has neither an R nor a Y channel");
    auto slice = [&](int c) { return Imf::Slice(Imf::FLOAT, base + c * f, 3 * f, 3 * f * size_t(im->width)); };
    fb.insert(hasR ? "R" : "Y", slice(0));
    if (hasG) fb.insert("G", slice(1));
    if (hasB) fb.insert("B", slice(2));
    in.setFrameBuffer(fb);
    in.readPixels(dw.min.y, dw.max.y);
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

std::shared_ptr<const Image> readPng(const std::filesystem::path& file) {
  FILE* fp = std::fopen(file.string().c_str(), "rb");
  if (!fp) throw InputError(file.string(), "", "cannot open image");
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  auto im = std::make_shared<Image>();
  std::vector<uint8_t> rows;
  bool ok = png && info;
  if (ok && setjmp(png_jmpbuf(png))) {
    ok = false;
  } else if (ok) {
    png_init_io(png, fp);
    png_read_info(png, info);
    // Everything to 8-bit RGBA.
    png_set_strip_16(png);
    png_set_palette_to_rgb(png);
    png_set_expand_gray_1_2_4_to_8(png);
    png_set_tRNS_to_alpha(png);
    png_set_gray_to_rgb(png);
    png_set_filler(png, 0xff, PNG_FILLER_AFTER);
    png_read_update_info(png, info);
    im->width = int(png_get_image_width(png, info));
    im->height = int(png_get_image_height(png, info));
    if (im->width <= 0 || im->height <= 0 || int64_t(im->width) * im->height > (int64_t(1) << 28)) {
      ok = false;
    } else {
      rows.resize(size_t(im->width) * im->height * 4);
      std::vector<png_bytep> ptrs(size_t(im->height));
      for (int y = 0; y < im->height; ++y) ptrs[size_t(y)] = rows.data() + size_t(y) * im->width * 4;
      png_read_image(png, ptrs.data());
      png_read_end(png, nullptr);
    }
  }
  if (png) png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
  std::fclose(fp);
  if (!ok) throw InputError(file.string(), "", "cannot read PNG image (corrupt, truncated or not a PNG)");
  im->texels.resize(size_t(im->width) * im->height);
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
  if (!std::filesystem::is_regular_file(file)) throw InputError(file.string(), "", "cannot open image");
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
  if (type == "image") {
    r.object(j, ptr, {"type", "file", "scale", "tint"});
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
    if (type == "checker") r.object(j, ptr, {"type", "colors", "scale"});
    else r.object(j, ptr, {"type", "colors", "scale", "octaves"});
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
