// The fast paths of imu_tk's calibration (issue 20, docs/performance.md) against the plain
// definitions they replace: the batch residual's hand-written Jacobian against automatic
// differentiation of the one-sample residual, the running-sum sliding variance against the
// two-pass variance of each window, and the log reader's decimal parser against
// std::from_chars.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "common/triad_log.h"
#include "estimation/triad/static_intervals.h"
#include "io/csv_reader.h"
#include "io/imu_log.h"
#include "models/triad.h"
#include "residuals/imu_tk_residual.h"

namespace accelcal {
namespace {

TEST(ImuTkBatchResidual, EqualsTheAutodiffResidualAndJacobianOfEachSample) {
  std::mt19937 random(20);
  std::uniform_real_distribution<double> counts(20000.0, 45000.0);
  std::uniform_real_distribution<double> angle(-0.05, 0.05);
  std::uniform_real_distribution<double> gain(0.8e-3, 1.6e-3);
  std::uniform_real_distribution<double> offset(31000.0, 34000.0);
  const double gravity_mps2 = 9.81744;
  std::vector<std::array<double, 3>> raw(40);
  for (std::array<double, 3>& u : raw) u = {counts(random), counts(random), counts(random)};
  const ImuTkBatchResidual batch(raw, gravity_mps2);
  ASSERT_EQ(batch.num_residuals(), 40);
  for (int trial = 0; trial < 5; ++trial) {
    TriadParameters p = TriadParametersWithOffset(offset(random), offset(random), offset(random));
    for (int j = 0; j < 3; ++j) {
      p[kTriadMisalignmentYz + j] = angle(random);
      p[kTriadGainX + j] = gain(random);
    }
    const double* parameters[] = {p.data()};
    std::vector<double> residuals(raw.size());
    std::vector<double> jacobian(raw.size() * kTriadParameterCount);
    double* jacobians[] = {jacobian.data()};
    ASSERT_TRUE(batch.Evaluate(parameters, residuals.data(), jacobians));
    for (size_t i = 0; i < raw.size(); ++i) {
      const std::unique_ptr<ceres::CostFunction> single(
          ImuTkResidual::Create(raw[i], gravity_mps2));
      double residual = 0.0;
      double row[kTriadParameterCount];
      double* rows[] = {row};
      ASSERT_TRUE(single->Evaluate(parameters, &residual, rows));
      EXPECT_NEAR(residuals[i], residual, 1e-12 * std::abs(gravity_mps2)) << "sample " << i;
      for (int k = 0; k < kTriadParameterCount; ++k) {
        EXPECT_NEAR(jacobian[i * kTriadParameterCount + k], row[k], 1e-12 * std::abs(row[k]))
            << "sample " << i << ", parameter " << TriadParameterInfos()[k].name;
      }
    }
  }
}

// The two-pass norm of the window centred on each sample, as imu_tk computes it.
std::vector<double> TwoPassNorm(const TriadLog& log, int window) {
  const int n = static_cast<int>(log.size());
  const int half = window / 2;
  std::vector<double> norm(n, 0.0);
  for (int i = half; i < n - half; ++i) {
    const std::array<double, 3> v = IntervalVariance(log, i - half, i + half);
    norm[i] = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  }
  return norm;
}

// Integer counts around 32768 with rests and moves, as imu_tk's Xsens log: exact sums, so a
// few ulps from the two passes, whose own rounding grows with w (64-bit sums; 128-bit for the
// coarse counts, 500 times as large, in the longest window). The same in m/s^2 (not integers): the
// re-anchored sums lose digits in a rest that follows a large move, (move / noise)^2 ulps, here up
// to 1e-9.
TEST(SlidingVarianceNorm, EqualsTheTwoPassNormOfEveryWindow) {
  std::mt19937 random(7);
  std::normal_distribution<double> noise(0.0, 4.0);
  std::uniform_real_distribution<double> level(25000.0, 40000.0);
  TriadLog counts;
  TriadLog coarse;
  TriadLog scaled;
  std::array<double, 3> mean{32768.0, 32768.0, 32768.0};
  for (int i = 0; i < 5000; ++i) {
    if (i % 700 == 0) mean = {level(random), level(random), level(random)};
    const bool moving = i % 700 > 500;
    std::array<double, 3> u;
    for (int k = 0; k < 3; ++k) {
      u[k] = std::round(mean[k] + noise(random) * (moving ? 300.0 : 1.0));
    }
    counts.Add(0.01 * i, u[0], u[1], u[2]);
    coarse.Add(0.01 * i, 500.0 * u[0], 500.0 * u[1], 500.0 * u[2]);
    scaled.Add(0.01 * i, 3e-4 * (u[0] - 32768.0), 3e-4 * (u[1] - 32768.0), 3e-4 * (u[2] - 32768.0));
  }
  for (const int window : {3, 11, 101, 1001}) {
    for (const TriadLog* log : {&counts, &coarse, &scaled}) {
      const std::vector<double> fast = SlidingVarianceNorm(*log, window);
      const std::vector<double> reference = TwoPassNorm(*log, window);
      ASSERT_EQ(fast.size(), reference.size());
      const double tolerance = log == &scaled ? 1e-8 : 1e-13;
      for (size_t i = 0; i < fast.size(); ++i) {
        EXPECT_NEAR(fast[i], reference[i], tolerance * reference[i])
            << "window " << window << ", sample " << i
            << (log == &scaled ? " (m/s^2)" : " (counts)");
      }
    }
  }
  // Shorter than the window: nothing is classified.
  TriadLog short_log;
  for (int i = 0; i < 5; ++i) short_log.Add(i, 1.0, 2.0, 3.0);
  EXPECT_EQ(SlidingVarianceNorm(short_log, 11), std::vector<double>(5, 0.0));
}

// The reader's short-decimal path must give the double std::from_chars gives
// (ParseFiniteNumber), bit for bit, and accept and refuse the same cells: each cell is put in
// the x column of a two-sample log.
void ExpectReadAsParseFiniteNumber(const std::string& cell) {
  TriadLog log;
  const Status status = ParseImuLog("0 " + cell + " 2 3\n0.01 4 5 6\n", ImuLogReadOptions(), &log);
  double expected = 0.0;
  const bool number = ParseFiniteNumber(cell, &expected);
  ASSERT_EQ(status.ok(), number) << "'" << cell << "': " << status.message();
  if (number) {
    EXPECT_EQ(std::signbit(log.output[0][0]), std::signbit(expected)) << cell;
    EXPECT_EQ(log.output[0][0], expected) << "'" << cell << "'";
  }
}

TEST(ImuLogReader, ReadsEveryDecimalAsStdFromChars) {
  for (const char* cell : {"3.3108000e+04",
                           "0",
                           "-0",
                           "+0.0",
                           ".5",
                           "-.5",
                           "+.5",
                           "5.",
                           "1e5",
                           "1E+05",
                           "1.5e-0",
                           "1e",
                           "1e+",
                           "e5",
                           ".",
                           "-",
                           "+",
                           "+-5",
                           "-+5",
                           "1..2",
                           "1.2.3",
                           "0x10",
                           "1e22",
                           "1e23",
                           "1e-22",
                           "1e-23",
                           "9007199254740992",
                           "9007199254740993",
                           "12345678901234567890",
                           "1234567890123456789",
                           "0.000000000000000000000000000001",
                           "00000000000000000000001.5",
                           "1e999",
                           "1e-999",
                           "inf",
                           "nan",
                           "1,5",
                           "3.3108000e+04x",
                           "0.1",
                           "0.3",
                           "1.7976931e308"}) {
    ExpectReadAsParseFiniteNumber(cell);
  }
  std::mt19937 random(9);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-30, 30);
  std::uniform_int_distribution<int> precision(0, 20);
  char buffer[64];
  for (int trial = 0; trial < 20000; ++trial) {
    const double x = mantissa(random) * std::pow(10.0, exponent(random));
    const int digits = precision(random);
    const char* format = trial % 3 == 0 ? "%.*e" : trial % 3 == 1 ? "%.*f" : "%.*g";
    std::snprintf(buffer, sizeof(buffer), format, digits, x);
    ExpectReadAsParseFiniteNumber(buffer);
  }
}

}  // namespace
}  // namespace accelcal
