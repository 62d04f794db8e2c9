#include "estimation/tilt_table/calibration_correction.h"

#include <ceres/jet.h>

namespace accelcal {

CorrectedSample CorrectBaseline(const Eigen::Vector4d& parameters,
                                const Eigen::Matrix4d& covariance, double measured_x,
                                double measured_y) {
  const double measured[2] = {measured_x, measured_y};
  CorrectedSample sample;
  Eigen::Matrix<double, 2, 4> jacobian = Eigen::Matrix<double, 2, 4>::Zero();
  for (int axis = 0; axis < 2; ++axis) {
    const int bias = BaselineIndex(BiasOf(axis));
    const int scale = BaselineIndex(ScaleOf(axis));
    const double gain = 1.0 + parameters[scale];
    const double acceleration = (measured[axis] - parameters[bias]) / gain;
    sample.acceleration[axis] = acceleration;
    jacobian(axis, bias) = -1.0 / gain;
    jacobian(axis, scale) = -acceleration / gain;
  }
  sample.covariance = jacobian * covariance * jacobian.transpose();
  return sample;
}

CorrectedTriadSample CorrectTriad(const TriadParameters& parameters,
                                  const Eigen::MatrixXd& covariance,
                                  const std::array<double, 3>& output) {
  using Jet = ceres::Jet<double, kTriadParameterCount>;
  std::array<Jet, kTriadParameterCount> variables;
  for (int p = 0; p < kTriadParameterCount; ++p) variables[p] = Jet(parameters[p], p);
  std::array<Jet, 3> force;
  TriadSpecificForce(variables.data(), output.data(), force.data());
  CorrectedTriadSample sample;
  Eigen::Matrix<double, 3, kTriadParameterCount> jacobian;
  for (int k = 0; k < 3; ++k) {
    sample.acceleration[k] = force[k].a;
    jacobian.row(k) = force[k].v.transpose();
  }
  sample.covariance = jacobian * covariance * jacobian.transpose();
  return sample;
}

}  // namespace accelcal
