// The batch sine and cosine kernel (common/sincos.h) against long double sinl/cosl, for
// both compiled versions (baseline SSE2 and AVX2 + FMA, the latter when this CPU has
// it) and the dispatching SinCos; and its user, the baseline's CalibrationAccumulator::
// AddTest, against the sample-by-sample Add that it replaces.
//
// The criterion is the error in ulps of the exact result, everywhere, with no absolute
// tolerance near the zeros of sin and cos. An absolute 1e-16 would be enough for the
// tilt table (f = -g sin(theta) is compared with a noise of 0.5 m/s^2), but it would
// hide exactly the failure a Cody-Waite reduction can have: too few bits of pi/2, which
// leaves x - k pi/2 with an absolute error of k times the missing bits. That error is
// invisible next to a result of order 1 and is all of the result near a multiple of
// pi/2. Measured in ulps of the result, it shows; with the three-part split of pi/2 the
// kernel meets the same bound there as elsewhere, so the test asks for it.
//
// The truth: glibc's sinl/cosl carry 64 bits, and reduce with a many-word pi, so their
// error is below 1/1000 of a double's ulp.

#include "common/sincos.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "common/cpu_features.h"
#include "estimation/tilt_table/linear_ls.h"
#include "simulation/simulator.h"

namespace accelcal {
namespace {

using SinCosFunction = void (*)(const double*, std::size_t, double*, double*);

struct Version {
  std::string name;
  SinCosFunction function;
};

// Every version this machine can run.
std::vector<Version> Versions() {
  std::vector<Version> versions = {{"SinCos", &SinCos},
                                   {"SinCosBaseline", &sincos_internal::SinCosBaseline}};
  if (CpuHasAvx2Fma()) {
    versions.push_back({"SinCosAvx2Fma", &sincos_internal::SinCosAvx2Fma});
  } else {
    std::printf(
        "AVX2 + FMA absent or disabled (ACCELCAL_DISABLE_AVX2): SinCosAvx2Fma not tested\n");
  }
  return versions;
}

// The acceptance bound, in ulps of the exact result. The kernel measures 0.79 at most
// (each test prints its figures); 2 leaves room for a compiler that rounds differently
// (fusing other products into FMAs, say) without letting a real loss of bits through.
constexpr double kMaxUlp = 2.0;

// The spacing of doubles at `truth`: 2^(e-52) for |truth| in [2^e, 2^(e+1)), and the
// subnormal spacing below DBL_MIN.
double UlpAt(long double truth) {
  const double rounded = static_cast<double>(truth);
  if (rounded == 0.0) return std::numeric_limits<double>::denorm_min();
  return std::max(std::ldexp(1.0, std::ilogb(rounded) - 52),
                  std::numeric_limits<double>::denorm_min());
}

double UlpError(double computed, long double truth) {
  return static_cast<double>(std::fabs(computed - truth) / UlpAt(truth));
}

// The largest error over a set of arguments, and where.
struct WorstError {
  double ulp = 0.0;
  double x = 0.0;
  const char* function = "";

  void Add(double x_value, double computed, long double truth, const char* name) {
    const double error = UlpError(computed, truth);
    if (error > ulp || std::isnan(error)) {
      ulp = error;
      x = x_value;
      function = name;
    }
  }
};

// Runs `version` on `x`, compares with sinl/cosl (and reports the distance to
// std::sin/std::cos, for information), and checks the bound.
WorstError CheckAgainstLongDouble(const Version& version, const std::vector<double>& x,
                                  const std::string& what) {
  std::vector<double> sin_x(x.size());
  std::vector<double> cos_x(x.size());
  version.function(x.data(), x.size(), sin_x.data(), cos_x.data());
  WorstError worst;
  WorstError worst_std;  // glibc's own double sin/cos, for comparison
  for (std::size_t i = 0; i < x.size(); ++i) {
    const long double sin_truth = sinl(static_cast<long double>(x[i]));
    const long double cos_truth = cosl(static_cast<long double>(x[i]));
    worst.Add(x[i], sin_x[i], sin_truth, "sin");
    worst.Add(x[i], cos_x[i], cos_truth, "cos");
    worst_std.Add(x[i], std::sin(x[i]), sin_truth, "sin");
    worst_std.Add(x[i], std::cos(x[i]), cos_truth, "cos");
  }
  std::printf("%-14s %-34s %9zu points: max error %.3f ulp (%s at x = %.17g); std:: %.3f ulp\n",
              version.name.c_str(), what.c_str(), x.size(), worst.ulp, worst.function, worst.x,
              worst_std.ulp);
  EXPECT_LE(worst.ulp, kMaxUlp) << version.name << ", " << what << ": " << worst.function
                                << " at x = " << worst.x;
  return worst;
}

// Uniform in [0, 1) from the top 53 bits: the same sequence on every platform.
double Uniform(std::mt19937_64* random) { return static_cast<double>((*random)() >> 11) * 0x1p-53; }

constexpr double kPi = 3.14159265358979323846;

TEST(SinCos, SplitOfHalfPiMatchesMachinsFormula) {
  // pi/2 = 8 atan(1/5) - 2 atan(1/239) in fixed point with 127 fractional bits. Every
  // term floor(2^127 / x^(2n+1)) is exact (repeated floor division is the floor of the
  // quotient) and its division by 2n+1 truncates by less than 1, so the error is below
  // 2 units per term: 28 terms of atan(1/5) times 8 and 9 of atan(1/239) times 2 make
  // under 2^9 units, 2^-118.
  using Fixed = unsigned __int128;
  const Fixed one = static_cast<Fixed>(1) << 127;
  const auto arctan_of_inverse = [&](unsigned x) {
    Fixed sum = 0;
    Fixed power = one / x;  // 2^127 / x^(2n+1), n = 0, 1, ...
    bool add = true;
    for (unsigned n = 0; power != 0; ++n) {
      const Fixed term = power / (2 * n + 1);
      sum = add ? sum + term : sum - term;
      add = !add;
      power /= static_cast<Fixed>(x) * x;
    }
    return sum;
  };
  const Fixed half_pi = 8 * arctan_of_inverse(5) - 2 * arctan_of_inverse(239);
  const auto to_fixed = [](double part) {
    // Exact: every part is a multiple of 2^-127 below 2.
    return (static_cast<Fixed>(std::ldexp(part, 127 - 64)) << 64) |
           static_cast<Fixed>(std::fmod(std::ldexp(part, 127), 0x1p64));
  };
  const Fixed part1 = to_fixed(sincos_internal::kHalfPi1);
  const Fixed part2 = to_fixed(sincos_internal::kHalfPi2);
  const Fixed part3 = to_fixed(sincos_internal::kHalfPi3);
  // kHalfPi1: pi/2 truncated to 33 significant bits (its leading bit is 2^0).
  EXPECT_TRUE(part1 == half_pi >> (127 - 32) << (127 - 32));
  // kHalfPi2: the next 33 significant bits of the remainder.
  const Fixed remainder1 = half_pi - part1;
  const int leading2 = 127 - __builtin_clzll(static_cast<std::uint64_t>(remainder1 >> 64));
  EXPECT_TRUE(part2 == remainder1 >> (leading2 - 32) << (leading2 - 32));
  // kHalfPi3: the rest, to within the Machin sum's error (< 2^9 units) plus half an ulp
  // of kHalfPi3 (2^5 units).
  const Fixed remainder2 = remainder1 - part2;
  const Fixed difference = remainder2 > part3 ? remainder2 - part3 : part3 - remainder2;
  EXPECT_TRUE(difference < (static_cast<Fixed>(1) << 10))
      << "kHalfPi3 is off by " << static_cast<double>(difference) << " x 2^-127";
  // And the parts are short enough for exact products k * part for |k| < 2^20.
  for (const double part : {sincos_internal::kHalfPi1, sincos_internal::kHalfPi2}) {
    int exponent;
    const double mantissa = std::frexp(part, &exponent);
    EXPECT_EQ(std::ldexp(mantissa, 33), std::trunc(std::ldexp(mantissa, 33))) << part;
  }
  const double largest_k = std::nearbyint(kSinCosFastPathLimitRad * 2 / kPi);
  EXPECT_LT(largest_k, 0x1p20);
}

TEST(SinCos, AccurateOnFourMillionPointsInPlusMinusFourPi) {
  std::vector<double> x;
  const int grid = 1 << 21;  // evenly spaced, ends included
  for (int i = 0; i <= grid; ++i) x.push_back(-4 * kPi + 8 * kPi * i / grid);
  std::mt19937_64 random(20180529);
  for (int i = 0; i < (1 << 21); ++i) x.push_back(-4 * kPi + 8 * kPi * Uniform(&random));
  for (const Version& version : Versions()) CheckAgainstLongDouble(version, x, "[-4 pi, 4 pi]");
}

TEST(SinCos, AccurateForRandomArgumentsUpToTheLimit) {
  std::mt19937_64 random(7);
  std::vector<double> uniform;
  std::vector<double> log_uniform;  // magnitudes from 2^-40 to the limit
  for (int i = 0; i < (1 << 19); ++i) {
    uniform.push_back(kSinCosFastPathLimitRad * (2 * Uniform(&random) - 1));
    const double magnitude = std::ldexp(1.0, -40 + static_cast<int>(60 * Uniform(&random)));
    log_uniform.push_back((Uniform(&random) < 0.5 ? -1 : 1) * magnitude * (1 + Uniform(&random)));
  }
  for (const Version& version : Versions()) {
    CheckAgainstLongDouble(version, uniform, "uniform in [-2^20, 2^20]");
    CheckAgainstLongDouble(version, log_uniform, "log-uniform 2^-40..2^20");
  }
}

TEST(SinCos, AccurateNearMultiplesOfHalfPi) {
  // The double nearest k pi/2 (k pi/2 is rounded from long double, so for large k it
  // may be a neighbour of the nearest) and 4 neighbours each side: there sin or cos is
  // of the order of x 2^-53, and its ulp error measures the reduction's bits of pi/2.
  // Every k up to 2^14, then random k up to the limit.
  std::vector<double> x;
  std::mt19937_64 random(11);
  const long double half_pi = 1.57079632679489661923132169163975144L;
  const double largest_k = std::floor(kSinCosFastPathLimitRad / static_cast<double>(half_pi));
  for (int i = 0; i < (1 << 15); ++i) {
    const double k = i <= (1 << 14) ? i : std::floor(largest_k * Uniform(&random));
    for (const double sign : {1.0, -1.0}) {
      const double nearest = sign * static_cast<double>(k * half_pi);
      double below = nearest;
      double above = nearest;
      x.push_back(nearest);
      for (int step = 0; step < 4; ++step) {
        below = std::nextafter(below, -HUGE_VAL);
        above = std::nextafter(above, HUGE_VAL);
        x.push_back(below);
        x.push_back(above);
      }
    }
  }
  for (const Version& version : Versions()) {
    CheckAgainstLongDouble(version, x, "nearest doubles to k pi/2");
  }
}

TEST(SinCos, SpecialValues) {
  const double limit = kSinCosFastPathLimitRad;
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> x = {0.0,
                                 -0.0,
                                 std::numeric_limits<double>::denorm_min(),
                                 -std::numeric_limits<double>::denorm_min(),
                                 DBL_MIN,
                                 1e-300,
                                 -1e-160,
                                 1e-8,
                                 kPi / 4,
                                 -kPi / 4,
                                 limit,
                                 -limit,
                                 std::nextafter(limit, inf),
                                 -std::nextafter(limit, inf),
                                 1e10,
                                 -1e22,
                                 1e300,
                                 DBL_MAX,
                                 inf,
                                 -inf,
                                 nan,
                                 -nan};
  for (const Version& version : Versions()) {
    SCOPED_TRACE(version.name);
    std::vector<double> sin_x(x.size());
    std::vector<double> cos_x(x.size());
    version.function(x.data(), x.size(), sin_x.data(), cos_x.data());
    for (std::size_t i = 0; i < x.size(); ++i) {
      char trace[64];
      std::snprintf(trace, sizeof trace, "x = %.17g", x[i]);
      SCOPED_TRACE(trace);
      if (std::isnan(x[i]) || std::isinf(x[i])) {
        EXPECT_TRUE(std::isnan(sin_x[i]));
        EXPECT_TRUE(std::isnan(cos_x[i]));
      } else if (std::fabs(x[i]) > limit) {
        // Beyond the limit the kernel is std::sin and std::cos.
        EXPECT_EQ(sin_x[i], std::sin(x[i]));
        EXPECT_EQ(cos_x[i], std::cos(x[i]));
      } else {
        EXPECT_LE(UlpError(sin_x[i], sinl(x[i])), kMaxUlp);
        EXPECT_LE(UlpError(cos_x[i], cosl(x[i])), kMaxUlp);
      }
    }
    // sin is odd down to the sign of zero, and exact for tiny arguments.
    EXPECT_TRUE(sin_x[0] == 0.0 && !std::signbit(sin_x[0]));
    EXPECT_TRUE(sin_x[1] == 0.0 && std::signbit(sin_x[1]));
    EXPECT_EQ(cos_x[0], 1.0);
    EXPECT_EQ(cos_x[1], 1.0);
    EXPECT_EQ(sin_x[2], x[2]);
    EXPECT_EQ(sin_x[3], x[3]);
    EXPECT_EQ(sin_x[5], 1e-300);
    EXPECT_EQ(cos_x[5], 1.0);
  }
}

TEST(SinCos, EveryLengthAndOffsetIsHandled) {
  // Vector bodies, scalar remainders and unaligned starts, with an out-of-limit value
  // at a varying position so that the second pass is exercised inside each.
  std::vector<double> x(80);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = 0.37 * i - 11.0;
  for (const Version& version : Versions()) {
    SCOPED_TRACE(version.name);
    for (std::size_t offset = 0; offset < 4; ++offset) {
      for (std::size_t n = 0; n + offset <= 67; ++n) {
        std::vector<double> input(x.begin() + offset, x.begin() + offset + n);
        if (n > 0) input[n / 2] = 3e7;
        std::vector<double> sin_x(n + 1, -7.0);  // one past the end must stay untouched
        std::vector<double> cos_x(n + 1, -7.0);
        version.function(input.data(), n, sin_x.data(), cos_x.data());
        for (std::size_t i = 0; i < n; ++i) {
          EXPECT_LE(UlpError(sin_x[i], sinl(input[i])), kMaxUlp) << n << " " << i;
          EXPECT_LE(UlpError(cos_x[i], cosl(input[i])), kMaxUlp) << n << " " << i;
        }
        EXPECT_EQ(sin_x[n], -7.0);
        EXPECT_EQ(cos_x[n], -7.0);
      }
    }
  }
}

// The baseline's bias and scale of one axis from long double sums of long double
// sinl/cosl, centred in a second pass: a reference far more accurate than either path.
void LongDoubleAxisFit(const CalibrationTest& test, bool x_axis, double gravity_mps2,
                       long double* bias, long double* scale) {
  const auto force = [&](int i) {
    const long double theta = test.theta_rad[i];
    return -gravity_mps2 * (x_axis ? sinl(theta) : cosl(theta));
  };
  const auto response = [&](int i) {
    return (x_axis ? test.measured_x[i] : test.measured_y[i]) - force(i);
  };
  const long double n = test.size();
  long double sum_force = 0;
  long double sum_response = 0;
  for (int i = 0; i < test.size(); ++i) {
    sum_force += force(i);
    sum_response += response(i);
  }
  const long double mean_force = sum_force / n;
  const long double mean_response = sum_response / n;
  long double force_force = 0;
  long double force_response = 0;
  for (int i = 0; i < test.size(); ++i) {
    force_force += (force(i) - mean_force) * (force(i) - mean_force);
    force_response += (force(i) - mean_force) * (response(i) - mean_response);
  }
  *scale = force_response / force_force;
  *bias = mean_response - *scale * mean_force;
}

// AddTest (SinCos, block sums in vector lanes) against Add (std::sin and std::cos, one
// running sum), on the course's design and on a narrow off-centre one where the bias is
// ill-conditioned, at lengths around the block and lane sizes. The sums differ by the
// rounding of sin and cos (within an ulp each) and the order of the additions: about
// 1e-14 relative. On the narrow design the conditioning magnifies that to 1e-11 in the
// bias, almost all of it Add's own error: against a long double reference AddTest's
// parameters are the more accurate ones, by a factor 10 to 50 (its shorter sums).
TEST(CalibrationAccumulator, AddTestAgreesWithAddSampleBySample) {
  const SimulationTruth truth = CourseTableOneTruth();
  LinearLsOptions options;
  options.noise_variance_x = truth.stated_noise_variance_x;
  options.noise_variance_y = truth.stated_noise_variance_y;
  double worst_sum = 0.0;
  double worst_add_test = 0.0;
  double worst_add = 0.0;
  for (const bool narrow : {false, true}) {
    for (const int samples : {0, 1, 3, 4, 5, 511, 512, 513, 1027, 20001}) {
      SCOPED_TRACE((narrow ? "angles in [1.0, 1.3] rad, " : "one turn, ") +
                   std::to_string(samples) + " samples");
      TiltSchedule schedule;
      schedule.sample_count = samples;
      if (narrow) {
        schedule.theta_begin_rad = 1.0;
        schedule.theta_end_rad = 1.3;
      }
      const CalibrationTest test = SimulateTiltTest(schedule, truth, 5);
      CalibrationAccumulator one_by_one(truth.gravity_mps2);
      for (int i = 0; i < test.size(); ++i) {
        one_by_one.Add(test.theta_rad[i], test.measured_x[i], test.measured_y[i]);
      }
      CalibrationAccumulator batch(truth.gravity_mps2);
      batch.AddTest(test);
      // Continuing after a first sample must use the shifts it set.
      CalibrationAccumulator continued(truth.gravity_mps2);
      if (samples > 0) {
        continued.Add(test.theta_rad[0], test.measured_x[0], test.measured_y[0]);
        CalibrationTest rest = test;
        rest.theta_rad.erase(rest.theta_rad.begin());
        rest.measured_x.erase(rest.measured_x.begin());
        rest.measured_y.erase(rest.measured_y.begin());
        continued.AddTest(rest);
      }
      for (const CalibrationAccumulator* other : {&batch, &continued}) {
        ASSERT_EQ(other->x().count(), one_by_one.x().count());
        if (samples == 0) continue;
        EXPECT_EQ(other->theta_min_rad(), one_by_one.theta_min_rad());
        EXPECT_EQ(other->theta_max_rad(), one_by_one.theta_max_rad());
        for (const bool x_axis : {true, false}) {
          const AxisRegressionAccumulator& expected = x_axis ? one_by_one.x() : one_by_one.y();
          const AxisRegressionAccumulator& actual = x_axis ? other->x() : other->y();
          // Means on the scale of g; centred sums on the scale of their Cauchy-Schwarz
          // bound (the cross sum can be near 0 on its own).
          const double ff = expected.CenteredForceForce();
          const double yy = expected.CenteredResponseResponse();
          const double differences[] = {
              std::fabs(actual.MeanForce() - expected.MeanForce()) / truth.gravity_mps2,
              std::fabs(actual.MeanResponse() - expected.MeanResponse()) / truth.gravity_mps2,
              std::fabs(actual.CenteredForceForce() - ff) / std::max(ff, 1e-300),
              std::fabs(actual.CenteredResponseResponse() - yy) / std::max(yy, 1e-300),
              std::fabs(actual.CenteredForceResponse() - expected.CenteredForceResponse()) /
                  std::max(std::sqrt(ff * yy), 1e-300)};
          for (const double difference : differences) {
            EXPECT_LE(difference, 1e-12);
            worst_sum = std::max(worst_sum, difference);
          }
        }
      }
      if (samples < 3) continue;
      BaselineFit add_fit;
      BaselineFit add_test_fit;
      // A few narrow samples may be refused (bias and scale inseparable); both alike.
      const bool solvable = SolveLinearLs(one_by_one, options, &add_fit).ok();
      ASSERT_EQ(SolveLinearLs(batch, options, &add_test_fit).ok(), solvable);
      if (!solvable) continue;
      long double reference[4];
      LongDoubleAxisFit(test, true, truth.gravity_mps2, &reference[0], &reference[1]);
      LongDoubleAxisFit(test, false, truth.gravity_mps2, &reference[2], &reference[3]);
      for (int k = 0; k < 4; ++k) {
        const auto relative_error = [&](double parameter) {
          return static_cast<double>(fabsl(parameter - reference[k]) / fabsl(reference[k]));
        };
        // The narrow design's bias is ill-conditioned (x: correlation 0.999 with the scale):
        // 1e-11 there, 1e-12 on the course's full turn.
        EXPECT_LE(relative_error(add_test_fit.parameters[k]), narrow ? 1e-11 : 1e-12)
            << "parameter " << k;
        EXPECT_LE(relative_error(add_fit.parameters[k]), 1e-9) << "parameter " << k;
        worst_add_test = std::max(worst_add_test, relative_error(add_test_fit.parameters[k]));
        worst_add = std::max(worst_add, relative_error(add_fit.parameters[k]));
      }
    }
  }
  std::printf(
      "AddTest vs Add: sums differ by %.2g relative at most; parameters' largest "
      "relative error against long double: AddTest %.2g, Add %.2g\n",
      worst_sum, worst_add_test, worst_add);
}

}  // namespace
}  // namespace accelcal
