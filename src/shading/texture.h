// Textures: colour functions of a surface point, read at a TextureQuery (shading/texture_query.h):
// the patch parameters (u, v) of a hit (RayHit::u, v) or the leaf's uv set, as `coordinates` says.
// An image (filtered over the query's footprint through the render's texture cache,
// texture/texture_cache.h; repeat wrapping; image row 0 at v = 1 so the image appears upright
// when v points up), a checkerboard, or fractal value noise blending two colours. The
// checkerboard and the noise are filtered over the query's footprint too (its axes in the
// coordinates read): the checkerboard box-filtered exactly over boxes that cover the footprint's
// parallelogram (checkerFootprintWeight), the noise's octaves finer than the footprint faded to
// their mean; a zero footprint is the point sample, bit for bit.
// Images are opened by the scene loader (src/scene/texture_reader.cpp); their texels are linear
// RGB. Immutable after construction; eval() is const and thread-safe.
#pragma once
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>
#include "core/vec.h"
#include "shading/texture_query.h"
#include "texture/texture_cache.h"

namespace rayes {

struct Texture {
  enum class Kind { Image, Checker, Noise };
  // Which coordinates the texture reads: the patch parameters, or the leaf's uv set (a leaf
  // without one reads its patch parameters).
  enum class Coordinates { Patch, Uv };
  Kind kind = Kind::Checker;
  Coordinates coordinates = Coordinates::Patch;
  Rgb color0{0, 0, 0}, color1{1, 1, 1};  // checker squares / noise 0 and 1
  float scale = 1;                       // repetitions per unit of (u, v)
  int octaves = 4;                       // noise
  std::shared_ptr<const TextureImage> image;  // Kind::Image
  float maxValue = std::numeric_limits<float>::infinity();  // an image's filtered values are clamped to it (reflectances: 1)

  Rgb eval(const TextureQuery& q) const;
  // A point sample at patch parameters (u, v).
  Rgb eval(float u, float v) const { return eval(TextureQuery::at(u, v)); }
  // Fractal value noise in [0, 1] (public for tests). With a footprint `width` > 0 (in noise
  // units), the octaves finer than it fade to their mean: octave o (lattice spacing 2^-o) is
  // whole while its spacing is at least 2 width and gone at spacing width, linearly in
  // log2(spacing). width <= 0: every octave, the point sample.
  static float noise(float x, float y, int octaves, float width = 0);
  // The weight of color1 in the checkerboard's mean over the footprint parallelogram at (x, y)
  // with full-width axes (ax, ay), (bx, by), in checks. Over one box [x ± hx] x [y ± hy] the
  // mean is exact and closed form: (1 - m(x, hx) m(y, hy)) / 2, m the mean of the ±1 square
  // wave (squareWaveMean). The parallelogram is covered by n = checkerProbes(L, |S|) boxes
  // along the longer axis L, centred at (x, y) + ((k + 1/2) / n - 1/2) L, each the box around its 1/n of the
  // parallelogram (half-widths (|L| / n + |S|) / 2 per coordinate), averaged -- so a slanted,
  // stretched footprint (a grazing ray off the image's centre column) is not widened to the
  // box around all of it, which blurs across the stretch. Axis-aligned footprints give the
  // single box exactly. In [0, 1]; finite for any input.
  static float checkerFootprintWeight(float x, float y, float ax, float ay, float bx, float by);
  // ceil(min(|lx|, |ly|) / short) in [1, kMaxCheckerProbes]: as many boxes as the long axis's
  // slant off the coordinate axes needs (an axis-aligned footprint: one, the exact box).
  static constexpr int kMaxCheckerProbes = 16;
  static int checkerProbes(float lx, float ly, float shortAxis);
  // The mean of (-1)^floor(t) over [x - h, x + h]: (T(x + h) - T(x - h)) / 2h with T the
  // triangle wave; the point value when the interval lies in one cell. In [-1, 1]; finite for
  // any finite x and any h.
  static double squareWaveMean(double x, double h);
};

}  // namespace rayes
