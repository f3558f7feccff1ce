// Writes a one-channel float OpenEXR for tests (height maps, textures, broken-file fixtures).
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

}  // namespace rayes::testing
