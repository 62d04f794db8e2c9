#ifndef ACCELCAL_ESTIMATION_TILT_TABLE_BASELINE_PARAMETERS_H_
#define ACCELCAL_ESTIMATION_TILT_TABLE_BASELINE_PARAMETERS_H_

// The baseline model's parameters and the fit both baseline solvers return.

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>

#include "models/effects.h"

namespace accelcal {

// The baseline's parameters, in the order of BaselineFit's vector and covariance. They are
// the catalogue's first four, so a parameter's place in the fit is its place in the
// catalogue; names and units come from Info(parameter).
constexpr int kBaselineParameterCount = 4;
inline constexpr std::array<Parameter, kBaselineParameterCount> kBaselineParameters = {
    Parameter::kBiasX, Parameter::kScaleX, Parameter::kBiasY, Parameter::kScaleY};

constexpr bool BaselineParametersLeadTheCatalogue() {
  for (int i = 0; i < kBaselineParameterCount; ++i) {
    if (kBaselineParameters[i].index() != i) return false;
  }
  return true;
}
static_assert(BaselineParametersLeadTheCatalogue(),
              "BaselineFit indexes its vector by catalogue index: bias_x, scale_x, bias_y and "
              "scale_y must be the catalogue's parameters 0..3");

// Where a baseline parameter sits in BaselineFit::parameters and covariance.
constexpr int BaselineIndex(Parameter parameter) { return parameter.index(); }

// The baseline parameters of one axis (0: x, 1: y).
constexpr Parameter BiasOf(int axis) { return axis == 0 ? Parameter::kBiasX : Parameter::kBiasY; }
constexpr Parameter ScaleOf(int axis) {
  return axis == 0 ? Parameter::kScaleX : Parameter::kScaleY;
}

// Goodness of fit of one axis against its stated noise variance.
struct AxisChiSquare {
  double chi2 = 0.0;  // sum of squared whitened residuals
  int dof = 0;        // samples minus the two fitted parameters
  // Two-sided p-value of chi2 under chi-square(dof): small when the residuals are
  // either larger or smaller than the stated noise explains.
  double p_value = 1.0;
};

struct BaselineFit {
  Eigen::Vector4d parameters = Eigen::Vector4d::Zero();  // kBaselineParameters' order
  Eigen::Matrix4d covariance = Eigen::Matrix4d::Zero();  // same order
  AxisChiSquare chi2_x;
  AxisChiSquare chi2_y;
  int sample_count = 0;

  double Value(Parameter parameter) const { return parameters[BaselineIndex(parameter)]; }
  double StandardDeviation(Parameter parameter) const {
    const int i = BaselineIndex(parameter);
    return std::sqrt(covariance(i, i));
  }
  double Covariance(Parameter a, Parameter b) const {
    return covariance(BaselineIndex(a), BaselineIndex(b));
  }
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

#endif  // ACCELCAL_ESTIMATION_TILT_TABLE_BASELINE_PARAMETERS_H_
