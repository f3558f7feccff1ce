// The instruction set that the row kernels run with: the loops over a grid row that GCC
// vectorises (ValueNoise::evalRow, NoiseDisplacement::sampleRow, DisplacedPatch::rowFrames)
// are compiled twice, for the x86-64 baseline (SSE2, four floats a step) and for AVX2 (eight),
// and each call takes the one vectorIsa() names. Measured: 15-30 % less time per displaced
// dicing (bench/history/2026-11.md, "Row kernels for AVX2").
//
// Same bits on every instruction set: the kernels do per lane the IEEE operations of one point
// alone (adds, multiplies, divisions, square roots, compares, selects, conversions), which round
// the same at any vector width; no fused multiply-add is allowed (-ffp-contract=off, and the
// AVX2 target does not include FMA) and nothing is reassociated (no -ffast-math). So an image
// does not depend on the machine it was rendered on; tests/core/vector_isa_test.cpp and the
// kernels' own tests compare both versions bit for bit.
//
// Chosen once per process: AVX2 where the CPU has it, unless RAYES_VECTOR_ISA=baseline is set
// (to check a result against the baseline code on the same machine). Thread-safe: the choice is
// an atomic; forceVectorIsa is for tests, which switch it between renders, not during one.
#pragma once
#include <string>

namespace rayes {

enum class VectorIsa { Baseline, Avx2 };

// The instruction set of the row kernels now.
VectorIsa vectorIsa();
// Whether this CPU (and build) can run the AVX2 kernels.
bool cpuHasAvx2();
// Runs the kernels with `isa` from now on (Avx2 only where cpuHasAvx2()); returns the previous
// choice. For tests and benchmarks.
VectorIsa forceVectorIsa(VectorIsa isa);
// "baseline" or "avx2" (the stats' settings.vector_isa).
std::string vectorIsaName(VectorIsa isa);
// The choice at start: AVX2 where the CPU has it, unless `environment` (RAYES_VECTOR_ISA's value,
// or null) is "baseline".
VectorIsa chooseVectorIsa(const char* environment, bool hasAvx2);

// Runs the kernels with one instruction set for its lifetime (tests and benchmarks).
class ScopedVectorIsa {
 public:
  explicit ScopedVectorIsa(VectorIsa isa) : previous_(forceVectorIsa(isa)) {}
  ~ScopedVectorIsa() { forceVectorIsa(previous_); }
  ScopedVectorIsa(const ScopedVectorIsa&) = delete;
  ScopedVectorIsa& operator=(const ScopedVectorIsa&) = delete;

 private:
  VectorIsa previous_;
};

}  // namespace rayes

// Marks a function to be compiled for AVX2 (x86-64 with GCC or Clang only; elsewhere the
// baseline version is the only one and vectorIsa() is always Baseline).
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define RAYES_AVX2_KERNELS 1
#define RAYES_TARGET_AVX2 __attribute__((target("avx2")))
#else
#define RAYES_AVX2_KERNELS 0
#define RAYES_TARGET_AVX2
#endif
// The body of a kernel, inlined into both versions so that each is compiled for its own target.
#define RAYES_KERNEL_BODY __attribute__((always_inline)) inline
