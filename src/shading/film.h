// The film: per-pixel sums of path contributions and of the first-hit AOVs, accumulated in a
// fixed order (pixel by pixel, samples in increasing sample index), so the image is
// bit-identical however paths were batched or threaded (docs/design.md, invariant 2).
// Sums are double precision. add*() for different pixels may run in parallel; one pixel's
// samples must be added in order by one thread. The radiance sums (rgb, count) and the AOV sums
// (alpha, depth, normal, lod, albedo, material, hits) are separate arrays, each in sample order
// on its own: a path's first hit may be added when its camera ray is shaded (addFirstHit) and its
// radiance when the path ends (addRadiance), with the bits of adding both at once (add).
//
// Window: a film holds the sums of a rectangle of the full image only (--crop, a part of a
// farm split: PixelWindow), by default the whole image. Pixels are always named by their index
// in the full image (y * fullWidth + x), so a pixel's samples, and their sums, are the same in
// any window; the resolved images are the window's size.
//
// Splats (light tracing) go to a separate buffer: a light path contributes to whichever pixel
// it reaches, so the buffer is an estimate of the whole image per light path. The resolved
// image adds it scaled by 1 / (light paths per pixel so far) = full pixels / splatPaths. The
// buffer is an exact accumulator: fixed point with kSplatFractionBits fractional bits in a
// signed 128-bit integer per channel (a splat is rounded once, to 2^-64, as it arrives; sums of
// such numbers are associative), so splats may arrive in any order and films holding disjoint
// sets of light paths add up (merge) to the same bits as one film that took them all. Range:
// |sum| < 2^63 (about 9.2e18) per pixel and channel; a splat or a sum beyond it saturates at
// the limit and is counted (splatSaturations(); the stats' film.splat_saturations).
#pragma once
#include <cstdint>
#include <vector>
#include "core/vec.h"

namespace rayes {

// A rectangle of the full image: columns [x0, x1), rows [y0, y1).
struct PixelWindow {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  int width() const { return x1 - x0; }
  int height() const { return y1 - y0; }
  uint64_t pixels() const { return uint64_t(width()) * uint64_t(height()); }
  bool empty() const { return x1 <= x0 || y1 <= y0; }
  bool contains(int x, int y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
  bool inside(const PixelWindow& o) const { return x0 >= o.x0 && y0 >= o.y0 && x1 <= o.x1 && y1 <= o.y1; }
  bool operator==(const PixelWindow&) const = default;
  static PixelWindow whole(int width, int height) { return {0, 0, width, height}; }
};

// What a camera path's first hit gives the AOVs (added when the camera generation is shaded).
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
  // The whole image of width x height pixels, or only `window` of it.
  Film(int width, int height);
  Film(int width, int height, PixelWindow window);
  int fullWidth() const { return fullWidth_; }
  int fullHeight() const { return fullHeight_; }
  const PixelWindow& window() const { return window_; }
  // The resolved images' size: the window's.
  int width() const { return window_.width(); }
  int height() const { return window_.height(); }
  // Whether the full-image pixel index lies in the window.
  bool contains(uint32_t pixel) const {
    return window_.contains(int(pixel % uint32_t(fullWidth_)), int(pixel / uint32_t(fullWidth_)));
  }
  // `pixel` is a full-image index inside the window. add() is addFirstHit() and addRadiance().
  void add(uint32_t pixel, const PixelSample& s) {
    addFirstHit(pixel, s);
    addRadiance(pixel, s.radiance);
  }
  void addFirstHit(uint32_t pixel, const FirstHit& h);  // the AOV sums (nothing for a miss)
  void addRadiance(uint32_t pixel, Rgb radiance);       // the beauty sum and the sample count
  uint32_t samples(uint32_t pixel) const { return sums_.count[index(pixel)]; }
  void addSplat(uint32_t pixel, Rgb value);
  // `paths` more light paths have been traced (whether or not they splatted anything).
  void countSplatPaths(uint64_t paths) { sums_.splatPaths += paths; }
  uint64_t splatSaturations() const { return sums_.splatSaturations; }

  // Resolved images (means) of the window. Beauty is RGBA, alpha = coverage (1 where no
  // camera sample was taken: light tracing knows nothing of coverage). AOVs average over the
  // samples that hit a surface (0 where none did).
  std::vector<float> beautyRgba() const;
  std::vector<float> depth() const;
  std::vector<float> normal() const;  // xyz per pixel
  std::vector<float> lod() const;
  std::vector<float> albedo() const;      // rgb per pixel
  std::vector<float> materialId() const;  // of the first sample (in sample order) that hit; -1: none
  std::vector<float> sampleCount() const;
  // Bytes of the sums held (for the stats' memory by owner).
  size_t bytes() const;

  // The raw sums, per pixel of the window in row order (the film file reads and writes them
  // bit for bit: app/film_file.h). Their sizes are fixed by the window.
  static constexpr int kSplatFractionBits = 64;
  struct Sums {
    std::vector<double> rgb, alpha, depth, normal, lod, albedo;  // rgb, normal, albedo: 3 per pixel
    std::vector<int32_t> material;
    std::vector<uint32_t> count, hits;
    std::vector<__int128> splat;  // 3 per pixel, fixed point (kSplatFractionBits)
    uint64_t splatPaths = 0, splatSaturations = 0;
  };
  const Sums& sums() const { return sums_; }
  Sums& sums() { return sums_; }
  // Adds the sums of `part`, a film of the same full image whose window lies inside this one's
  // (merging the parts of a farm split). Splats and light paths add exactly; a pixel's camera
  // samples must come from one of the two films only (pixel bands), so its sums are copied
  // bit for bit. Returns false, adding nothing, if the sizes differ, the window is not inside,
  // or a pixel has camera samples in both.
  bool addFilm(const Film& part);

 private:
  size_t index(uint32_t pixel) const {
    if (wholeImage_) return pixel;
    const uint32_t x = pixel % uint32_t(fullWidth_), y = pixel / uint32_t(fullWidth_);
    return size_t(y - uint32_t(window_.y0)) * size_t(window_.width()) + (x - uint32_t(window_.x0));
  }

  int fullWidth_, fullHeight_;
  PixelWindow window_;
  bool wholeImage_;
  Sums sums_;
};

}  // namespace rayes
