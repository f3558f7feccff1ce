// The film: per-pixel sums of path contributions and of the first-hit AOVs, accumulated in a
// fixed order (pixel by pixel, samples in increasing sample index), so the image is
// bit-identical however paths were batched or threaded (docs/design.md, invariant 2).
// Sums are double precision. add*() for different pixels may run in parallel; one pixel's
// samples must be added in order by one thread.
//
// Splats (light tracing) go to a separate buffer: a light path contributes to whichever pixel
// it reaches, so the buffer is an estimate of the whole image per light path. The resolved
// image adds it scaled by 1 / (light paths per pixel so far) = pixels / splatPaths; the caller
// adds splats in an order fixed by path ids (the light tracer sorts them per batch).
#pragma once
#include <cstdint>
#include <vector>
#include "core/vec.h"

namespace rayes {

// What a camera path's first hit gives the AOVs (kept per path while the path is traced).
struct FirstHit {
  bool hitSurface = false;  // the camera ray hit something (alpha)
  float depth = 0;          // camera-ray hit distance
  Vec3 normal;              // shading normal at the first hit, facing the camera
  float lod = 0;            // level of detail at the first hit
  Rgb albedo;               // the first hit's BSDF reflectance (Bsdf::reflectance)
  int32_t materialId = -1;  // the first hit's material index
};

struct PixelSample : FirstHit {
  Rgb radiance;
};

class Film {
 public:
  Film(int width, int height);
  int width() const { return width_; }
  int height() const { return height_; }
  void add(uint32_t pixel, const PixelSample& s);
  uint32_t samples(uint32_t pixel) const { return count_[pixel]; }
  void addSplat(uint32_t pixel, Rgb value);
  // `paths` more light paths have been traced (whether or not they splatted anything).
  void countSplatPaths(uint64_t paths) { splatPaths_ += paths; }

  // Resolved images (means). Beauty is RGBA, alpha = coverage (1 where no camera sample was
  // taken: light tracing knows nothing of coverage). AOVs average over the samples that hit a
  // surface (0 where none did).
  std::vector<float> beautyRgba() const;
  std::vector<float> depth() const;
  std::vector<float> normal() const;  // xyz per pixel
  std::vector<float> lod() const;
  std::vector<float> albedo() const;      // rgb per pixel
  std::vector<float> materialId() const;  // of the first sample (in sample order) that hit; -1: none
  std::vector<float> sampleCount() const;
  // Bytes of the sums held (for the stats' memory by owner).
  size_t bytes() const;

 private:
  int width_, height_;
  std::vector<double> rgb_, alpha_, depth_, normal_, lod_, albedo_;
  std::vector<int32_t> material_;
  std::vector<uint32_t> count_, hits_;
  std::vector<double> splat_;
  uint64_t splatPaths_ = 0;
};

}  // namespace rayes
