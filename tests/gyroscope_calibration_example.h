#ifndef ACCELCAL_TESTS_GYROSCOPE_CALIBRATION_EXAMPLE_H_
#define ACCELCAL_TESTS_GYROSCOPE_CALIBRATION_EXAMPLE_H_

// A triad's calibration with a gyroscope section, both in counts, of plausible size (an Xsens
// MTi's: 415 counts per m/s^2 about a mid-scale of 32768; 6258 counts per rad/s about an offset
// near 0) and a gyroscope covariance with correlations everywhere, for the calibration file's
// tests and apply's.

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <random>

#include "io/calibration_file.h"
#include "models/gyroscope.h"
#include "models/gyroscope_effect_list.h"
#include "models/triad.h"

namespace accelcal {
namespace testing {

inline GyroscopeParameters ExampleGyroscopeParameters() {
  GyroscopeParameters parameters =
      GyroscopeParametersWithGain(1.01 / 6258.0, 0.99 / 6258.0, 1.02 / 6258.0);
  const double angles[6] = {0.01, -0.02, 0.015, 0.005, -0.01, 0.02};  // yz, zy, zx, xz, xy, yx
  for (int p = 0; p < 6; ++p) parameters[kGyroscopeMisalignmentYz + p] = angles[p];
  return parameters;
}

inline GyroscopeOffset ExampleGyroscopeOffset() { return {31.5, -12.25, 7.0}; }

// sigma_i sigma_j rho_ij: sigmas of 1 mrad, 0.1% of the gain and 2 counts; the correlations of
// a random factor (fixed seed), so that every entry of J C J^T counts.
inline Eigen::MatrixXd ExampleGyroscopeCovariance() {
  constexpr int n = kGyroscopeCalibrationParameterCount;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::MatrixXd factor(n, n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) factor(i, j) = uniform(random) + (i == j ? 2.0 : 0.0);
  }
  const Eigen::MatrixXd product = factor * factor.transpose();
  const Eigen::VectorXd inverse = product.diagonal().cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd correlation = inverse.asDiagonal() * product * inverse.asDiagonal();
  Eigen::VectorXd sigma(n);
  const GyroscopeParameters parameters = ExampleGyroscopeParameters();
  for (int p = 0; p < n; ++p) {
    if (p < kGyroscopeGainX) {
      sigma[p] = 1e-3;
    } else if (p < kGyroscopeCalibrationOffsetX) {
      sigma[p] = 1e-3 * parameters[p];
    } else {
      sigma[p] = 2.0;
    }
  }
  return sigma.asDiagonal() * correlation * sigma.asDiagonal();
}

// The triad's part: small angles, gains 1/415 (m/s^2)/count, offsets near 32768 counts.
inline CalibrationRecord ExampleTriadRecord() {
  CalibrationRecord record;
  record.geometry = "triad";
  record.output_unit = "count";
  GeometryInfo geometry;
  EXPECT_TRUE(GeometryOf("triad", "count", &geometry).ok());
  record.parameter_order = geometry.parameters;
  record.values.resize(kTriadParameterCount);
  record.values << 0.002, -0.001, 0.003, 1.0 / 415.0, 1.01 / 415.0, 0.99 / 415.0, 32768.0 + 40.0,
      32768.0 - 25.0, 32768.0 + 10.0;
  Eigen::VectorXd variance(kTriadParameterCount);
  variance << 1e-8, 1e-8, 1e-8, 1e-14, 1e-14, 1e-14, 4.0, 4.0, 4.0;
  record.covariance = variance.asDiagonal();
  record.gravity_mps2 = 9.81;
  record.noise_variance = {36.0, 36.0, 49.0};
  record.noise_variance_from = "pooled within-pose variances";
  record.fit = {{"poses", 20}};
  record.poorly_determined = nlohmann::json::array();
  return record;
}

inline CalibrationRecord ExampleTriadRecordWithGyroscope() {
  CalibrationRecord record = ExampleTriadRecord();
  const Status status = MakeGyroscopeCalibrationSection(
      ExampleGyroscopeParameters(), ExampleGyroscopeOffset(), ExampleGyroscopeCovariance(),
      GyroscopeOutputUnit::kCount, &record.gyroscope);
  EXPECT_TRUE(status.ok()) << status.message();
  record.gyroscope.fit = {{"turns", 37}, {"chi2", 41.5}};
  record.has_gyroscope = true;
  return record;
}

// `record` given a gyroscope section of the example's 12 and the effect terms `terms` (indices
// into the block, in its order) at `values`, term t's variance `variances[t]` (no correlation),
// with the 12 unknowns' fit as its baseline: a version-2 section as calibrate_imu writes one.
inline void AddExampleGyroscopeTerms(const std::vector<int>& terms,
                                     const GyroscopeEffectCoefficients& values,
                                     const std::vector<double>& variances,
                                     CalibrationRecord* record) {
  const int n = kGyroscopeCalibrationParameterCount + static_cast<int>(terms.size());
  Eigen::MatrixXd covariance = Eigen::MatrixXd::Zero(n, n);
  covariance.topLeftCorner(12, 12) = ExampleGyroscopeCovariance();
  for (size_t t = 0; t < terms.size(); ++t) covariance(12 + t, 12 + t) = variances[t];
  const Status status = MakeGyroscopeCalibrationSection(
      ExampleGyroscopeParameters(), ExampleGyroscopeOffset(), terms, values, covariance,
      GyroscopeOutputUnit::kCount, &record->gyroscope);
  ASSERT_TRUE(status.ok()) << status.message();
  record->has_gyroscope = true;
  record->gyroscope.baseline.parameter_order.assign(record->gyroscope.parameter_order.begin(),
                                                    record->gyroscope.parameter_order.begin() + 12);
  record->gyroscope.baseline.values = record->gyroscope.values.head(12);
  record->gyroscope.baseline.covariance = ExampleGyroscopeCovariance();
}

}  // namespace testing
}  // namespace accelcal

#endif  // ACCELCAL_TESTS_GYROSCOPE_CALIBRATION_EXAMPLE_H_
