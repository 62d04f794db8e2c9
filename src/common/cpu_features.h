#ifndef ACCELCAL_COMMON_CPU_FEATURES_H_
#define ACCELCAL_COMMON_CPU_FEATURES_H_

// Hand-made function multiversioning for the few vectorized loops (common/sincos.cc, the
// baseline's block sums in estimation/tilt_table/linear_ls.cc). The build targets plain x86-64
// (SSE2), so that the binaries run on any x86-64 machine; a loop that gains from wider
// vectors is compiled a second time with ACCELCAL_TARGET_AVX2_FMA, and the caller picks
// that version when CpuHasAvx2Fma():
//
//   ACCELCAL_TARGET_AVX2_FMA void LoopAvx2Fma(...) { LoopBody(...); }
//   void LoopBaseline(...) { LoopBody(...); }  // LoopBody always_inline
//
// rather than GCC's target_clones, which makes one clone per listed extension ("avx2,fma"
// gives an AVX2 clone and an FMA clone, neither with both) and needs ifunc support.

#if defined(__x86_64__) || defined(__i386__)
#define ACCELCAL_TARGET_AVX2_FMA __attribute__((target("avx2,fma")))
#else
#define ACCELCAL_TARGET_AVX2_FMA
#endif

namespace accelcal {

// True when this CPU has AVX2 and FMA and the OS saves the AVX registers, unless the
// environment sets ACCELCAL_DISABLE_AVX2 (to anything but "" or "0"), which runs the
// baseline versions instead: to reproduce an older machine's last bits, or to test those
// versions here (ACCELCAL_DISABLE_AVX2=1 ctest). Read once per process.
bool CpuHasAvx2Fma();

}  // namespace accelcal

#endif  // ACCELCAL_COMMON_CPU_FEATURES_H_
