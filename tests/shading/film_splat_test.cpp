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

namespace rayes {
namespace {

// The splat buffer is exact: the same splats in any order, or split between two films and
// merged, give the same bits (a double sum would not: 1e16 + 1 - 1e16).
TEST(FilmSplats, ExactInAnyOrderAndAcrossFilms) {
  const std::vector<Rgb> values = {{1e16f, 0.1f, 3}, {1, 0.2f, 1e-9f}, {-1e16f, 0.3f, 7}, {0.5f, 1e-7f, 2}};
  Film forward(1, 1), backward(1, 1), first(1, 1), second(1, 1);
  for (size_t i = 0; i < values.size(); ++i) {
    forward.addSplat(0, values[i]);
    backward.addSplat(0, values[values.size() - 1 - i]);
    (i % 2 ? first : second).addSplat(0, values[i]);
  }
  first.countSplatPaths(2);
  second.countSplatPaths(2);
  forward.countSplatPaths(4);
  backward.countSplatPaths(4);
  ASSERT_TRUE(first.addFilm(second));
  EXPECT_EQ(forward.sums().splat, backward.sums().splat);
  EXPECT_EQ(forward.sums().splat, first.sums().splat);
  EXPECT_EQ(first.sums().splatPaths, 4u);
  EXPECT_EQ(forward.beautyRgba(), first.beautyRgba());
  // 1e16 - 1e16 + 1 + 0.5, exactly (the float 1e16 is 10000000272564224).
  EXPECT_EQ(forward.beautyRgba()[0], 1.5f / 4);
  EXPECT_EQ(forward.splatSaturations(), 0u);
}

TEST(FilmSplats, BeyondTheRangeSaturatesAndIsCounted) {
  Film film(1, 1);
  film.addSplat(0, {3e38f, 1, 1});  // beyond the range alone
  EXPECT_EQ(film.splatSaturations(), 1u);
  for (int i = 0; i < 2; ++i) film.addSplat(0, {0, 4e18f, 0});
  EXPECT_EQ(film.splatSaturations(), 1u) << "8e18 + 1 is within 2^63";
  film.addSplat(0, {0, 4e18f, 0});  // each within the range, not their sum
  EXPECT_EQ(film.splatSaturations(), 2u);
}

// A film of a window holds its pixels only, named by their full-image index; resolved, it is
// the window's size; a part's window added to the frame's film copies its sums.
TEST(FilmWindow, HoldsTheWindowsPixelsByTheirFullImageIndex) {
  Film film(5, 4, PixelWindow{1, 2, 4, 4});
  EXPECT_EQ(film.width(), 3);
  EXPECT_EQ(film.height(), 2);
  EXPECT_TRUE(film.contains(2 * 5 + 1));
  EXPECT_FALSE(film.contains(1 * 5 + 1));
  EXPECT_FALSE(film.contains(2 * 5 + 4));
  PixelSample s;
  s.radiance = {2, 4, 6};
  film.add(3 * 5 + 3, s);  // (3, 3): the window's last pixel
  EXPECT_EQ(film.samples(3 * 5 + 3), 1u);
  const auto rgba = film.beautyRgba();
  ASSERT_EQ(rgba.size(), 4u * 6);
  EXPECT_EQ(rgba[4 * 5], 2.0f);
  Film frame(5, 4);
  ASSERT_TRUE(frame.addFilm(film));
  EXPECT_EQ(frame.samples(3 * 5 + 3), 1u);
  EXPECT_EQ(frame.beautyRgba()[4 * 18 + 2], 6.0f);
  EXPECT_FALSE(frame.addFilm(film)) << "a pixel's samples come from one part only";
  EXPECT_FALSE(film.addFilm(frame)) << "a window larger than the film's";
}

}  // namespace
}  // namespace rayes
