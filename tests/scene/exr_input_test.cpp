// openExrInput (scene/exr_input.h): the checks made before OpenEXR allocates anything for a file.
#include <gtest/gtest.h>
#include <gmock/gmock.h>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <unistd.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfMultiPartOutputFile.h>
#include <ImfOutputFile.h>
#include <ImfOutputPart.h>
#include <ImfPartType.h>
#include "core/error.h"
#include "scene/exr_input.h"

namespace rayes {
namespace {
using ::testing::HasSubstr;

std::string tempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("rayes_exr_input_test_" + std::to_string(getpid()) + name)).string();
}

std::string errorOf(const std::string& path) {
  try {
    openExrInput(path, "image");
  } catch (const InputError& e) {
    return e.message();
  }
  return "";
}

TEST(ExrInput, AttributeLargerThanTheFileIsRefusedBeforeOpenExrAllocatesIt) {
  // OpenEXR 3.1 would allocate the declared 2^31 - 1 bytes of this unknown attribute type.
  const std::string path = tempPath("huge-attribute.exr");
  std::string bytes("\x76\x2f\x31\x01\x02\x00\x00\x00", 8);
  bytes += std::string("junk\0bogus\0", 11) + std::string("\xff\xff\xff\x7f", 4) + "only a few bytes";
  std::ofstream(path, std::ios::binary) << bytes;
  const std::string e = errorOf(path);
  EXPECT_THAT(e, HasSubstr(path));
  EXPECT_THAT(e, HasSubstr("attribute 'junk' claims 2147483647 bytes"));
  std::remove(path.c_str());
}

TEST(ExrInput, PreviewLargerThanTheFileIsRefused) {
  // A preview image's pixels are allocated from its width and height, whatever its size says.
  const std::string path = tempPath("huge-preview.exr");
  std::string bytes("\x76\x2f\x31\x01\x02\x00\x00\x00", 8);
  bytes += std::string("preview\0preview\0", 16) + std::string("\x08\0\0\0\xff\xff\0\0\xff\xff\0\0", 12) + "xyz";
  std::ofstream(path, std::ios::binary) << bytes;
  EXPECT_THAT(errorOf(path), HasSubstr("attribute 'preview' claims 17179344900 bytes"));
  std::remove(path.c_str());
}

TEST(ExrInput, MultiPartHeadersAreWalkedToTheirEnd) {
  // Two parts: the walk must step over both headers and the empty one that ends them.
  const std::string path = tempPath("two-parts.exr");
  std::vector<Imf::Header> headers(2, Imf::Header(2, 2));
  for (int p = 0; p < 2; ++p) {
    headers[size_t(p)].channels().insert("Y", Imf::Channel(Imf::FLOAT));
    headers[size_t(p)].setName("part" + std::to_string(p));
    headers[size_t(p)].setType(Imf::SCANLINEIMAGE);
  }
  const std::vector<float> y{0, 1, 2, 3};
  {
    Imf::MultiPartOutputFile file(path.c_str(), headers.data(), 2);
    for (int p = 0; p < 2; ++p) {
      Imf::OutputPart part(file, p);
      Imf::FrameBuffer fb;
      fb.insert("Y", Imf::Slice(Imf::FLOAT, (char*)y.data(), sizeof(float), 2 * sizeof(float)));
      part.setFrameBuffer(fb);
      part.writePixels(2);
    }
  }
  EXPECT_EQ(errorOf(path), "");
  // The same file cut inside its second header: OpenEXR's own error, still an InputError.
  std::filesystem::resize_file(path, 80);
  EXPECT_THAT(errorOf(path), HasSubstr(path));
  std::remove(path.c_str());
}

}  // namespace
}  // namespace rayes
