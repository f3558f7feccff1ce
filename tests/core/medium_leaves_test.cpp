// TransmittanceProduct (core/medium_leaves.h): the shadow rays' product over brick leaves,
// accumulated in any order to the same bits, equal to the float product within the fixed
// point's rounding, and exactly zero once any factor is.
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <vector>
#include "core/medium_leaves.h"
#include "core/rng.h"

namespace rayes {
namespace {

TEST(TransmittanceProduct, AnyOrderGivesTheSameBitsAndTheProduct) {
  std::vector<float> f;
  for (uint32_t i = 0; i < 200; ++i) f.push_back(0.5f + sampleUniform(RngKey{i, 0, 0, 1}, 0) * 0.5f);  // a product near 1e-25: a normal float
  uint64_t forward = 0, backward = 0;
  double exact = 1;
  for (const float x : f) {
    TransmittanceProduct::addLocal(forward, TransmittanceProduct::term(x));
    exact *= x;
  }
  for (auto it = f.rbegin(); it != f.rend(); ++it) TransmittanceProduct::add(backward, TransmittanceProduct::term(*it));
  EXPECT_EQ(forward, backward);
  // Each term rounds −log x to 2^-24: the product is off by at most 200 · 2^-25 relative, plus
  // the float result's own rounding.
  const double got = TransmittanceProduct::valueOf(forward);
  EXPECT_NEAR(got / exact, 1.0, 200 * std::ldexp(1.0, -25) + 1e-6);
}

TEST(TransmittanceProduct, OneAndZeroAreExact) {
  EXPECT_EQ(TransmittanceProduct::term(1.0f), 0u);
  EXPECT_EQ(TransmittanceProduct::valueOf(0), 1.0f);
  uint64_t s = 0;
  TransmittanceProduct::add(s, TransmittanceProduct::term(0.5f));
  TransmittanceProduct::add(s, TransmittanceProduct::term(0.0f));
  TransmittanceProduct::add(s, TransmittanceProduct::term(0.25f));
  EXPECT_EQ(TransmittanceProduct::valueOf(s), 0.0f);
  EXPECT_EQ(TransmittanceProduct::term(std::nanf("")), TransmittanceProduct::kZero) << "not a number counts as black";
}

}  // namespace
}  // namespace rayes
