// The film: per-pixel sums of path contributions and of the first-hit AOVs, accumulated in a
// fixed order (pixel by pixel, samples in increasing sample index), so the image is
// bit-identical however paths were batched or threaded (docs/design.md, invariant 2).
// Sums are double precision. add*() for different pixels may run in parallel; one pixel's
// samples must be added in order by one thread.
#pragma once
#include <cstdint>
#include <vector>
#include "core/vec.h"

namespace rayes {

struct PixelSample {
  Rgb radiance;
  bool hitSurface = false;  // the camera ray hit something (alpha)
  float depth = 0;          // camera-ray hit distance
  Vec3 normal;              // shading normal at the first hit, facing the camera
  float lod = 0;            // level of detail at the first hit
  Rgb albedo;               // the first hit's BSDF reflectance (Bsdf::reflectance)
  int32_t materialId = -1;  // the first hit's material index
};

class Film {
 public:
  Film(int width, int height);
  int width() const { return width_; }
  int height() const { return height_; }
  void add(uint32_t pixel, const PixelSample& s);
  uint32_t samples(uint32_t pixel) const { return count_[pixel]; }

  // Resolved images (means). Beauty is RGBA, alpha = coverage. AOVs average over the samples
  // that hit a surface (0 where none did).
  std::vector<float> beautyRgba() const;
  std::vector<float> depth() const;
  std::vector<float> normal() const;  // xyz per pixel
  std::vector<float> lod() const;
  std::vector<float> albedo() const;      // rgb per pixel
  std::vector<float> materialId() const;  // of the first sample (in sample order) that hit; -1: none
  std::vector<float> sampleCount() const;

 private:
  int width_, height_;
  std::vector<double> rgb_, alpha_, depth_, normal_, lod_, albedo_;
  std::vector<int32_t> material_;
  std::vector<uint32_t> count_, hits_;
};

}  // namespace rayes
