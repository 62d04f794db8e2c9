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

namespace {

// The value of `model` (3 outputs of N parameters, a generic lambda over ceres::Jet) at `values`
// and its covariance J C J^T, J the Jacobian by automatic differentiation of `model` itself.
template <int N, typename Model>
void PropagateCovariance(const std::array<double, N>& values, const Eigen::MatrixXd& covariance,
                         const Model& model, Eigen::Vector3d* value,
                         Eigen::Matrix3d* value_covariance) {
  using Jet = ceres::Jet<double, N>;
  std::array<Jet, N> variables;
  for (int p = 0; p < N; ++p) variables[p] = Jet(values[p], p);
  std::array<Jet, 3> outputs;
  model(variables.data(), outputs.data());
  Eigen::Matrix<double, 3, N> jacobian;
  for (int k = 0; k < 3; ++k) {
    (*value)[k] = outputs[k].a;
    jacobian.row(k) = outputs[k].v.transpose();
  }
  *value_covariance = jacobian * covariance * jacobian.transpose();
}

}  // namespace

CorrectedTriadSample CorrectTriad(const TriadParameters& parameters,
                                  const Eigen::MatrixXd& covariance,
                                  const std::array<double, 3>& output) {
  CorrectedTriadSample sample;
  PropagateCovariance<kTriadParameterCount>(
      parameters, covariance,
      [&output](const auto* variables, auto* force) {
        TriadSpecificForce(variables, output.data(), force);
      },
      &sample.acceleration, &sample.covariance);
  return sample;
}

CorrectedGyroscopeSample CorrectGyroscope(const GyroscopeParameters& parameters,
                                          const GyroscopeOffset& offset,
                                          const Eigen::MatrixXd& covariance,
                                          const std::array<double, 3>& output) {
  std::array<double, kGyroscopeCalibrationParameterCount> values;
  for (int p = 0; p < kGyroscopeParameterCount; ++p) values[p] = parameters[p];
  for (int k = 0; k < 3; ++k) values[kGyroscopeCalibrationOffsetX + k] = offset[k];
  CorrectedGyroscopeSample sample;
  PropagateCovariance<kGyroscopeCalibrationParameterCount>(
      values, covariance,
      [&output](const auto* variables, auto* rate) {
        GyroscopeAngularRate(variables, variables + kGyroscopeCalibrationOffsetX, output.data(),
                             rate);
      },
      &sample.angular_rate, &sample.covariance);
  return sample;
}

bool CorrectTriad(const TriadCalibrationModel& model, const std::array<double, 3>& output,
                  CorrectedTriadSample* sample) {
  if (!model.has_effects()) {
    *sample = CorrectTriad(
        model.parameters,
        model.covariance.topLeftCorner(kTriadParameterCount, kTriadParameterCount), output);
    return true;
  }
  std::array<double, kTriadCorrectionUnknowns> values;
  for (int p = 0; p < kTriadParameterCount; ++p) values[p] = model.parameters[p];
  for (int c = 0; c < kTriadEffectCoefficientCount; ++c)
    values[kTriadParameterCount + c] = model.effects[c];
  bool settled = true;
  CorrectedTriadSample corrected;
  PropagateCovariance<kTriadCorrectionUnknowns>(
      values, model.covariance,
      [&](const auto* variables, auto* force) {
        settled = TriadCorrectedForce(variables, variables + kTriadParameterCount, output.data(),
                                      model.gravity_mps2, force);
      },
      &corrected.acceleration, &corrected.covariance);
  if (!settled) return false;
  *sample = corrected;
  return true;
}

CorrectedGyroscopeSample CorrectGyroscope(const GyroscopeCalibrationModel& model,
                                          const std::array<double, 3>& output,
                                          const Eigen::Vector3d& specific_force) {
  constexpr int n = kGyroscopeCalibrationParameterCount;
  if (!model.has_effects()) {
    return CorrectGyroscope(model.parameters, model.offset, model.covariance.topLeftCorner(n, n),
                            output);
  }
  std::array<double, kGyroscopeCorrectionUnknowns> values;
  for (int p = 0; p < kGyroscopeParameterCount; ++p) values[p] = model.parameters[p];
  for (int k = 0; k < 3; ++k) values[kGyroscopeCalibrationOffsetX + k] = model.offset[k];
  for (int c = 0; c < kGyroscopeEffectCoefficientCount; ++c) values[n + c] = model.effects[c];
  const double force[3] = {specific_force.x(), specific_force.y(), specific_force.z()};
  CorrectedGyroscopeSample sample;
  PropagateCovariance<kGyroscopeCorrectionUnknowns>(
      values, model.covariance,
      [&](const auto* variables, auto* rate) {
        GyroscopeCorrectedRate(variables, variables + kGyroscopeCalibrationOffsetX, variables + n,
                               output.data(), force, rate);
      },
      &sample.angular_rate, &sample.covariance);
  return sample;
}

}  // namespace accelcal
