#ifndef ACCELCAL_ESTIMATION_TRIAD_IMU_TK_CALIBRATION_H_
#define ACCELCAL_ESTIMATION_TRIAD_IMU_TK_CALIBRATION_H_

// imu_tk's accelerometer calibration (Tedaldi, Pretto, Menegatti, ICRA 2014; imu_tk's
// MultiPosCalibration::calibrateAcc), reproduced rule for rule so that its printed output
// can be checked to its digits:
//
//  1. The initial rest is the samples from the first to the one nearest t_0 + init_rest_s;
//     its variance norm is v_rest = |(var_x, var_y, var_z)| (estimation/triad/static_intervals.h).
//  2. For k = 2..10: static intervals where the windowed variance norm is below k v_rest;
//     of those with at least interval_samples samples, the first interval_samples samples.
//     With fewer than min_intervals such intervals, k is skipped.
//  3. Each k is solved from the same initial guess: minimise
//       1/2 sum_i (g - |T K (u_i - b)|)^2          (residuals/imu_tk_residual.h)
//     over the 9 parameters of models/triad.h, unweighted, by Ceres with imu_tk's options
//     (Levenberg-Marquardt, dense QR, Ceres' default stopping rules, written out below so
//     that they do not move with the Ceres version).
//  4. The k with the lowest final cost is kept (the first one on a tie).
//
// Step 4 compares costs of different sample sets (more intervals, more terms); it is imu_tk's
// rule, reproduced, not endorsed (issue 20). Nothing is printed here.

#include <ceres/solver.h>

#include <string>
#include <vector>

#include "common/status.h"
#include "common/triad_log.h"
#include "estimation/triad/static_intervals.h"
#include "models/triad.h"

namespace accelcal {

struct ImuTkOptions {
  double gravity_mps2 = 9.81;  // imu_tk's default; its Xsens example sets 9.81744
  double init_rest_s = 30.0;   // imu_tk's default; its Xsens example sets 50
  // imu_tk's default initial guess: angles 0, gains 1, bias 0 (its example sets 32768).
  TriadParameters initial = TriadParametersWithOffset(0.0, 0.0, 0.0);
  int window_samples = 101;    // odd; imu_tk raises it to at least 11 and to the next odd
  int interval_samples = 100;  // samples used from each interval, and its minimum length
  int min_intervals = 12;
  int min_multiplier = 2;
  int max_multiplier = 10;
  // Ceres' defaults, which imu_tk leaves as they are (it sets only the dense QR solver).
  int max_iterations = 50;
  double function_tolerance = 1e-6;
  double gradient_tolerance = 1e-10;
  double parameter_tolerance = 1e-8;
};

struct ImuTkSweepEntry {
  int multiplier = 0;      // k
  double threshold = 0.0;  // k v_rest, in the log's unit squared
  int detected_intervals = 0;
  int used_intervals = 0;  // those of at least interval_samples samples
  bool solved = false;     // false: too few intervals, not attempted
  double cost = 0.0;       // Ceres' final cost, 1/2 sum r^2, (m/s^2)^2
  double initial_cost = 0.0;
  int iterations = 0;
  std::string termination;  // Ceres' termination type and message
  TriadParameters parameters{};
};

struct ImuTkResult {
  int rest_end = 0;  // last sample of the initial rest
  std::array<double, 3> rest_variance{};
  double rest_variance_norm = 0.0;
  std::vector<ImuTkSweepEntry> sweep;
  int chosen = -1;  // index into sweep
  // At the chosen k: every detected interval, and whether its first samples were used.
  std::vector<StaticInterval> intervals;
  std::vector<bool> interval_used;
  std::string brief_report;  // Ceres' BriefReport at the chosen k

  const ImuTkSweepEntry& best() const { return sweep[chosen]; }
};

// Fails, saying why, when the log is shorter than the window, the initial rest is not inside
// it or holds motion (its variance norm above twice the median of its windows' norms: the
// thresholds would let motion through; the message says when the sensor starts moving), no k
// yields min_intervals intervals, or the chosen fit ends at a negative gain (imu_tk's cost
// is blind to a gain's sign; a start far from the zero-g output can end there).
Status CalibrateImuTk(const TriadLog& log, const ImuTkOptions& options, ImuTkResult* result);

// The detector's window: options.window_samples raised to at least 11 and to the next odd
// number, as imu_tk does.
int ImuTkWindow(const ImuTkOptions& options);

// Step 2's samples: the first `interval_samples` of each interval at least that long (indices
// into the log, in order); `used` counts those intervals.
std::vector<int> ImuTkSamples(const std::vector<StaticInterval>& intervals, int interval_samples,
                              int* used);

// Step 3's Ceres options: Levenberg-Marquardt, dense QR, the options' stopping rules, one
// thread, silent.
ceres::Solver::Options ImuTkSolverOptions(const ImuTkOptions& options);

// One solve of step 3 on given samples (the indices into `log`), from `options.initial`.
ImuTkSweepEntry SolveImuTkProblem(const TriadLog& log, const std::vector<int>& samples,
                                  const ImuTkOptions& options, std::string* brief_report);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TRIAD_IMU_TK_CALIBRATION_H_
