// Which file the texture cache reads (src/texture/oiio/texture_file.h): plain images converted once
// into the conversion folder and found there afterwards, tiled MIP-mapped files read in place,
// sRGB images decoded to linear, and bad files refused with the file's name.
#include <fstream>
#include <gtest/gtest.h>
#include <OpenImageIO/imageio.h>
#include "core/error.h"
#include "support/temp_folder.h"
#include "support/texture_test_files.h"
#include "texture/oiio/texture_file.h"

namespace rayes {
namespace {

namespace fs = std::filesystem;

std::string inputErrorOf(const fs::path& source, const fs::path& dir) {
  try {
    prepareTextureFile(source, dir, {});
  } catch (const InputError& e) {
    return e.message();
  }
  return "";
}

TEST(TextureFile, APlainImageIsConvertedOnceAndFoundAfterwards) {
  const testing::TempFolder temp;
  testing::writeRgbExr(temp.path("t.exr"), 4, 4, std::vector<Rgb>(16, Rgb{0.5f, 0.25f, 1}));
  std::vector<std::string> notices;
  const auto tell = [&](const std::string& s) { notices.push_back(s); };
  const fs::path dir = temp.path("cache");
  const PreparedTextureFile first = prepareTextureFile(temp.path("t.exr"), dir, tell);
  EXPECT_TRUE(first.converted);
  EXPECT_FALSE(first.inPlace);
  EXPECT_EQ(first.path.parent_path(), dir);
  ASSERT_EQ(notices.size(), 1u);
  EXPECT_NE(notices[0].find("t.exr"), std::string::npos) << notices[0];
  // Another run (another scene naming the same bytes elsewhere) finds the conversion.
  fs::copy_file(temp.path("t.exr"), temp.path("copy.exr"));
  const PreparedTextureFile again = prepareTextureFile(temp.path("t.exr"), dir, tell);
  EXPECT_FALSE(again.converted);
  EXPECT_EQ(again.path, first.path);
  EXPECT_EQ(notices.size(), 1u) << "told once per conversion";
  // Nothing else is left in the folder: no temporaries.
  size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir)) files += e.is_regular_file();
  EXPECT_EQ(files, 1u);
  // The conversion is tiled and MIP-mapped, so it is read in place.
  const PreparedTextureFile converted = prepareTextureFile(first.path, dir, tell);
  EXPECT_TRUE(converted.inPlace);
  EXPECT_EQ(converted.path, first.path);
  auto in = OIIO::ImageInput::open(first.path.string());
  ASSERT_TRUE(in);
  EXPECT_GT(in->spec().tile_width, 0);
  EXPECT_TRUE(in->seek_subimage(0, 2));
}

void writeGreyPng(const fs::path& path, int w, int h, const std::vector<uint8_t>& grey) {
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out && out->open(path.string(), OIIO::ImageSpec(w, h, 1, OIIO::TypeDesc::UINT8)));
  out->write_image(OIIO::TypeDesc::UINT8, grey.data());
  out->close();
}

TEST(TextureFile, AnEditedFileIsConvertedAgainFromItsNewPixels) {
  const testing::TempFolder temp;
  const fs::path dir = temp.path("cache");
  for (const char* name : {"t.exr", "t.png"}) {
    const bool png = fs::path(name).extension() == ".png";
    if (png) writeGreyPng(temp.path(name), 2, 2, {255, 255, 255, 255});
    else testing::writeRgbExr(temp.path(name), 2, 2, std::vector<Rgb>(4, Rgb{1, 1, 1}));
    const fs::path a = prepareTextureFile(temp.path(name), dir, {}).path;
    // Rewritten under the same name with another size: the conversion reads the new file, not
    // what a cache kept of the old one (read through OpenImageIO's shared ImageCache, the PNG
    // was decoded with the old layout and OpenImageIO's buffers were corrupted).
    if (png) writeGreyPng(temp.path(name), 3, 1, {255, 0, 255});
    else testing::writeRgbExr(temp.path(name), 3, 1, {Rgb{1, 1, 1}, Rgb{0, 0, 0}, Rgb{1, 1, 1}});
    const PreparedTextureFile b = prepareTextureFile(temp.path(name), dir, {});
    EXPECT_TRUE(b.converted) << name;
    EXPECT_NE(a, b.path) << name;
    auto in = OIIO::ImageInput::open(b.path.string());
    ASSERT_TRUE(in);
    ASSERT_EQ(in->spec().width, 3) << name;
    ASSERT_EQ(in->spec().height, 1) << name;
    std::vector<float> texels(3 * size_t(in->spec().nchannels));
    ASSERT_TRUE(in->read_image(0, 0, 0, in->spec().nchannels, OIIO::TypeDesc::FLOAT, texels.data()));
    const int n = in->spec().nchannels;
    EXPECT_EQ(texels[0], 1.0f) << name;
    EXPECT_EQ(texels[size_t(n)], 0.0f) << name;
    EXPECT_EQ(texels[2 * size_t(n)], 1.0f) << name;
  }
}

TEST(TextureFile, AConversionBeyondItsMemoryIsAResourceLimitNamingTheFile) {
  const testing::TempFolder temp;
  const fs::path dir = temp.path("cache");
  testing::writeRgbExr(temp.path("big.exr"), 64, 64, std::vector<Rgb>(64 * 64, Rgb{0.5f, 0.5f, 0.5f}));
  // 64 x 64 x 3 floats: 48 KiB of pixels, a 64 MiB staging buffer, a 64 KiB float pyramid.
  try {
    prepareTextureFile(temp.path("big.exr"), dir, {}, uint64_t(32) << 20);
    ADD_FAILURE() << "no error";
  } catch (const ResourceError& e) {
    EXPECT_EQ(e.file(), temp.path("big.exr"));
    EXPECT_NE(std::string(e.what()).find("maketx"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir)) << "nothing written before the check";
  // With the memory it needs the same file converts, and once converted it needs none.
  const fs::path made = prepareTextureFile(temp.path("big.exr"), dir, {}, uint64_t(80) << 20).path;
  EXPECT_EQ(prepareTextureFile(temp.path("big.exr"), dir, {}, 1).path, made);
}

TEST(TextureFile, PngIsDecodedFromSrgbToLinear) {
  const testing::TempFolder temp;
  auto out = OIIO::ImageOutput::create(temp.path("s.png"));
  ASSERT_TRUE(out);
  ASSERT_TRUE(out->open(temp.path("s.png"), OIIO::ImageSpec(4, 1, 3, OIIO::TypeDesc::UINT8)));
  const uint8_t px[12] = {0, 0, 0, 10, 10, 10, 128, 128, 128, 255, 255, 255};
  out->write_image(OIIO::TypeDesc::UINT8, px);
  out->close();
  const auto image = testing::quietCache(temp.dir())->open(temp.path("s.png"));
  for (int i = 0; i < 4; ++i) {
    const double s = px[3 * i] / 255.0;
    const double linear = s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
    // Stored as half floats: within half an ulp of 11 bits.
    EXPECT_NEAR(image->closest((i + 0.5f) / 4, 0.5f).y, linear, linear * 0x1p-11 + 1e-7) << int(px[3 * i]);
  }
}

TEST(TextureFile, ADataWindowAwayFromTheOriginIsTheWholeTexture) {
  const testing::TempFolder temp;
  OIIO::ImageSpec spec(3, 2, 1, OIIO::TypeDesc::FLOAT);
  spec.x = 5;
  spec.y = 7;
  spec.full_x = spec.full_y = -10;
  spec.full_width = spec.full_height = 21;
  auto out = OIIO::ImageOutput::create(temp.path("w.exr"));
  ASSERT_TRUE(out->open(temp.path("w.exr"), spec));
  const float y[6] = {0.0f, 0.1f, 0.2f, 0.3f, 0.4f, 0.5f};
  out->write_image(OIIO::TypeDesc::FLOAT, y);
  out->close();
  const auto image = testing::quietCache(temp.dir())->open(temp.path("w.exr"));
  ASSERT_EQ(image->width(), 3);
  ASSERT_EQ(image->height(), 2);
  for (int p = 0; p < 6; ++p) EXPECT_EQ(image->closest((p % 3 + 0.5f) / 3, (p / 3 + 0.5f) / 2).x, y[p]) << p;
}

TEST(TextureFile, BadFilesAreRefusedNamingTheFile) {
  const testing::TempFolder temp;
  const fs::path dir = temp.path("cache");
  std::ofstream(temp.path("garbage.png")) << "not a png";
  EXPECT_NE(inputErrorOf(temp.path("garbage.png"), dir).find("garbage.png: not an image"), std::string::npos)
      << inputErrorOf(temp.path("garbage.png"), dir);
  EXPECT_NE(inputErrorOf(temp.path("missing.exr"), dir).find("missing.exr: cannot open image"), std::string::npos);
  EXPECT_NE(inputErrorOf(temp.dir(), dir).find("a directory"), std::string::npos);
  // A truncated image: the header is there, the pixels are not.
  testing::writeRgbExr(temp.path("whole.exr"), 64, 64, std::vector<Rgb>(64 * 64, Rgb{0.5f, 0.5f, 0.5f}));
  const auto bytes = fs::file_size(temp.path("whole.exr"));
  fs::copy_file(temp.path("whole.exr"), temp.path("cut.exr"));
  fs::resize_file(temp.path("cut.exr"), bytes / 2);
  const std::string cut = inputErrorOf(temp.path("cut.exr"), dir);
  EXPECT_NE(cut.find("cut.exr"), std::string::npos) << cut;
  EXPECT_FALSE(cut.empty());
  // Nothing is left behind by the failures.
  if (fs::exists(dir))
    for (const auto& e : fs::directory_iterator(dir)) ADD_FAILURE() << "left " << e.path();
}

TEST(TextureFile, AConversionFolderThatCannotBeMadeNamesTheOption) {
  const testing::TempFolder temp;
  testing::writeRgbExr(temp.path("t.exr"), 2, 2, std::vector<Rgb>(4, Rgb{1, 1, 1}));
  std::ofstream(temp.path("file")) << "x";
  try {
    prepareTextureFile(temp.path("t.exr"), temp.path("file/sub"), {});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "--texture-cache-dir");
  }
}

}  // namespace
}  // namespace rayes
