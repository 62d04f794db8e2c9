#include "residuals/compressed_calibration_residual.h"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "common/format.h"
#include "common/sincos.h"
#include "models/sensor_model.h"

namespace accelcal {
namespace {

using Basis = Eigen::Matrix<double, CompressedCalibrationResidual::kBasisSize, 1>;

Basis BasisAt(double sin_theta, double cos_theta, double drift_coordinate) {
  Basis phi;
  phi << 1.0, drift_coordinate, sin_theta, cos_theta, sin_theta * sin_theta, sin_theta * cos_theta;
  return phi;
}

// Parameters far from `reference` in every tilt-test parameter at once (an angle offset of
// 0.1 rad, say): where a model outside the basis cannot hide.
ModelParameters<double> Spread(const ModelParameters<double>& reference, SensingAxis axis) {
  ModelParameters<double> spread = reference;
  double sign = 1.0;
  for (const Parameter parameter : CalibrationParameters(axis)) {
    const double size = Info(parameter).example_size;
    spread[parameter] += sign * (size > 0.0 ? 25.0 * size : 0.05);
    sign = -sign;
  }
  return spread;
}

}  // namespace

Status CompressedCalibrationResidual::Make(const CalibrationTest& test, double gravity_mps2,
                                           const AxisNoise noise[2],
                                           const ModelParameters<double>& reference,
                                           std::unique_ptr<CompressedCalibrationResidual> out[2]) {
  constexpr int kGramEntries = kResidualCount * (kResidualCount + 1) / 2;
  // Six probe samples whose basis rows are independent: four quadrants and pi/4 at u = 0
  // separate 1, sin, cos, sin^2 and sin cos; one sample at u = 1/2 separates the drift.
  const double probe_theta[kBasisSize] = {0.0, M_PI / 2, M_PI, 3 * M_PI / 2, M_PI / 4, 0.0};
  const double probe_drift[kBasisSize] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.5};
  Eigen::Matrix<double, kBasisSize, kBasisSize> probes;
  for (int j = 0; j < kBasisSize; ++j) {
    probes.row(j) =
        BasisAt(std::sin(probe_theta[j]), std::cos(probe_theta[j]), probe_drift[j]).transpose();
  }
  const Eigen::Matrix<double, kBasisSize, kBasisSize> probe_inverse = probes.inverse();

  std::unique_ptr<CompressedCalibrationResidual> residuals[2];
  const SensingAxis axes[2] = {SensingAxis::kX, SensingAxis::kY};
  for (int a = 0; a < 2; ++a) {
    const SensingAxis axis = axes[a];
    auto coefficients = [&](const ModelParameters<double>& p) {
      Basis predicted;
      for (int j = 0; j < kBasisSize; ++j) {
        predicted[j] =
            PredictCalibrationOutput(probe_theta[j], probe_drift[j], axis, gravity_mps2, p);
      }
      return Basis(probe_inverse * predicted);
    };
    // The model must lie in span(phi): check it away from the probes, at the reference and
    // at parameters well beyond any estimate.
    for (const ModelParameters<double>& p : {reference, Spread(reference, axis)}) {
      const Basis c = coefficients(p);
      for (const double theta : {0.3, 1.9, 2.71, 4.4, 5.8, -7.1}) {
        for (const double u : {-0.5, -0.13, 0.41}) {
          const double direct = PredictCalibrationOutput(theta, u, axis, gravity_mps2, p);
          const double through_basis = BasisAt(std::sin(theta), std::cos(theta), u).dot(c);
          if (!(std::abs(direct - through_basis) <= 1e-9 * (1.0 + std::abs(direct)))) {
            return Status::Error(StringPrintf(
                "the calibration model is not a combination of the compressed basis (%.3g at "
                "theta %.3g, u %.3g); use the per-sample residuals",
                direct - through_basis, theta, u));
          }
        }
      }
    }
    residuals[a].reset(new CompressedCalibrationResidual);
    CompressedCalibrationResidual& r = *residuals[a];
    r.axis_ = axis;
    r.gravity_mps2_ = gravity_mps2;
    r.sample_count_ = test.size();
    std::copy(probe_theta, probe_theta + kBasisSize, r.probe_theta_rad_);
    std::copy(probe_drift, probe_drift + kBasisSize, r.probe_drift_);
    r.probe_inverse_ = probe_inverse;
    r.reference_coefficients_ = coefficients(reference);
  }

  // G of both axes about their references, in one pass: sin and cos by blocks (SinCos), the
  // lower triangles accumulated in plain arrays (fixed sizes the compiler unrolls).
  const Basis& cx = residuals[0]->reference_coefficients_;
  const Basis& cy = residuals[1]->reference_coefficients_;
  double gram_x[kGramEntries] = {};
  double gram_y[kGramEntries] = {};
  const int n = test.size();
  constexpr int kBlock = 512;
  double sines[kBlock];
  double cosines[kBlock];
  const std::vector<AxisNoise::Whitening> whitening[2] = {noise[0].WhiteningOf(n),
                                                          noise[1].WhiteningOf(n)};
  double previous_x[kResidualCount] = {};
  double previous_y[kResidualCount] = {};
  for (int i = 0; i < n; ++i) {
    if (i % kBlock == 0) {
      SinCos(test.theta_rad.data() + i, std::min(kBlock, n - i), sines, cosines);
    }
    const double sin_theta = sines[i % kBlock];
    const double cos_theta = cosines[i % kBlock];
    const double u = DriftCoordinate(i, n);
    double row_x[kResidualCount] = {
        1.0, u, sin_theta, cos_theta, sin_theta * sin_theta, sin_theta * cos_theta, 0.0};
    double row_y[kResidualCount];
    double predicted_x = 0.0;
    double predicted_y = 0.0;
    for (int k = 0; k < kBasisSize; ++k) {
      row_y[k] = row_x[k];
      predicted_x += row_x[k] * cx[k];
      predicted_y += row_x[k] * cy[k];
    }
    row_x[kBasisSize] = test.measured_x[i] - predicted_x;
    row_y[kBasisSize] = test.measured_y[i] - predicted_y;
    // Whitened rows: a_i row_i - b_i row_{i-1}.
    const AxisNoise::Whitening& wx = whitening[0][i];
    const AxisNoise::Whitening& wy = whitening[1][i];
    double white_x[kResidualCount];
    double white_y[kResidualCount];
    for (int k = 0; k < kResidualCount; ++k) {
      white_x[k] = wx.current * row_x[k] - wx.previous * previous_x[k];
      white_y[k] = wy.current * row_y[k] - wy.previous * previous_y[k];
      previous_x[k] = row_x[k];
      previous_y[k] = row_y[k];
    }
    int entry = 0;
    for (int row = 0; row < kResidualCount; ++row) {
      for (int col = 0; col <= row; ++col, ++entry) {
        gram_x[entry] += white_x[row] * white_x[col];
        gram_y[entry] += white_y[row] * white_y[col];
      }
    }
  }

  for (int a = 0; a < 2; ++a) {
    const double* packed = a == 0 ? gram_x : gram_y;
    Eigen::Matrix<double, kResidualCount, kResidualCount> gram;
    int entry = 0;
    for (int row = 0; row < kResidualCount; ++row) {
      for (int col = 0; col <= row; ++col, ++entry) {
        gram(row, col) = gram(col, row) = packed[entry];
      }
    }
    // z^T G z = |Lambda^1/2 V^T D z|^2 with D the columns' norms; rounding can leave tiny
    // negative eigenvalues in rank-deficient directions, which are zero.
    Eigen::Matrix<double, kResidualCount, 1> norms = gram.diagonal().cwiseSqrt();
    for (int k = 0; k < kResidualCount; ++k) {
      if (!(norms[k] > 0.0)) norms[k] = 1.0;
    }
    const Eigen::Matrix<double, kResidualCount, kResidualCount> normalized =
        norms.cwiseInverse().asDiagonal() * gram * norms.cwiseInverse().asDiagonal();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, kResidualCount, kResidualCount>>
        eigen(normalized);
    if (eigen.info() != Eigen::Success) {
      return Status::Error("the eigendecomposition of the tilt test's Gram matrix failed");
    }
    const Eigen::Matrix<double, kResidualCount, 1> root =
        eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt();
    residuals[a]->weights_ =
        root.asDiagonal() * eigen.eigenvectors().transpose() * norms.asDiagonal();
  }
  out[0] = std::move(residuals[0]);
  out[1] = std::move(residuals[1]);
  return Status::Ok();
}

}  // namespace accelcal
