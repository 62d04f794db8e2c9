#ifndef ACCELCAL_ESTIMATION_GYROSCOPE_IMU_TK_GYROSCOPE_CALIBRATION_H_
#define ACCELCAL_ESTIMATION_GYROSCOPE_IMU_TK_GYROSCOPE_CALIBRATION_H_

// imu_tk's gyroscope calibration (Tedaldi, Pretto, Menegatti, ICRA 2014, section IV-C; imu_tk's
// MultiPosCalibration::calibrateAccGyro after calibrateAcc), reproduced rule for rule so that
// its printed output can be checked to its digits. It runs after the accelerometer's
// calibration (estimation/triad/imu_tk_calibration.h) and uses its result:
//
//  1. The static intervals are those the accelerometer's calibration detected at its chosen k,
//     of which only those of at least interval_samples samples (ImuTkResult::interval_used).
//     The gravity direction of each is the mean over the WHOLE interval (not its first
//     interval_samples samples: imu_tk calls its extractor with only_means = true here, whatever
//     acc_use_means says) of the calibrated specific force T K (u - b) (models/triad.h),
//     normalised.
//  2. The gyroscope's offset b_g is the mean of its output over the initial rest (the samples
//     up to ImuTkResult::rest_end; imu_tk's dataMean over initialInterval), and is not estimated.
//  3. One residual per pair of consecutive used intervals (a "turn", residuals/
//     imu_tk_gyroscope_residual.h): the rate is integrated from the LAST sample of the earlier
//     interval to the sample BEFORE the first of the later one (imu_tk's search: the first
//     sample at or after the earlier interval's end time, to one before the first at or after
//     the later one's start time), with the time steps of the time stamps (imu_tk's
//     gyro_dt_ = -1) or a fixed step.
//  4. Ceres minimises 1/2 sum |r|^2 over the 9 angles and gains from the initial guess, with
//     imu_tk's options (Levenberg-Marquardt, dense QR, Ceres' default stopping rules, written
//     out so that they do not move with the Ceres version; ImuTkSolverOptions). The final cost
//     is what imu_tk prints as "Gyroscopes calibration: residual".
//
// Nothing is printed here.

#include <ceres/solver.h>

#include <array>
#include <vector>

#include "common/status.h"
#include "common/triad_log.h"
#include "estimation/triad/imu_tk_calibration.h"
#include "models/gyroscope.h"

namespace accelcal {

struct ImuTkGyroscopeOptions {
  // imu_tk's default guess: angles 0, gains 1 (rad/s)/count. Its Xsens example sets the gains
  // to 1/6258.
  GyroscopeParameters initial = GyroscopeParametersWithGain(1.0, 1.0, 1.0);
  // imu_tk's gyro_dt_: the integration step (s); 0 or less takes each step from the time stamps.
  double data_period_s = -1.0;
  // Ceres' defaults, which imu_tk leaves as they are (it sets only the dense QR solver).
  int max_iterations = 50;
  double function_tolerance = 1e-6;
  double gradient_tolerance = 1e-10;
  double parameter_tolerance = 1e-8;
};

// One turn: the motion between two consecutive used static intervals.
struct ImuTkGyroscopeTurn {
  int interval_before = 0;  // indices into ImuTkResult::intervals
  int interval_after = 0;
  int first_sample = 0;  // the samples integrated, inclusive (indices into the log)
  int last_sample = 0;
  std::array<double, 3> gravity_before{};  // unit vectors, accelerometer frame
  std::array<double, 3> gravity_after{};
  double turn_angle_rad = 0.0;       // angle between the two gravity directions
  double residual_angle_rad = 0.0;   // angle between R^T gravity_before and gravity_after, at
                                     // the solution: how far the calibrated rates miss the turn
  std::array<double, 3> residual{};  // r at the solution
};

struct ImuTkGyroscopeResult {
  GyroscopeParameters parameters{};  // the 9 estimated (models/gyroscope.h)
  GyroscopeOffset offset{};          // counts: the mean of the initial rest
  int rest_end = 0;                  // last sample of the initial rest
  std::vector<ImuTkGyroscopeTurn> turns;
  double cost = 0.0;  // Ceres' final cost, 1/2 sum |r|^2: imu_tk's printed "residual"
  double initial_cost = 0.0;
  ceres::Solver::Summary summary;

  // What imu_tk prints: the "Misalignment Matrix" (row-major), the diagonal of the "Scale
  // Matrix" (gains) and the "inverse scale factors" (counts per rad/s).
  std::array<double, 9> misalignment_matrix() const;
  std::array<double, 3> inverse_gains() const;
};

// The fewest used intervals accepted: each turn gives two independent equations (r compares unit
// vectors), so 9 parameters need at least 5 turns.
constexpr int kImuTkGyroscopeMinIntervals = 6;

// Fails, saying why, when the log has no gyroscope samples (or not one per time stamp), the
// accelerometer's result is not a successful calibration of this log, it used fewer than
// kImuTkGyroscopeMinIntervals intervals, or Ceres fails.
Status CalibrateImuTkGyroscope(const TriadLog& log, const ImuTkResult& accelerometer,
                               const ImuTkGyroscopeOptions& options, ImuTkGyroscopeResult* result);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_GYROSCOPE_IMU_TK_GYROSCOPE_CALIBRATION_H_
