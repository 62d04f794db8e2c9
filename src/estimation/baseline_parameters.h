#ifndef ACCELCAL_ESTIMATION_BASELINE_PARAMETERS_H_
#define ACCELCAL_ESTIMATION_BASELINE_PARAMETERS_H_

// The baseline model's parameters and the fit both baseline solvers return.

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>

namespace accelcal {

// Order of the baseline parameter vector and of its covariance, named as in the spec.
enum BaselineParameter : int { kBiasX = 0, kScaleX = 1, kBiasY = 2, kScaleY = 3 };
constexpr int kBaselineParameterCount = 4;
constexpr std::array<const char*, kBaselineParameterCount> kBaselineParameterNames = {
    "bias_x", "scale_x", "bias_y", "scale_y"};
constexpr std::array<const char*, kBaselineParameterCount> kBaselineParameterUnits = {"m/s^2", "1",
                                                                                      "m/s^2", "1"};

// Goodness of fit of one axis against its stated noise variance.
struct AxisChiSquare {
  double chi2 = 0.0;  // sum of squared whitened residuals
  int dof = 0;        // samples minus the two fitted parameters
  // Two-sided p-value of chi2 under chi-square(dof): small when the residuals are
  // either larger or smaller than the stated noise explains.
  double p_value = 1.0;
};

struct BaselineFit {
  Eigen::Vector4d parameters = Eigen::Vector4d::Zero();  // bias_x, scale_x, bias_y, scale_y
  Eigen::Matrix4d covariance = Eigen::Matrix4d::Zero();  // same order
  AxisChiSquare chi2_x;
  AxisChiSquare chi2_y;
  int sample_count = 0;

  Eigen::Vector4d StandardDeviations() const { return covariance.diagonal().cwiseSqrt(); }
  Eigen::Matrix4d Correlation() const;
};

inline Eigen::Matrix4d BaselineFit::Correlation() const {
  const Eigen::Vector4d inverse_sigma = StandardDeviations().cwiseInverse();
  return inverse_sigma.asDiagonal() * covariance * inverse_sigma.asDiagonal();
}

// How far two fits of the same data are apart: the largest parameter difference
// relative to the parameter, and the largest covariance difference relative to
// sqrt(C_ii C_jj) (so near-zero off-diagonal terms are judged on the scale of the
// variances, not of themselves).
struct FitDifference {
  double parameters = 0.0;
  double covariance = 0.0;
};

inline FitDifference CompareFits(const BaselineFit& a, const BaselineFit& b) {
  FitDifference difference;
  for (int i = 0; i < kBaselineParameterCount; ++i) {
    const double scale = std::abs(a.parameters[i]) > 0.0 ? std::abs(a.parameters[i]) : 1.0;
    difference.parameters =
        std::max(difference.parameters, std::abs(a.parameters[i] - b.parameters[i]) / scale);
    for (int j = 0; j < kBaselineParameterCount; ++j) {
      const double covariance_scale = std::sqrt(a.covariance(i, i) * a.covariance(j, j));
      difference.covariance =
          std::max(difference.covariance,
                   std::abs(a.covariance(i, j) - b.covariance(i, j)) / covariance_scale);
    }
  }
  return difference;
}

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_BASELINE_PARAMETERS_H_
