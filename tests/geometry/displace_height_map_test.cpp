// Height maps: bilinear filtering and the min-max pyramid (geometry/displacement.h), from
// memory and through the texture cache.
#include <gtest/gtest.h>
#include <cstring>
#include <limits>
#include <memory>
#include <OpenImageIO/imageio.h>
#include "geometry/displacement.h"
#include "support/patch_test_util.h"
#include "support/temp_folder.h"
#include "texture/texture_cache.h"

namespace rayes {
namespace {

using test::Random;

std::shared_ptr<HeightMap> randomMap(int w, int h, uint64_t seed) {
  Random rng(seed);
  std::vector<float> t(size_t(w) * h);
  for (auto& x : t) x = rng.uniform(-3.0f, 5.0f);
  return std::make_shared<HeightMap>(w, h, std::move(t));
}

TEST(HeightMap, SampleIsBetweenItsFourTexelsAndInterpolatesCentres) {
  const auto map = randomMap(5, 3, 1);
  // At a texel centre the sample is the texel.
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 5; ++i) EXPECT_FLOAT_EQ(map->sample((i + 0.5f) / 5, (j + 0.5f) / 3), map->texel(i, j));
  // Edges clamp.
  EXPECT_FLOAT_EQ(map->sample(0, 0), map->texel(0, 0));
  EXPECT_FLOAT_EQ(map->sample(1, 1), map->texel(4, 2));
}

// A grid row is sampled with its texels fetched once (DisplacedPatch::dice through
// Displacement::sampleRow): the same bits as one point at a time, at the clamped edges, on
// one-texel-wide maps and for parameters outside [0, 1] or NaN too.
TEST(HeightMap, RowSamplesEqualPointSamplesBitForBit) {
  Random rng(7);
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{{37, 23}, {1, 9}, {9, 1}, {1, 1}}) {
    const auto map = randomMap(w, h, uint64_t(w * 100 + h));
    const HeightMapDisplacement disp(map, 0.75f, -0.25f);
    for (int row = 0; row < 40; ++row) {
      const int n = 1 + int(rng.uniform(0.0f, 30.0f));
      const float v = row == 0 ? -0.5f : row == 1 ? 1.5f : rng.uniform(0.0f, 1.0f);
      std::vector<float> u(static_cast<size_t>(n));
      for (auto& x : u) x = rng.uniform(-0.2f, 1.2f);
      if (row == 2) u[0] = std::numeric_limits<float>::quiet_NaN();
      std::vector<Vec3> p(static_cast<size_t>(n));
      std::vector<HeightSample> got(static_cast<size_t>(n));
      disp.sampleRow(n, p.data(), p.data(), p.data(), u.data(), v, got.data());
      for (int k = 0; k < n; ++k) {
        const HeightSample want = disp.sample(p[size_t(k)], p[size_t(k)], p[size_t(k)], u[size_t(k)], v);
        EXPECT_EQ(std::memcmp(&want, &got[size_t(k)], sizeof want), 0)
            << w << "x" << h << " u " << u[size_t(k)] << " v " << v << ": " << got[size_t(k)].h << " against " << want.h;
      }
    }
  }
}

TEST(HeightMap, PyramidRangeContainsTheBruteForceRange) {
  const auto map = randomMap(37, 23, 2);  // not powers of two
  Random rng(3);
  for (int k = 0; k < 5000; ++k) {
    const int i0 = rng.below(37), i1 = i0 + rng.below(37 - i0), j0 = rng.below(23), j1 = j0 + rng.below(23 - j0);
    float mn = 1e30f, mx = -1e30f;
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        mn = std::min(mn, map->texel(i, j));
        mx = std::max(mx, map->texel(i, j));
      }
    const Interval r = map->texelRange(i0, i1, j0, j1);
    ASSERT_LE(r.lo, mn);
    ASSERT_GE(r.hi, mx);
  }
}

TEST(HeightMap, RangeOverUvRectContainsEverySample) {
  for (auto [w, h] : {std::pair{37, 23}, std::pair{64, 64}, std::pair{1, 1}, std::pair{1, 9}, std::pair{256, 3}}) {
    const auto map = randomMap(w, h, uint64_t(w * 1000 + h));
    Random rng(uint64_t(w + h));
    int outside = 0;
    double ratio = 0;
    int ratioCount = 0;
    for (int b = 0; b < 200; ++b) {
      const float su = std::pow(10.0f, rng.uniform(-4, 0)), sv = std::pow(10.0f, rng.uniform(-4, 0));
      const float u0 = rng.uniform(0, 1 - su), v0 = rng.uniform(0, 1 - sv), u1 = u0 + su, v1 = v0 + sv;
      const Interval r = map->range(u0, u1, v0, v1);
      float mn = 1e30f, mx = -1e30f;
      for (int k = 0; k < 5000; ++k) {
        const int pu = rng.below(6), pv = rng.below(6);
        const float u = pu == 0 ? u0 : pu == 1 ? u1 : std::min(u1, u0 + su * rng.uniform());
        const float v = pv == 0 ? v0 : pv == 1 ? v1 : std::min(v1, v0 + sv * rng.uniform());
        const float x = map->sample(u, v);
        mn = std::min(mn, x);
        mx = std::max(mx, x);
        if (!r.contains(x)) ++outside;
      }
      if (mx - mn > 1e-3f) {
        ratio += r.width() / (mx - mn);
        ++ratioCount;
      }
    }
    EXPECT_EQ(outside, 0) << w << "x" << h;
    if (ratioCount) std::printf("height map %dx%d: mean interval width / sampled spread = %.2f\n", w, h, ratio / ratioCount);
  }
}

TEST(HeightMap, DerivativesMatchDifferences) {
  const auto map = randomMap(16, 16, 4);
  Random rng(6);
  for (int k = 0; k < 500; ++k) {
    const float u = rng.uniform(0.05f, 0.95f), v = rng.uniform(0.05f, 0.95f);
    float du = 0, dv = 0;
    map->sample(u, v, &du, &dv);
    const float e = 1e-4f;
    // Skip samples within e of a texel centre line, where the bilinear kinks.
    const float fx = u * 16 - 0.5f, fy = v * 16 - 0.5f;
    if (std::fabs(fx - std::round(fx)) < 2e-3f || std::fabs(fy - std::round(fy)) < 2e-3f) continue;
    EXPECT_NEAR(du, (map->sample(u + e, v) - map->sample(u - e, v)) / (2 * e), 0.05f * (1 + std::fabs(du)));
    EXPECT_NEAR(dv, (map->sample(u, v + e) - map->sample(u, v - e)) / (2 * e), 0.05f * (1 + std::fabs(dv)));
  }
}

TEST(HeightMap, RejectsBadInput) {
  EXPECT_THROW(HeightMap(0, 3, std::vector<float>{}), std::invalid_argument);
  EXPECT_THROW(HeightMap(2, 2, std::vector<float>{1, 2, 3}), std::invalid_argument);
  EXPECT_THROW(HeightMap(1, 1, std::vector<float>{std::nanf("")}), std::invalid_argument);
}

// A large image read through a small texture cache: the pyramid is a small fraction of the
// image, samples equal those of the same texels in memory bit for bit, and every range holds
// the samples of its rectangle.
TEST(HeightMap, LargeImageThroughASmallCache) {
  const int w = 4096, h = 4096;
  std::vector<float> texels(size_t(w) * h);
  Random rng(11);
  // Smooth hills plus noise: ranges over large rectangles are narrower than the whole image's.
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i)
      texels[size_t(j) * w + i] = std::sin(float(i) * 0.003f) * std::cos(float(j) * 0.002f) * 10.0f + rng.uniform(-1.0f, 1.0f);
  const testing::TempFolder temp;
  const std::string file = (temp.dir() / "big.exr").string();
  {
    auto out = OIIO::ImageOutput::create(file);
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open(file, OIIO::ImageSpec(w, h, 1, OIIO::TypeDesc::FLOAT)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, texels.data()));
    out->close();
  }
  TextureCacheOptions options;
  options.memoryBytes = uint64_t(4) << 20;  // a sixteenth of the image
  options.conversionDir = temp.dir() / "converted";
  options.notice = [](const std::string&) {};
  const auto cache = TextureCache::make(options);
  const HeightMap cached(cache->open(file), 0);
  const HeightMap memory(w, h, texels);
  ASSERT_EQ(cached.width(), w);
  // Two floats per cell of kCell x kCell texels, and a third more for the coarser levels.
  const double cells = double(w / HeightMap::kCell) * double(h / HeightMap::kCell);
  EXPECT_LE(double(cached.pyramidBytes()), 2 * sizeof(float) * cells * 4 / 3 + 64);
  EXPECT_EQ(cached.meanNeighbourDifference(), memory.meanNeighbourDifference());
  EXPECT_GT(cache->stats().tilesRead, 0u);

  int outside = 0;
  for (int b = 0; b < 300; ++b) {
    const float su = std::pow(10.0f, rng.uniform(-5, 0)), sv = std::pow(10.0f, rng.uniform(-5, 0));
    const float u0 = rng.uniform(0, 1 - su), v0 = rng.uniform(0, 1 - sv), u1 = u0 + su, v1 = v0 + sv;
    const Interval r = cached.range(u0, u1, v0, v1);
    for (int k = 0; k < 300; ++k) {
      const int pu = rng.below(6), pv = rng.below(6);
      const float u = pu == 0 ? u0 : pu == 1 ? u1 : std::min(u1, u0 + su * rng.uniform());
      const float v = pv == 0 ? v0 : pv == 1 ? v1 : std::min(v1, v0 + sv * rng.uniform());
      float du = 0, dv = 0, mu = 0, mv = 0;
      const float x = cached.sample(u, v, &du, &dv);
      const float y = memory.sample(u, v, &mu, &mv);
      ASSERT_EQ(std::memcmp(&x, &y, sizeof x), 0) << u << " " << v;
      ASSERT_EQ(du, mu);
      ASSERT_EQ(dv, mv);
      if (!r.contains(x)) ++outside;
    }
  }
  EXPECT_EQ(outside, 0);
}

TEST(HeightMapDisplacement, AmplitudeAndOffsetApplyToTheRange) {
  auto map = randomMap(8, 8, 5);
  const HeightMapDisplacement d(map, -2.0f, 1.0f);
  const Interval r = d.range(Box3{}, 0, 1, 0, 1);
  const Interval t = map->range(0, 1, 0, 1);
  EXPECT_LE(r.lo, 1.0f - 2.0f * t.hi);
  EXPECT_GE(r.hi, 1.0f - 2.0f * t.lo);
  EXPECT_NEAR(r.lo, 1.0f - 2.0f * t.hi, 1e-3f);
}

}  // namespace
}  // namespace rayes
