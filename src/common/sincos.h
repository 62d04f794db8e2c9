#ifndef ACCELCAL_COMMON_SINCOS_H_
#define ACCELCAL_COMMON_SINCOS_H_

// Sine and cosine of a whole array at once, for the loops that need both per sample (the
// tilt table's f_x = -g sin(theta), f_y = -g cos(theta) over tens of thousands of angles).
// std::sin plus std::cos cost 7.5 to 12 ns per element: two scalar calls, each handling
// any argument with branches. This kernel is one branch-free loop that the compiler
// vectorizes: 1.9 ns per element for both with AVX2 + FMA, 5.3 ns with SSE2 (2-core AMD
// EPYC VM; tools/bench/monte_carlo_bench.cc, BM_SinCos; docs/performance.md).
//
// How: x = k pi/2 + r with k the nearest integer to x 2/pi and |r| <= pi/4 (Cody-Waite
// reduction with pi/2 split in three parts, below), then minimax polynomials for sin r and
// cos r, and the quadrant k mod 4 picks which one, with which sign, goes where:
//
//   k mod 4:     0        1        2        3
//   sin x    =  sin r    cos r   -sin r   -cos r
//   cos x    =  cos r   -sin r   -cos r    sin r
//
// Accuracy: within 1 ulp of the exact result for |x| <= kSinCosFastPathLimitRad (0.79
// ulp at most over millions of arguments, against long double sinl/cosl in
// tests/sincos_test.cc), including at the doubles nearest to multiples of pi/2, where
// the result is tiny and a reduction with too few bits of pi/2 would lose all of its
// significant digits. Beyond the limit, and for inf and NaN, each element is computed by
// std::sin and std::cos instead.
//
// On x86-64 the loop is compiled twice, for the baseline ISA (SSE2) and for AVX2 + FMA,
// and the first call picks the version the CPU runs. The results of the two versions
// can differ in the last bit (FMA rounds once where SSE2 rounds twice); both are
// within the same bound.

#include <cstddef>

namespace accelcal {

// The reduction is exact while k times a 33-bit part of pi/2 fits in a double's 53 bits,
// i.e. |k| < 2^20, |x| < 2^20 pi/2 = 1.6e6 rad; the limit is the power of two below,
// where |k| <= 667 544. That is 167 000 turns, far more than any table angle; beyond it
// std::sin and std::cos, which reduce with as many bits of pi as it takes, are used.
constexpr double kSinCosFastPathLimitRad = 1048576.0;  // 2^20

// sin_out[i] = sin(x[i]) and cos_out[i] = cos(x[i]) for i < n. The three arrays must not
// overlap.
void SinCos(const double* x, std::size_t n, double* sin_out, double* cos_out);

namespace sincos_internal {

// pi/2 = kHalfPi1 + kHalfPi2 + kHalfPi3 + O(2^-122). kHalfPi1 and kHalfPi2 are the
// first 33 significant bits of pi/2 and the next 33 significant bits of what remains,
// so that k kHalfPi1 and k kHalfPi2 are exact for |k| < 2^20; kHalfPi3 is the rest,
// rounded to 53 bits. The bits are those of pi's binary expansion (pi/2 =
// 0x1.921fb54442d18469898cc51701b839a2...); tests/sincos_test.cc recomputes them from
// Machin's formula in 128-bit integers and checks these constants against it.
constexpr double kHalfPi1 = 0x1.921fb544p+0;
constexpr double kHalfPi2 = 0x1.0b4611a6p-34;
constexpr double kHalfPi3 = 0x1.3198a2e037073p-69;

// The two compiled versions (common/cpu_features.h), so that the tests can check both.
// SinCosAvx2Fma needs CpuHasAvx2Fma(); elsewhere than x86 both are the portable version.
void SinCosBaseline(const double* x, std::size_t n, double* sin_out, double* cos_out);
void SinCosAvx2Fma(const double* x, std::size_t n, double* sin_out, double* cos_out);

}  // namespace sincos_internal
}  // namespace accelcal

#endif  // ACCELCAL_COMMON_SINCOS_H_
