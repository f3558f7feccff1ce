// Writes float OpenEXRs for tests: one channel (height maps, textures, broken-file fixtures) or
// R, G, B (references and masks).
#pragma once
#include <string>
#include <vector>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>

namespace rayes::testing {

inline void writeOneChannelExr(const std::string& path, int w, int h, const char* channel,
                               const std::vector<float>& data) {
  Imf::Header header(w, h);
  header.channels().insert(channel, Imf::Channel(Imf::FLOAT));
  Imf::FrameBuffer fb;
  fb.insert(channel, Imf::Slice(Imf::FLOAT, (char*)data.data(), sizeof(float), sizeof(float) * size_t(w)));
  Imf::OutputFile file(path.c_str(), header);
  file.setFrameBuffer(fb);
  file.writePixels(h);
}

// `rgb` interleaved, w x h; ZIP-compressed (OpenEXR's default), 16 rows per chunk.
inline void writeRgbExr(const std::string& path, int w, int h, const std::vector<float>& rgb) {
  Imf::Header header(w, h);
  for (const char* c : {"R", "G", "B"}) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
  Imf::FrameBuffer fb;
  const size_t px = 3 * sizeof(float);
  for (int c = 0; c < 3; ++c)
    fb.insert(std::string(1, "RGB"[c]), Imf::Slice(Imf::FLOAT, (char*)(rgb.data() + c), px, px * size_t(w)));
  Imf::OutputFile file(path.c_str(), header);
  file.setFrameBuffer(fb);
  file.writePixels(h);
}

}  // namespace rayes::testing
