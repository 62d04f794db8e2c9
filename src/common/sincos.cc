#include "common/sincos.h"

#include <cmath>
#include <cstdint>
#include <cstring>

#include "common/cpu_features.h"

namespace accelcal {
namespace sincos_internal {
namespace {

// The reduction's error terms and the rounding trick below are exact IEEE arithmetic,
// which -ffast-math would "simplify" to zero.
#ifdef __FAST_MATH__
#error "common/sincos.cc must not be compiled with -ffast-math"
#endif

constexpr double kTwoOverPi = 0x1.45f306dc9c883p-1;  // 2/pi rounded; only picks k
// Adding 1.5 2^52 rounds to the nearest integer (the sum's unit in the last place is 1)
// and leaves that integer, in two's complement, in the low bits of the sum's mantissa
// for |value| < 2^51. Needs the default round-to-nearest mode.
constexpr double kRoundingMagic = 0x1.8p52;

inline std::uint64_t Bits(double value) {
  std::uint64_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

const std::uint64_t kFastPathLimitBits = Bits(kSinCosFastPathLimitRad);

inline double FromBits(std::uint64_t bits) {
  double value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

// The loop body for both compiled versions. No branch, no call, no table: every lane
// does the same arithmetic, so the vectorizer can take the loop whole.
__attribute__((always_inline)) inline void SinCosLoop(const double* __restrict x, std::size_t n,
                                                      double* __restrict sin_out,
                                                      double* __restrict cos_out) {
  // Its top bit is set when some |x[i]| exceeds the fast path's limit or x[i] is NaN. The
  // bit patterns of non-negative doubles order like their values, with every NaN above
  // infinity, and both are below 2^63, so limit - bits(|x|) wraps to a set top bit exactly
  // when |x| is beyond the limit. Subtraction and OR vectorize on every x86-64 (a 64-bit
  // compare needs SSE4.2, and cost the SSE2 version half its speed).
  std::uint64_t outside_fast_path = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double xi = x[i];
    outside_fast_path |= kFastPathLimitBits - Bits(std::fabs(xi));
    const double rounded = xi * kTwoOverPi + kRoundingMagic;
    const double k = rounded - kRoundingMagic;
    const std::uint64_t quadrant = Bits(rounded) & 3;

    // r = x - k pi/2 as r + c, c the rounding error of the two subtractions that can
    // round. x - k kHalfPi1 is exact (k kHalfPi1 is exact and, for k != 0, within a
    // factor 2 of x: Sterbenz), so is k kHalfPi2; k kHalfPi3 rounds by ~k 2^-122, far
    // below what matters. Each error term is the Fast2Sum (a - s) - b of s = a - b.
    // Where the compiler fuses a product into an FMA (the AVX2 + FMA version), the
    // product is exact there too, and an error term then also covers its rounding.
    const double t1 = xi - k * kHalfPi1;
    const double p2 = k * kHalfPi2;
    const double t2 = t1 - p2;
    const double e2 = (t1 - t2) - p2;
    const double p3 = k * kHalfPi3;
    const double r = t2 - p3;
    const double c = ((t2 - r) - p3) + e2;

    // Minimax polynomials on |r| <= pi/4 (a little more if x 2/pi rounded up to k + 1/2):
    //   sin r = r + r^3 S(r^2),         S of degree 5 (r^13)
    //   cos r = 1 - r^2/2 + r^4 C(r^2), C of degree 5 (r^14)
    // with fdlibm's coefficients (k_sin.c, k_cos.c), whose approximation errors are below
    // 2^-58 relative, a thirtieth of an ulp. Taylor series reaching that need r^17 and r^18:
    // two more multiply-adds each, 15% of the kernel's time.
    const double z = r * r;
    double sin_poly = 0x1.5d93a5acfd57cp-33;
    sin_poly = sin_poly * z - 0x1.ae5e68a2b9cebp-26;
    sin_poly = sin_poly * z + 0x1.71de357b1fe7dp-19;
    sin_poly = sin_poly * z - 0x1.a01a019c161d5p-13;
    sin_poly = sin_poly * z + 0x1.111111110f8a6p-7;
    sin_poly = sin_poly * z - 0x1.5555555555549p-3;
    double cos_poly = -0x1.8fae9be8838d4p-37;
    cos_poly = cos_poly * z + 0x1.1ee9ebdb4b1c4p-29;
    cos_poly = cos_poly * z - 0x1.27e4f809c52adp-22;
    cos_poly = cos_poly * z + 0x1.a01a019cb1590p-16;
    cos_poly = cos_poly * z - 0x1.6c16c16c15177p-10;
    cos_poly = cos_poly * z + 0x1.555555555554cp-5;
    const double half_z = 0.5 * z;
    // sin(r + c) = sin r + c cos r to far below an ulp (c is at most an ulp of r), with
    // cos r ~ 1 - r^2/2. The large term r is added last, so the result rounds once.
    // The sum turns r = -0 into -0 + +0 = +0; sin r has the sign of r on [-pi/4, pi/4],
    // so copying it back (a bit operation, unlike a select on r == 0, which made GCC
    // give up on vectorizing the loop) puts -0 right and changes nothing else.
    const double sin_r = std::copysign(r + (r * z * sin_poly + c * (1.0 - half_z)), r);
    // cos(r + c) = cos r - c sin r. 1 - r^2/2 is the large part; w + ((1 - w) - r^2/2)
    // keeps the rounding error of w = 1 - r^2/2 (exact by Sterbenz: w is in [0.69, 1]),
    // which would otherwise be half an ulp on its own.
    const double w = 1.0 - half_z;
    const double cos_r = w + (((1.0 - w) - half_z) + (z * z * cos_poly - c * r));

    // The quadrant as bit masks: swap the two when k is odd, then flip sin's sign in
    // quadrants 2 and 3 and cos's in 1 and 2.
    const std::uint64_t swap_mask = 0 - (quadrant & 1);
    const std::uint64_t sin_sign = (quadrant & 2) << 62;
    const std::uint64_t cos_sign = ((quadrant + 1) & 2) << 62;
    const std::uint64_t sin_bits = Bits(sin_r);
    const std::uint64_t cos_bits = Bits(cos_r);
    sin_out[i] = FromBits(((sin_bits & ~swap_mask) | (cos_bits & swap_mask)) ^ sin_sign);
    cos_out[i] = FromBits(((cos_bits & ~swap_mask) | (sin_bits & swap_mask)) ^ cos_sign);
  }
  // A second pass, only when the loop saw them, for what the reduction cannot handle.
  // Keeping it out of the loop above keeps that loop free of calls; the garbage it wrote
  // for these elements (inf - inf and the like, no undefined behaviour) is overwritten
  // here. (Run unconditionally it cost a third of the kernel's time.)
  if ((outside_fast_path >> 63) == 0) return;
  for (std::size_t i = 0; i < n; ++i) {
    if (!(std::fabs(x[i]) <= kSinCosFastPathLimitRad)) {
      sin_out[i] = std::sin(x[i]);
      cos_out[i] = std::cos(x[i]);
    }
  }
}

}  // namespace

void SinCosBaseline(const double* x, std::size_t n, double* sin_out, double* cos_out) {
  SinCosLoop(x, n, sin_out, cos_out);
}

ACCELCAL_TARGET_AVX2_FMA void SinCosAvx2Fma(const double* x, std::size_t n, double* sin_out,
                                            double* cos_out) {
  SinCosLoop(x, n, sin_out, cos_out);
}

}  // namespace sincos_internal

void SinCos(const double* x, std::size_t n, double* sin_out, double* cos_out) {
  if (CpuHasAvx2Fma()) {
    sincos_internal::SinCosAvx2Fma(x, n, sin_out, cos_out);
  } else {
    sincos_internal::SinCosBaseline(x, n, sin_out, cos_out);
  }
}

}  // namespace accelcal
