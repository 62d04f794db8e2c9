#include "estimation/calibration_correction.h"

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

}  // namespace accelcal
