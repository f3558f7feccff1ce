// The film's splat buffer (light tracing): added at the end, scaled by 1 / (light paths per
// pixel so far), alongside whatever camera samples a pixel has; alpha 1 where no camera
// sample was taken; a film without splats resolves exactly as before.
#include <gtest/gtest.h>
#include "shading/film.h"

namespace rayes {
namespace {

TEST(FilmSplats, ScaledByLightPathsPerPixel) {
  Film film(2, 1);
  film.addSplat(0, {3, 6, 9});
  film.addSplat(0, {1, 2, 3});
  film.countSplatPaths(8);  // 4 light paths per pixel
  const auto rgba = film.beautyRgba();
  EXPECT_DOUBLE_EQ(rgba[0], 1.0);
  EXPECT_DOUBLE_EQ(rgba[1], 2.0);
  EXPECT_DOUBLE_EQ(rgba[2], 3.0);
  EXPECT_EQ(rgba[3], 1.0f) << "no camera sample: no coverage information";
  EXPECT_EQ(rgba[4], 0.0f) << "a pixel no splat reached";
  EXPECT_EQ(rgba[7], 1.0f);
}

TEST(FilmSplats, AddedToCameraSamplesAndAbsentWithoutSplatPaths) {
  Film film(1, 1);
  PixelSample s;
  s.radiance = {0.5f, 0.5f, 0.5f};
  s.hitSurface = true;
  film.add(0, s);
  film.addSplat(0, {2, 2, 2});
  EXPECT_EQ(film.beautyRgba()[0], 0.5f) << "splats count only once light paths are counted";
  film.countSplatPaths(2);
  EXPECT_EQ(film.beautyRgba()[0], 1.5f);
  EXPECT_EQ(film.beautyRgba()[3], 1.0f);
}

}  // namespace
}  // namespace rayes
