#include "common/cpu_features.h"

#include <cstdlib>

namespace accelcal {
namespace {

bool QueryAvx2Fma() {
  const char* disable = std::getenv("ACCELCAL_DISABLE_AVX2");
  if (disable != nullptr && disable[0] != '\0' && disable[0] != '0') return false;
#if defined(__x86_64__) || defined(__i386__)
  // libgcc's (and compiler-rt's) CPU model also checks XCR0, i.e. that the OS saves the
  // AVX registers on a context switch, not just the CPUID bits.
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
  return false;
#endif
}

}  // namespace

bool CpuHasAvx2Fma() {
  static const bool has_avx2_fma = QueryAvx2Fma();
  return has_avx2_fma;
}

}  // namespace accelcal
