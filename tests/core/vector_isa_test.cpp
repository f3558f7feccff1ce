// The row kernels' instruction set (core/vector_isa.h): AVX2 where the CPU has it unless
// RAYES_VECTOR_ISA=baseline, the baseline everywhere else, and a test can switch between them.
// That both versions give the same bits is the kernels' own tests' business
// (tests/geometry/displace_noise_test.cpp, tests/geometry/displace_patch_test.cpp,
// tests/app/forest_render_test.cpp).
#include <gtest/gtest.h>
#include "core/vector_isa.h"

namespace rayes {
namespace {

TEST(VectorIsa, Avx2WhereTheCpuHasItUnlessTheEnvironmentAsksForTheBaseline) {
  EXPECT_EQ(chooseVectorIsa(nullptr, true), VectorIsa::Avx2);
  EXPECT_EQ(chooseVectorIsa("", true), VectorIsa::Avx2);
  EXPECT_EQ(chooseVectorIsa("avx2", true), VectorIsa::Avx2);
  EXPECT_EQ(chooseVectorIsa("baseline", true), VectorIsa::Baseline);
  EXPECT_EQ(chooseVectorIsa(nullptr, false), VectorIsa::Baseline);
  EXPECT_EQ(chooseVectorIsa("avx2", false), VectorIsa::Baseline);  // never code the CPU cannot run
}

TEST(VectorIsa, ScopedChoiceHoldsAndIsRestored) {
  const VectorIsa before = vectorIsa();
  {
    ScopedVectorIsa baseline(VectorIsa::Baseline);
    EXPECT_EQ(vectorIsa(), VectorIsa::Baseline);
    {
      ScopedVectorIsa avx2(VectorIsa::Avx2);
      EXPECT_EQ(vectorIsa(), cpuHasAvx2() ? VectorIsa::Avx2 : VectorIsa::Baseline);
    }
    EXPECT_EQ(vectorIsa(), VectorIsa::Baseline);
  }
  EXPECT_EQ(vectorIsa(), before);
  EXPECT_EQ(vectorIsaName(VectorIsa::Avx2), "avx2");
  EXPECT_EQ(vectorIsaName(VectorIsa::Baseline), "baseline");
}

}  // namespace
}  // namespace rayes
