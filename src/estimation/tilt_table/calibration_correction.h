#ifndef ACCELCAL_ESTIMATION_TILT_TABLE_CALIBRATION_CORRECTION_H_
#define ACCELCAL_ESTIMATION_TILT_TABLE_CALIBRATION_CORRECTION_H_

// Applying a baseline calibration to new outputs: the inverse of the measurement model
// (spec/error-model.md, models/sensor_model.h) per axis k,
//
//   a_k = (m_k - bias_k) / (1 + scale_k),
//
// and the covariance of (a_x, a_y) that the calibration's own uncertainty gives, to first
// order: J C J^T with C the parameters' covariance (kBaselineParameters' order) and
//
//   d a_k / d bias_k = -1 / (1 + scale_k),   d a_k / d scale_k = -a_k / (1 + scale_k).
//
// The sensor's white noise is not in it: it is the uncertainty of the correction, shared by
// every sample (a bias error moves them all alike), not the sample-to-sample scatter.

#include <Eigen/Core>
#include <array>

#include "estimation/tilt_table/baseline_parameters.h"
#include "models/gyroscope.h"
#include "models/gyroscope_correction.h"
#include "models/triad.h"
#include "models/triad_correction.h"

namespace accelcal {

struct CorrectedSample {
  Eigen::Vector2d acceleration = Eigen::Vector2d::Zero();  // m/s^2, (x, y)
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();    // (m/s^2)^2
};

// `parameters` and `covariance` in kBaselineParameters' order; 1 + scale_k must be positive
// (a calibration file's reader and the estimators guarantee it for any real sensor).
CorrectedSample CorrectBaseline(const Eigen::Vector4d& parameters,
                                const Eigen::Matrix4d& covariance, double measured_x,
                                double measured_y);

// A triad's correction a = T K (u - b) (models/triad.h) of one output u (in the calibration's
// output unit), and the covariance of a that the parameters' covariance (9x9, block order)
// gives, to first order, J C J^T with J = d a / d parameters (automatic differentiation of
// TriadSpecificForce itself, so the correction and its Jacobian cannot disagree). As for the
// baseline, it is shared by every sample and excludes the sensor's noise.
struct CorrectedTriadSample {
  Eigen::Vector3d acceleration = Eigen::Vector3d::Zero();  // m/s^2
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();    // (m/s^2)^2
};
CorrectedTriadSample CorrectTriad(const TriadParameters& parameters,
                                  const Eigen::MatrixXd& covariance,
                                  const std::array<double, 3>& output);

// The same with the model discovery settled on (models/triad_correction.h): its effect terms
// applied, J over the 9 and the block. Without effect terms, exactly the 9-parameter
// correction above. Returns false (and leaves *sample) when the output has no force near the
// 9-parameter correction's (TriadCorrectedForce).
bool CorrectTriad(const TriadCalibrationModel& model, const std::array<double, 3>& output,
                  CorrectedTriadSample* sample);

// A gyroscope's correction w = T K (u - b) (models/gyroscope.h) of one output u (in the
// calibration's output unit), and the covariance of w that the 12x12 covariance of the block
// and the offset (kGyroscopeCalibrationParameterCount, that order) gives, to first order,
// J C J^T with J = d w / d (block, offset) by automatic differentiation of
// GyroscopeAngularRate. Shared by every sample, as the triad's, and without the gyroscope's
// noise.
struct CorrectedGyroscopeSample {
  Eigen::Vector3d angular_rate = Eigen::Vector3d::Zero();  // rad/s
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();    // (rad/s)^2
};
CorrectedGyroscopeSample CorrectGyroscope(const GyroscopeParameters& parameters,
                                          const GyroscopeOffset& offset,
                                          const Eigen::MatrixXd& covariance,
                                          const std::array<double, 3>& output);

// The same with the model discovery settled on (models/gyroscope_correction.h): w =
// GyroscopeCorrectedRate, its effect terms applied, `specific_force` (m/s^2, the calibrated
// accelerometer's at the same sample; read only when the model has a g-sensitivity), J over
// the 12 and the block. Without effect terms, exactly the correction above.
CorrectedGyroscopeSample CorrectGyroscope(const GyroscopeCalibrationModel& model,
                                          const std::array<double, 3>& output,
                                          const Eigen::Vector3d& specific_force);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TILT_TABLE_CALIBRATION_CORRECTION_H_
