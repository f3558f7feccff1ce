// Writes three float channels R, G, B (interleaved, w x h) to an OpenEXR file: the bench helpers'
// images (error masks, closed-form references). Throws the library's exception on failure.
#pragma once
#include <string>
#include <vector>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>

namespace rayes {

inline void writeRgbExr(const std::string& path, int w, int h, std::vector<float>& rgb) {
  Imf::Header header(w, h);
  for (const char* c : {"R", "G", "B"}) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
  Imf::FrameBuffer fb;
  const size_t px = 3 * sizeof(float);
  for (int c = 0; c < 3; ++c)
    fb.insert(std::string(1, "RGB"[c]), Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(rgb.data() + c), px, px * w));
  Imf::OutputFile file(path.c_str(), header);
  file.setFrameBuffer(fb);
  file.writePixels(h);
}

}  // namespace rayes
