#include "core/vector_isa.h"
#include <atomic>
#include <cstdlib>
#include <cstring>

namespace rayes {

namespace {

std::atomic<VectorIsa>& current() {
  static std::atomic<VectorIsa> isa{chooseVectorIsa(std::getenv("RAYES_VECTOR_ISA"), cpuHasAvx2())};
  return isa;
}

}  // namespace

bool cpuHasAvx2() {
#if RAYES_AVX2_KERNELS
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
#else
  return false;
#endif
}

VectorIsa vectorIsa() { return current().load(std::memory_order_relaxed); }

VectorIsa forceVectorIsa(VectorIsa isa) {
  if (isa == VectorIsa::Avx2 && !cpuHasAvx2()) isa = VectorIsa::Baseline;
  return current().exchange(isa, std::memory_order_relaxed);
}

VectorIsa chooseVectorIsa(const char* environment, bool hasAvx2) {
  if (!hasAvx2) return VectorIsa::Baseline;
  if (environment && std::strcmp(environment, "baseline") == 0) return VectorIsa::Baseline;
  return VectorIsa::Avx2;
}

std::string vectorIsaName(VectorIsa isa) { return isa == VectorIsa::Avx2 ? "avx2" : "baseline"; }

}  // namespace rayes
