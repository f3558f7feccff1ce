// Reads every channel of an OpenEXR (as written by rayes: 32-bit float) with its data and
// display windows, for tests that compare images bit for bit.
#pragma once
#include <cstring>
#include <map>
#include <string>
#include <vector>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>

namespace rayes::testing {

struct ExrImage {
  int dataX0 = 0, dataY0 = 0, width = 0, height = 0;  // the data window
  int displayWidth = 0, displayHeight = 0;
  std::map<std::string, std::vector<float>> channels;  // row order over the data window
  // Channel `c` at absolute pixel (x, y) of the display window.
  float at(const std::string& c, int x, int y) const {
    return channels.at(c)[size_t(y - dataY0) * size_t(width) + size_t(x - dataX0)];
  }
  // Every channel's bits equal.
  bool sameBits(const ExrImage& o) const {
    if (channels.size() != o.channels.size()) return false;
    for (const auto& [name, v] : channels) {
      const auto it = o.channels.find(name);
      if (it == o.channels.end() || it->second.size() != v.size() ||
          std::memcmp(v.data(), it->second.data(), v.size() * sizeof(float)) != 0)
        return false;
    }
    return true;
  }
};

inline ExrImage readExrImage(const std::string& path) {
  Imf::InputFile file(path.c_str());
  const Imath::Box2i dw = file.header().dataWindow(), disp = file.header().displayWindow();
  ExrImage im;
  im.dataX0 = dw.min.x;
  im.dataY0 = dw.min.y;
  im.width = dw.max.x - dw.min.x + 1;
  im.height = dw.max.y - dw.min.y + 1;
  im.displayWidth = disp.max.x - disp.min.x + 1;
  im.displayHeight = disp.max.y - disp.min.y + 1;
  Imf::FrameBuffer fb;
  for (auto c = file.header().channels().begin(); c != file.header().channels().end(); ++c) {
    std::vector<float>& v = im.channels[c.name()];
    v.assign(size_t(im.width) * size_t(im.height), 0.0f);
    char* base = (char*)v.data() - (ptrdiff_t(dw.min.x) + ptrdiff_t(dw.min.y) * im.width) * ptrdiff_t(sizeof(float));
    fb.insert(c.name(), Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * size_t(im.width)));
  }
  file.setFrameBuffer(fb);
  file.readPixels(dw.min.y, dw.max.y);
  return im;
}

}  // namespace rayes::testing
