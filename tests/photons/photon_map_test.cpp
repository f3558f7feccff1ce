// The photon map (photons/photon_map.h) as photon mapping's estimates rely on it: the k nearest
// photons and the photons within a radius are exactly those a brute-force scan finds (ties by
// position in the map), an empty map answers nothing, coincident photons are all found, and the
// map's order does not depend on the thread count (the images are bit-identical).
#include <gtest/gtest.h>
#include <algorithm>
#include <limits>
#include <random>
#include <set>
#include <vector>
#include "core/parallel.h"
#include "photons/photon_map.h"

namespace rayes {
namespace {

constexpr float kNoLimit = std::numeric_limits<float>::max();

std::vector<Photon> randomPhotons(size_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1, 1);
  std::vector<Photon> photons(n);
  for (size_t i = 0; i < n; ++i) {
    photons[i].p = {u(rng), u(rng), 0.25f * u(rng)};  // flatter in z, like photons on a floor
    photons[i].power = {float(i), 0, 0};              // the input position, to tell photons apart
  }
  return photons;
}

float dist2(const Photon& ph, Vec3 x) {
  const Vec3 d = ph.p - x;
  return dot(d, d);
}

// The k nearest within maxR2 by (squared distance, map position), as nearest() defines them.
std::vector<uint32_t> bruteNearest(const PhotonMap& map, Vec3 x, int k, float maxR2) {
  std::vector<std::pair<float, uint32_t>> all;
  for (size_t i = 0; i < map.size(); ++i)
    if (dist2(map[i], x) <= maxR2) all.push_back({dist2(map[i], x), uint32_t(i)});
  std::sort(all.begin(), all.end());
  std::vector<uint32_t> out;
  for (size_t i = 0; i < all.size() && int(i) < k; ++i) out.push_back(all[i].second);
  return out;
}

TEST(PhotonMap, NearestAreTheBruteForceNearest) {
  const PhotonMap map(randomPhotons(3000, 7));
  ASSERT_EQ(map.size(), 3000u);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.2f, 1.2f);
  std::vector<uint32_t> found;
  for (int q = 0; q < 300; ++q) {
    const Vec3 x{u(rng), u(rng), 0.3f * u(rng)};
    for (int k : {1, 8, 32, 500}) {
      for (float maxR2 : {kNoLimit, 0.01f}) {
        const float r2 = map.nearest(x, k, maxR2, found);
        const std::vector<uint32_t> expected = bruteNearest(map, x, k, maxR2);
        ASSERT_EQ(found, expected) << "query " << q << ", k " << k << ", maxR2 " << maxR2;
        // The k-th's squared distance, or maxR2 when fewer than k lie within it.
        const float expectedR2 = int(expected.size()) == k ? dist2(map[expected.back()], x) : maxR2;
        EXPECT_EQ(r2, expectedR2);
      }
    }
  }
}

TEST(PhotonMap, WithinVisitsExactlyThePhotonsInTheRadius) {
  const PhotonMap map(randomPhotons(2000, 3));
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.2f, 1.2f);
  for (int q = 0; q < 200; ++q) {
    const Vec3 x{u(rng), u(rng), 0.3f * u(rng)};
    for (float r2 : {0.0f, 0.001f, 0.05f, 10.0f}) {
      std::multiset<uint32_t> visited;
      map.within(x, r2, [&](uint32_t i) { visited.insert(i); });
      std::multiset<uint32_t> expected;
      for (size_t i = 0; i < map.size(); ++i)
        if (dist2(map[i], x) <= r2) expected.insert(uint32_t(i));
      ASSERT_EQ(visited, expected) << "query " << q << ", r2 " << r2;  // each once
    }
  }
}

TEST(PhotonMap, AnEmptyMapFindsNothing) {
  const PhotonMap empty{std::vector<Photon>{}};
  EXPECT_EQ(empty.size(), 0u);
  std::vector<uint32_t> found{1, 2, 3};
  EXPECT_EQ(empty.nearest({0, 0, 0}, 8, 4.0f, found), 4.0f);
  EXPECT_TRUE(found.empty());
  int visits = 0;
  empty.within({0, 0, 0}, kNoLimit, [&](uint32_t) { ++visits; });
  EXPECT_EQ(visits, 0);
  const PhotonMap defaulted;
  EXPECT_EQ(defaulted.nearest({1, 2, 3}, 1, kNoLimit, found), kNoLimit);
  EXPECT_TRUE(found.empty());
}

TEST(PhotonMap, CoincidentPhotonsAreAllFound) {
  // 100 photons on one point (a degenerate box at every level of the tree) among 50 others.
  std::vector<Photon> photons = randomPhotons(50, 9);
  for (int i = 0; i < 100; ++i) photons.push_back(Photon{{0.5f, 0.5f, 0}, {0, 0, 1}, {0, 0, 1}, {1, 1, 1}, 1});
  const PhotonMap map(photons);
  std::vector<uint32_t> found;
  EXPECT_EQ(map.nearest({0.5f, 0.5f, 0}, 10, kNoLimit, found), 0.0f);
  ASSERT_EQ(found.size(), 10u);
  EXPECT_EQ(found, bruteNearest(map, {0.5f, 0.5f, 0}, 10, kNoLimit));  // the ten first in map order
  int atPoint = 0;
  map.within({0.5f, 0.5f, 0}, 0.0f, [&](uint32_t i) { atPoint += map[i].p == Vec3{0.5f, 0.5f, 0}; });
  EXPECT_EQ(atPoint, 100);
  // Every photon on one point.
  const PhotonMap same(std::vector<Photon>(64, Photon{{1, 1, 1}, {0, 0, 1}, {0, 0, 1}, {1, 1, 1}, 1}));
  EXPECT_EQ(same.nearest({1, 1, 2}, 64, kNoLimit, found), 1.0f);
  EXPECT_EQ(found.size(), 64u);
}

TEST(PhotonMap, TheMapIsTheSameForAnyThreadCount) {
  // Above the size at which halves are built as parallel tasks.
  const std::vector<Photon> photons = randomPhotons(40000, 13);
  std::vector<Vec3> order[2];
  for (int threads : {1, 2}) {
    ThreadLimit limit(threads);
    const PhotonMap map(photons);
    for (size_t i = 0; i < map.size(); ++i) order[threads - 1].push_back(map[i].power);
  }
  EXPECT_EQ(order[0], order[1]);
}

}  // namespace
}  // namespace rayes
