// Textures: colour functions of a surface point, read at a TextureQuery (shading/texture_query.h):
// the patch parameters (u, v) of a hit (RayHit::u, v) or the leaf's uv set, as `coordinates` says.
// An image (filtered over the query's footprint through the render's texture cache,
// texture/texture_cache.h; repeat wrapping; image row 0 at v = 1 so the image appears upright
// when v points up), a checkerboard, or fractal value noise blending two colours.
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
  // Fractal value noise in [0, 1] (public for tests).
  static float noise(float x, float y, int octaves);
};

}  // namespace rayes
