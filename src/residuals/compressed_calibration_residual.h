#ifndef ACCELCAL_RESIDUALS_COMPRESSED_CALIBRATION_RESIDUAL_H_
#define ACCELCAL_RESIDUALS_COMPRESSED_CALIBRATION_RESIDUAL_H_

// All N tilt-test residuals of one axis (CalibrationResidual) as one block of 7 residuals
// with exactly the same sum of squares and the same J^T J, for any parameter values.
//
// Why it is exact: for fixed parameters, the model's prediction of an axis is a linear
// combination of six functions of the sample,
//
//   phi(theta, u) = [1, u, sin theta, cos theta, sin^2 theta, sin theta cos theta],
//
// because the angle offset rotates (sin, cos) linearly, the non-orthogonal projection is
// linear in the force, the nonlinearity squares it, and the drift is linear in u. So
// prediction_i = phi_i^T c(p), and with e_i = m_i - phi_i^T c(p0) the residuals at a
// reference p0 (the baseline fit),
//
//   sum_i (m_i - phi_i^T c(p))^2 = z^T G z,   z = [-(c(p) - c(p0)); 1],
//   G = sum_i [phi_i; e_i] [phi_i; e_i]^T      (7x7, accumulated once),
//
// and z^T G z = |W z|^2 with W = Lambda^1/2 V^T D from the eigendecomposition of the
// column-normalised G (rank-deficient designs are fine: their null directions get zero
// rows). The coefficients c(p) are not written out by hand: they are read off the model
// itself (PredictCalibrationOutput) at six probe samples, c = P^-1 y(p), so the model
// stays in one place. Make() checks at spread parameters and samples that the model does
// lie in span(phi) and fails otherwise (an effect registered later with another shape,
// e.g. a cubic scale term), so the caller can fall back to the per-sample residuals.
//
// Time-correlated noise and outliers (models/noise_model.h) whiten the rows themselves:
// the whitened residual w_i = a_i e_i - b_i e_{i-1} is linear in the same c(p), with the
// row a_i [phi_i; e_i] - b_i [phi_{i-1}; e_{i-1}], so G stays exact.
//
// Cost: one pass over the test to build G (a sin and a cos per sample and 28 products),
// then each evaluation is six predictions and a 7x7 product, independent of N. Robust
// losses act per sample and cannot be compressed; use CalibrationResidual for those.

#include <ceres/autodiff_cost_function.h>

#include <Eigen/Core>
#include <memory>

#include "common/measurements.h"
#include "common/status.h"
#include "models/noise_model.h"
#include "models/sensor_model.h"
#include "residuals/scalar_blocks.h"

namespace accelcal {

class CompressedCalibrationResidual {
 public:
  static constexpr int kBasisSize = 6;
  static constexpr int kResidualCount = kBasisSize + 1;

  // The same parameter blocks as CalibrationResidual of the axis.
  static constexpr int kBlockCount = kCalibrationParameterCount;

  // Accumulates G of both axes (index 0: x, 1: y) over `test` in one pass, about the
  // `reference` parameters (the residuals are best conditioned near them). Fails when the
  // model is not in span(phi).
  static Status Make(const CalibrationTest& test, double gravity_mps2, const AxisNoise noise[2],
                     const ModelParameters<double>& reference,
                     std::unique_ptr<CompressedCalibrationResidual> residuals[2]);

  template <typename T, typename... Rest>
  bool operator()(const T* const first, Rest... rest) const {
    ModelParameters<T> parameters;
    T* residual = GatherParameters(blocks(), &parameters, first, rest...);
    Eigen::Matrix<T, kBasisSize, 1> predicted;
    for (int j = 0; j < kBasisSize; ++j) {
      predicted[j] = PredictCalibrationOutput(probe_theta_rad_[j], probe_drift_[j], axis_,
                                              gravity_mps2_, parameters);
    }
    Eigen::Matrix<T, kResidualCount, 1> z;
    z.template head<kBasisSize>() =
        reference_coefficients_.template cast<T>() - probe_inverse_.template cast<T>() * predicted;
    z[kBasisSize] = T(1.0);
    Eigen::Map<Eigen::Matrix<T, kResidualCount, 1>> out(residual);
    out = weights_.template cast<T>() * z;
    return true;
  }

  // Takes ownership of `residual`.
  static ceres::CostFunction* Create(CompressedCalibrationResidual* residual) {
    return new ScalarBlocksCostFunction<CompressedCalibrationResidual, kResidualCount, kBlockCount>(
        residual);
  }

  int sample_count() const { return sample_count_; }
  // The parameter blocks, in the order Create's cost function takes them.
  const std::array<Parameter, kBlockCount>& blocks() const { return CalibrationParameters(axis_); }

 private:
  CompressedCalibrationResidual() = default;

  SensingAxis axis_ = SensingAxis::kX;
  double gravity_mps2_ = 0.0;
  int sample_count_ = 0;
  double probe_theta_rad_[kBasisSize] = {};
  double probe_drift_[kBasisSize] = {};
  Eigen::Matrix<double, kBasisSize, kBasisSize> probe_inverse_;    // P^-1: c = P^-1 y
  Eigen::Matrix<double, kBasisSize, 1> reference_coefficients_;    // c(p0)
  Eigen::Matrix<double, kResidualCount, kResidualCount> weights_;  // W (the rows are whitened)
};

}  // namespace accelcal

#endif  // ACCELCAL_RESIDUALS_COMPRESSED_CALIBRATION_RESIDUAL_H_
