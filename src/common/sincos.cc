#include "common/sincos.h"

#include <cmath>
#include <cstdint>
#include <cstring>

#include "common/cpu_features.h"

namespace accelcal {
namespace sincos_internal {
namespace {

// 1/n!, each rounded once (n! is an exact double for n <= 18).
constexpr double InverseFactorial(int n) {
  double factorial = 1.0;
  for (int i = 2; i <= n; ++i) factorial *= i;
  return 1.0 / factorial;
}

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
  for (std::size_t i = 0; i < n; ++i) {
    const double xi = x[i];
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

    // Taylor series on |r| <= pi/4 (a little more if x 2/pi rounded up to k + 1/2):
    //   sin r = r + r^3 S(r^2),         S(z) = -1/3! + z/5! - ... + z^7/17!
    //   cos r = 1 - r^2/2 + r^4 C(r^2), C(z) = 1/4! - z/6! + ... - z^7/18!
    // The first omitted terms, r^19/19! and r^20/20!, are below 1e-19, a thousandth of
    // an ulp of the results.
    const double z = r * r;
    double sin_poly = InverseFactorial(17);
    sin_poly = sin_poly * z - InverseFactorial(15);
    sin_poly = sin_poly * z + InverseFactorial(13);
    sin_poly = sin_poly * z - InverseFactorial(11);
    sin_poly = sin_poly * z + InverseFactorial(9);
    sin_poly = sin_poly * z - InverseFactorial(7);
    sin_poly = sin_poly * z + InverseFactorial(5);
    sin_poly = sin_poly * z - InverseFactorial(3);
    double cos_poly = -InverseFactorial(18);
    cos_poly = cos_poly * z + InverseFactorial(16);
    cos_poly = cos_poly * z - InverseFactorial(14);
    cos_poly = cos_poly * z + InverseFactorial(12);
    cos_poly = cos_poly * z - InverseFactorial(10);
    cos_poly = cos_poly * z + InverseFactorial(8);
    cos_poly = cos_poly * z - InverseFactorial(6);
    cos_poly = cos_poly * z + InverseFactorial(4);
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
  // A second, cheap pass for what the reduction cannot handle. Keeping it out of the
  // loop above keeps that loop free of calls; the garbage it wrote for these elements
  // (inf - inf and the like, no undefined behaviour) is overwritten here.
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
