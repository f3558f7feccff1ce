// nextFloatUp/Down are std::nextafter towards +-inf, bit for bit: the interval bounds' outward
// rounding (and so every displaced bound and image) must not change by inlining it.
#include <cmath>
#include <limits>
#include <gtest/gtest.h>
#include "core/next_float.h"
#include "core/rng.h"

namespace rayes {
namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();

void expectSameAsNextafter(float x) {
  const float up = nextFloatUp(x), down = nextFloatDown(x);
  if (std::isnan(x)) {
    EXPECT_TRUE(std::isnan(up) && std::isnan(down));
    return;
  }
  EXPECT_EQ(detail::floatBits(up), detail::floatBits(std::nextafter(x, kInf))) << x;
  EXPECT_EQ(detail::floatBits(down), detail::floatBits(std::nextafter(x, -kInf))) << x;
}

TEST(NextFloat, EqualsNextafterAtTheEdges) {
  const float max = std::numeric_limits<float>::max(), tiny = std::numeric_limits<float>::denorm_min(),
              normal = std::numeric_limits<float>::min();
  for (float x : {0.0f, -0.0f, tiny, -tiny, normal, -normal, max, -max, kInf, -kInf, 1.0f, -1.0f,
                  std::numeric_limits<float>::quiet_NaN()})
    expectSameAsNextafter(x);
}

// Every bit pattern agrees (checked once off-line over all 2^32); here a million random ones.
TEST(NextFloat, EqualsNextafterOnRandomBitPatterns) {
  for (uint64_t i = 0; i < 1000000; ++i) expectSameAsNextafter(detail::bitsFloat(uint32_t(mix64(i) >> 32)));
}

}  // namespace
}  // namespace rayes
