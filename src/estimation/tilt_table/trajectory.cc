#include "estimation/tilt_table/trajectory.h"

#include <ceres/jet.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>

#include "models/dead_reckoning.h"
#include "models/sensor_model.h"

namespace accelcal {
namespace {

// The parameters that act in the run (models/effects.h), one Jet variable each.
constexpr const std::array<Parameter, kRunParameterCount>& kRunParameters = RunParameters();
using Jet = ceres::Jet<double, kRunParameterCount>;

// Covariance of (p, v, n_prev) of one axis, n the acceleration noise: AR(1) across
// samples (models/noise_model.h), n' = rho n_prev + w with w of variance q (1 - rho^2), so
// that every n has the variance q (white when rho = 0). One trapezoidal step:
//   p' = p + dt v + dt^2/4 (n_prev + n'),  v' = v + dt/2 (n_prev + n'),  n_prev' = n'.
class AxisNoisePropagator {
 public:
  AxisNoisePropagator(double dt_s, double acceleration_variance, double correlation)
      : innovation_variance_(acceleration_variance * (1.0 - correlation * correlation)) {
    const double carried = 1.0 + correlation;                // n_prev + rho n_prev
    transition_ << 1.0, dt_s, 0.25 * dt_s * dt_s * carried,  //
        0.0, 1.0, 0.5 * dt_s * carried,                      //
        0.0, 0.0, correlation;
    input_ << 0.25 * dt_s * dt_s, 0.5 * dt_s, 1.0;
    covariance_.setZero();
    covariance_(2, 2) = acceleration_variance;  // the first sample's noise
  }

  void Step() {
    covariance_ = transition_ * covariance_ * transition_.transpose() +
                  innovation_variance_ * input_ * input_.transpose();
  }
  double PositionVariance() const { return covariance_(0, 0); }

 private:
  double innovation_variance_;
  Eigen::Matrix3d transition_;
  Eigen::Vector3d input_;
  Eigen::Matrix3d covariance_;
};

Eigen::Vector2d Values(const Jet& x, const Jet& y) { return Eigen::Vector2d(x.a, y.a); }

// d (x, y) / d (the estimate's free parameters); zero for those that do not act in the run.
Eigen::Matrix<double, 2, Eigen::Dynamic> Jacobian(const Jet& x, const Jet& y,
                                                  const std::vector<Parameter>& columns) {
  Eigen::Matrix<double, 2, Eigen::Dynamic> jacobian =
      Eigen::Matrix<double, 2, Eigen::Dynamic>::Zero(2, columns.size());
  for (size_t c = 0; c < columns.size(); ++c) {
    for (size_t r = 0; r < kRunParameters.size(); ++r) {
      if (kRunParameters[r] == columns[c]) {
        jacobian(0, c) = x.v[r];
        jacobian(1, c) = y.v[r];
      }
    }
  }
  return jacobian;
}

}  // namespace

Status DeadReckon(const VehicleRun& run, const RunConditions& conditions, const BaselineFit& fit,
                  const TrajectoryOptions& options, DeadReckoningResult* result) {
  return DeadReckon(run, conditions, FromBaselineFit(fit), options, result);
}

Status DeadReckon(const VehicleRun& run, const RunConditions& conditions,
                  const ParameterEstimate& estimate, const TrajectoryOptions& options,
                  DeadReckoningResult* result) {
  const int count = run.size();
  if (count < 2) {
    return Status::Error("the run has " + std::to_string(count) +
                         " sample(s); at least 2 are needed to integrate");
  }
  const double duration_s = run.timestamp_s.back() - run.timestamp_s.front();
  const double dt_s = run.SampleInterval();
  if (!(dt_s > 0.0)) return Status::Error("the run's time does not increase");
  if (!(conditions.noise_variance_x > 0.0) || !(conditions.noise_variance_y > 0.0)) {
    return Status::Error("the run's stated noise variances must be positive");
  }
  // The slope of each axis's response at zero force (1 + s_k with the built-in effects).
  const RunCorrection<double> at_estimate(estimate.values);
  const double slope_x = at_estimate.response(SensingAxis::kX).c[1];
  const double slope_y = at_estimate.response(SensingAxis::kY).c[1];
  if (!(slope_x > 0.0) || !(slope_y > 0.0)) {
    return Status::Error("a scale factor error of -1 or less cannot be inverted");
  }
  const int stride = std::max(1, options.path_stride);

  // Each parameter acting in the run is a Jet variable, so every corrected acceleration,
  // velocity and position carries its exact derivative with respect to them (the others do
  // not act in the run and stay neutral).
  ModelParameters<Jet> jets;
  for (size_t r = 0; r < kRunParameters.size(); ++r) {
    jets[kRunParameters[r]] = Jet(estimate.Value(kRunParameters[r]), static_cast<int>(r));
  }
  const RunCorrection<Jet> correct(jets);

  AxisKinematics<Jet> x{Jet(conditions.initial_position_x_m),
                        Jet(conditions.initial_velocity_x_mps)};
  AxisKinematics<Jet> y{Jet(conditions.initial_position_y_m),
                        Jet(conditions.initial_velocity_y_mps)};
  AxisKinematics<double> raw_x{conditions.initial_position_x_m, conditions.initial_velocity_x_mps};
  AxisKinematics<double> raw_y{conditions.initial_position_y_m, conditions.initial_velocity_y_mps};

  // The baseline's inverse is (m - b)/(1 + s): the run's noise reaches the corrected
  // acceleration divided by the response's slope (1 + s).
  const double variance_x =
      conditions.noise_variance_x * estimate.values[Parameter::kNoiseVarianceX];
  const double variance_y =
      conditions.noise_variance_y * estimate.values[Parameter::kNoiseVarianceY];
  AxisNoisePropagator noise_x(dt_s, variance_x / (slope_x * slope_x),
                              estimate.noise_correlation[0]);
  AxisNoisePropagator noise_y(dt_s, variance_y / (slope_y * slope_y),
                              estimate.noise_correlation[1]);

  result->path.clear();
  result->path.reserve(count / stride + 2);
  auto record = [&](int j) {
    PathPoint point;
    point.timestamp_s = run.timestamp_s[j];
    point.position = Values(x.position, y.position);
    point.raw_position = Eigen::Vector2d(raw_x.position, raw_y.position);
    const Eigen::Matrix<double, 2, Eigen::Dynamic> jacobian =
        Jacobian(x.position, y.position, estimate.free);
    point.parameter_covariance = jacobian * estimate.covariance * jacobian.transpose();
    point.noise_covariance =
        Eigen::Vector2d(noise_x.PositionVariance(), noise_y.PositionVariance()).asDiagonal();
    result->path.push_back(point);
  };

  Jet previous_x;
  Jet previous_y;
  correct(Jet(run.measured_x[0]), Jet(run.measured_y[0]), &previous_x, &previous_y);
  record(0);
  for (int j = 1; j < count; ++j) {
    Jet acceleration_x;
    Jet acceleration_y;
    correct(Jet(run.measured_x[j]), Jet(run.measured_y[j]), &acceleration_x, &acceleration_y);
    TrapezoidalStep(dt_s, previous_x, acceleration_x, &x);
    TrapezoidalStep(dt_s, previous_y, acceleration_y, &y);
    TrapezoidalStep(dt_s, run.measured_x[j - 1], run.measured_x[j], &raw_x);
    TrapezoidalStep(dt_s, run.measured_y[j - 1], run.measured_y[j], &raw_y);
    noise_x.Step();
    noise_y.Step();
    previous_x = acceleration_x;
    previous_y = acceleration_y;
    if (j % stride == 0 || j == count - 1) record(j);
  }

  result->endpoint = Values(x.position, y.position);
  result->raw_endpoint = Eigen::Vector2d(raw_x.position, raw_y.position);
  result->end_velocity = Values(x.velocity, y.velocity);
  result->jacobian = Jacobian(x.position, y.position, estimate.free);
  result->jacobian_columns = estimate.free;
  result->parameter_part = result->path.back().parameter_covariance;
  result->noise_part = result->path.back().noise_covariance;
  result->covariance = result->parameter_part + result->noise_part;
  result->dt_s = dt_s;
  result->duration_s = duration_s;
  result->sample_count = count;
  return Status::Ok();
}

}  // namespace accelcal
