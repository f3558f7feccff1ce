// The texture cache (src/texture/texture_cache.h) as a specification: what a lookup returns in
// terms of the image's texels, that any cache size and thread count give the same values, and
// what its stats count.
#include <cmath>
#include <random>
#include <gtest/gtest.h>
#include <tbb/parallel_for.h>
#include "core/error.h"
#include "support/temp_folder.h"
#include "support/texture_test_files.h"
#include "texture/texture_cache.h"

namespace rayes {
namespace {

std::vector<Rgb> randomTexels(int w, int h, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Rgb> t(size_t(w) * size_t(h));
  for (Rgb& c : t) c = {u(rng), u(rng), u(rng)};
  return t;
}

// Bilinear interpolation with repeat wrapping of the texels, in double (texel centres at
// ((i + 0.5) / w, (j + 0.5) / h), row 0 at t = 0).
Vec3 bilinearReference(const std::vector<Rgb>& t, int w, int h, double s, double tt) {
  const double x = s * w - 0.5, y = tt * h - 0.5;
  const double fx = std::floor(x), fy = std::floor(y), ax = x - fx, ay = y - fy;
  auto at = [&](long i, long j) {
    const long ii = ((i % w) + w) % w, jj = ((j % h) + h) % h;
    return t[size_t(jj) * size_t(w) + size_t(ii)];
  };
  const long i = long(fx), j = long(fy);
  Vec3 r;
  for (int c = 0; c < 3; ++c)
    r[c] = float((at(i, j)[c] * (1 - ax) + at(i + 1, j)[c] * ax) * (1 - ay) +
                 (at(i, j + 1)[c] * (1 - ax) + at(i + 1, j + 1)[c] * ax) * ay);
  return r;
}

TEST(TextureCache, APointSampleIsTheBilinearBlendOfTheFinestLevel) {
  const testing::TempFolder temp;
  const int w = 16, h = 8;
  const auto texels = randomTexels(w, h, 1);
  testing::writeRgbExr(temp.path("r.exr"), w, h, texels);
  const auto image = testing::quietCache(temp.dir())->open(temp.path("r.exr"));
  ASSERT_EQ(image->width(), w);
  ASSERT_EQ(image->height(), h);
  EXPECT_EQ(image->levels(), 5);  // 16x8, 8x4, 4x2, 2x1, 1x1
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(-2.0f, 3.0f);  // outside [0, 1]: repeat wrapping
  for (int k = 0; k < 2000; ++k) {
    const float s = u(rng), t = u(rng);
    const Rgb got = image->filtered(s, t, 0, 0, 0, 0, TextureWrap::Periodic);
    const Vec3 want = bilinearReference(texels, w, h, s, t);
    // Texels in [0, 1]: a blend of four in float is within a few float roundings (2^-24 each)
    // of the exact one; the wrap of s and t into [0, 1) rounds s * w by up to 2^-24 * 3 * w,
    // which moves the blend by at most that times the largest texel difference (1).
    const float bound = 8 * 0x1p-24f + 0x1p-24f * 3 * w;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], bound) << s << ", " << t;
  }
}

TEST(TextureCache, AFootprintOverTheWholeImageReturnsItsMean) {
  const testing::TempFolder temp;
  // An 8 x 8 checkerboard of 0 and 1 texels, 8 x 8 texels each: mean 1/2, and every MIP level
  // from 8 x 8 texels down is 1/2 everywhere (box filter).
  const int n = 64;
  std::vector<Rgb> t(size_t(n) * n);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) t[size_t(y) * n + x] = ((x / 8 + y / 8) % 2) ? Rgb{1, 1, 1} : Rgb{0, 0, 0};
  testing::writeRgbExr(temp.path("c.exr"), n, n, t);
  const auto image = testing::quietCache(temp.dir())->open(temp.path("c.exr"));
  for (float s : {0.1f, 0.37f, 0.5f, 0.93f})
    for (float axis : {1.0f, 2.0f}) {
      const Rgb c = image->filtered(s, 1 - s, axis, 0, 0, axis, TextureWrap::Periodic);
      // Box-filtered levels of 0 and 1 at 8 x 8 and coarser are exactly 1/2, and OIIO's
      // filter is a convex combination of a level's texels: exactly 1/2 up to float rounding.
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], 0.5f, 1e-6f) << s << " axis " << axis;
    }
  // A footprint of one texel sees the checkerboard: a point inside a square is its colour.
  EXPECT_NEAR(image->filtered(4.5f / n, 4.5f / n, 0.5f / n, 0, 0, 0.5f / n, TextureWrap::Periodic).x, 0.0f, 1e-6f);
  EXPECT_NEAR(image->filtered(12.5f / n, 4.5f / n, 0.5f / n, 0, 0, 0.5f / n, TextureWrap::Periodic).x, 1.0f, 1e-6f);
}

TEST(TextureCache, ClosestIsTheTexelHoldingThePoint) {
  const testing::TempFolder temp;
  const int w = 8, h = 6;
  const auto texels = randomTexels(w, h, 3);
  testing::writeRgbExr(temp.path("e.exr"), w, h, texels);
  const auto image = testing::quietCache(temp.dir())->open(temp.path("e.exr"));
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(0.0f, 0.99999994f);
  for (int k = 0; k < 1000; ++k) {
    const float s = u(rng), t = u(rng);
    const int x = std::min(w - 1, int(s * w)), y = std::min(h - 1, int(t * h));
    EXPECT_EQ(image->closest(s, t), texels[size_t(y) * w + x]) << s << ", " << t;
  }
}

TEST(TextureCache, CoarserLevelsAreBoxFilteredMeans) {
  // The environment's sampling distribution relies on it: a coarse cell is positive wherever a
  // texel under it is.
  const testing::TempFolder temp;
  const int w = 8, h = 4;
  const auto texels = randomTexels(w, h, 5);
  testing::writeRgbExr(temp.path("m.exr"), w, h, texels);
  const auto image = testing::quietCache(temp.dir())->open(temp.path("m.exr"));
  const std::vector<Rgb> level1 = image->levelRgb(1);
  ASSERT_EQ(level1.size(), size_t(4 * 2));
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) {
      Rgb mean{};
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) mean += texels[size_t(2 * y + dy) * w + size_t(2 * x + dx)] * 0.25f;
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(level1[size_t(y) * 4 + x][c], mean[c], 4 * 0x1p-24f) << x << ", " << y;
    }
}

TEST(TextureCache, GreyImagesReturnTheirChannelInAllThree) {
  const testing::TempFolder temp;
  auto out = OIIO::ImageOutput::create(temp.path("g.exr"));
  ASSERT_TRUE(out);
  ASSERT_TRUE(out->open(temp.path("g.exr"), OIIO::ImageSpec(2, 1, 1, OIIO::TypeDesc::FLOAT)));
  const float y[2] = {0.25f, 0.75f};
  out->write_image(OIIO::TypeDesc::FLOAT, y);
  out->close();
  const auto image = testing::quietCache(temp.dir())->open(temp.path("g.exr"));
  EXPECT_EQ(image->channels(), 1);
  EXPECT_EQ(image->closest(0.7f, 0.5f), (Rgb{0.75f, 0.75f, 0.75f}));
}

TEST(TextureCache, NonFiniteAndNegativeTexelsReadAsZero) {
  const testing::TempFolder temp;
  testing::writeRgbExr(temp.path("bad.exr"), 2, 1, {{-1, std::nanf(""), 0.5f}, {INFINITY, 2, -0.0f}});
  const auto image = testing::quietCache(temp.dir())->open(temp.path("bad.exr"));
  EXPECT_EQ(image->closest(0.25f, 0.5f), (Rgb{0, 0, 0.5f}));
  // Infinity is kept by the conversion but never returned.
  const Rgb c = image->closest(0.75f, 0.5f);
  EXPECT_EQ(c.x, 0.0f);
  EXPECT_EQ(c.y, 2.0f);
  // Non-finite coordinates and axes: black and a point sample, never NaN.
  EXPECT_EQ(image->filtered(NAN, 0.5f, 0, 0, 0, 0, TextureWrap::Periodic), (Rgb{0, 0, 0}));
  const Rgb p = image->filtered(0.25f, 0.5f, INFINITY, 0, 0, NAN, TextureWrap::Clamp);
  for (int k = 0; k < 3; ++k) EXPECT_TRUE(std::isfinite(p[k]));
}

// The same lookups, in parallel on every thread, through caches of very different sizes: the
// same bits (a lookup is a pure function of the file and its arguments).
TEST(TextureCache, AnyCacheSizeAndThreadCountGiveTheSameValues) {
  const testing::TempFolder temp;
  const int w = 512, h = 512;  // 64 x 64 tiles: 64 tiles at the finest level, 4 MiB of floats
  testing::writeRgbExr(temp.path("big.exr"), w, h, randomTexels(w, h, 6));
  const size_t n = 20000;
  std::vector<float> q(6 * n);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f), d(0.0f, 0.05f);
  for (size_t k = 0; k < n; ++k) q[6 * k] = u(rng), q[6 * k + 1] = u(rng), q[6 * k + 2] = d(rng),
                                  q[6 * k + 3] = d(rng) * 0.1f, q[6 * k + 4] = -d(rng) * 0.1f, q[6 * k + 5] = d(rng);
  auto lookups = [&](uint64_t bytes, bool parallel) {
    const auto image = testing::quietCache(temp.dir(), bytes)->open(temp.path("big.exr"));
    std::vector<Rgb> out(n);
    auto one = [&](size_t k) {
      const float* a = &q[6 * k];
      out[k] = image->filtered(a[0], a[1], a[2], a[3], a[4], a[5], TextureWrap::Periodic);
    };
    if (parallel) tbb::parallel_for(size_t(0), n, one);
    else for (size_t k = 0; k < n; ++k) one(k);
    return out;
  };
  const std::vector<Rgb> ref = lookups(uint64_t(256) << 20, false);
  for (const auto& [bytes, parallel] : {std::pair{uint64_t(1) << 20, true}, std::pair{uint64_t(1) << 20, false},
                                        std::pair{uint64_t(256) << 20, true}}) {
    const std::vector<Rgb> got = lookups(bytes, parallel);
    for (size_t k = 0; k < n; ++k) ASSERT_EQ(got[k], ref[k]) << "lookup " << k << " with " << bytes << " bytes";
  }
}

TEST(TextureCache, StatsCountFilesTilesAndHits) {
  const testing::TempFolder temp;
  testing::writeRgbExr(temp.path("a.exr"), 256, 256, randomTexels(256, 256, 8));
  const auto cache = testing::quietCache(temp.dir());
  const auto a = cache->open(temp.path("a.exr"));
  EXPECT_EQ(cache->open(temp.path("a.exr")), a) << "a file opened twice is one image";
  TextureCacheStats s = cache->stats();
  EXPECT_EQ(s.files, 1u);
  EXPECT_EQ(s.conversions, 1u);
  EXPECT_EQ(s.tilesRead, 0u) << "opening reads no tile";
  for (int k = 0; k < 1000; ++k) a->filtered(0.3f, 0.6f, 0, 0, 0, 0, TextureWrap::Periodic);
  s = cache->stats();
  EXPECT_GE(s.tilesRead, 1u);
  EXPECT_LE(s.tilesRead, 4u) << "one bilinear point touches at most 4 tiles";
  EXPECT_GE(s.bytesRead, s.tilesRead * 64 * 64 * 3 * 2) << "half-float tiles at least";
  EXPECT_GE(s.hitRate, 0.0);
  EXPECT_LE(s.hitRate, 1.0);
  EXPECT_EQ(s.memoryLimitBytes, kDefaultTextureMemoryBytes);
  EXPECT_GE(s.imageBytes, uint64_t(256) * 256 * 3 * 2);
}

}  // namespace
}  // namespace rayes
