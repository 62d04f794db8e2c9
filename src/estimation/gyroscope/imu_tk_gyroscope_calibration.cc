#include "estimation/gyroscope/imu_tk_gyroscope_calibration.h"

#include <ceres/ceres.h>

#include <cmath>
#include <utility>

#include "common/format.h"
#include "common/vector3.h"
#include "models/triad.h"
#include "residuals/imu_tk_gyroscope_residual.h"

namespace accelcal {

std::array<double, 9> ImuTkGyroscopeResult::misalignment_matrix() const {
  std::array<double, 9> matrix;
  GyroscopeMisalignmentMatrix(parameters.data(), matrix.data());
  return matrix;
}

std::array<double, 3> ImuTkGyroscopeResult::inverse_gains() const {
  return {1.0 / parameters[kGyroscopeGainX], 1.0 / parameters[kGyroscopeGainY],
          1.0 / parameters[kGyroscopeGainZ]};
}

namespace {

// Step 1: the normalised mean of the calibrated specific force over samples [start, end], each
// sample calibrated first, then summed in order and divided (imu_tk's calibrated samples, then
// its dataMean).
std::array<double, 3> GravityDirection(const TriadLog& log, const TriadParameters& accelerometer,
                                       int start, int end) {
  std::array<double, 3> mean{};
  for (int i = start; i <= end; ++i) {
    double force[3];
    TriadSpecificForce(accelerometer.data(), log.output[i].data(), force);
    for (int k = 0; k < 3; ++k) mean[k] += force[k];
  }
  const double count = end - start + 1;
  for (int k = 0; k < 3; ++k) mean[k] /= count;
  const double norm = std::sqrt(mean[0] * mean[0] + mean[1] * mean[1] + mean[2] * mean[2]);
  for (int k = 0; k < 3; ++k) mean[k] /= norm;
  return mean;
}

Status CheckInputs(const TriadLog& log, const ImuTkResult& accelerometer, int* used) {
  if (!log.has_gyroscope()) {
    return Status::Error(
        "the log has no gyroscope samples: give the gyroscope's file (--gyro_log, imu_tk's pair) "
        "or a log with gyroscope columns");
  }
  if (log.gyroscope.size() != log.size()) {
    return Status::Error(StringPrintf(
        "the log has %zu gyroscope samples for %zu time stamps; imu_tk's calibration needs one "
        "gyroscope sample per accelerometer sample",
        log.gyroscope.size(), log.size()));
  }
  if (accelerometer.chosen < 0 ||
      accelerometer.chosen >= static_cast<int>(accelerometer.sweep.size()) ||
      accelerometer.interval_used.size() != accelerometer.intervals.size()) {
    return Status::Error(
        "the accelerometer's imu_tk calibration did not succeed; the gyroscope's calibration "
        "needs its static intervals and parameters");
  }
  const int n = static_cast<int>(log.size());
  if (accelerometer.rest_end < 0 || accelerometer.rest_end >= n) {
    return Status::Error(
        "the accelerometer's result does not belong to this log (its initial "
        "rest ends past the last sample)");
  }
  *used = 0;
  for (size_t i = 0; i < accelerometer.intervals.size(); ++i) {
    const StaticInterval& interval = accelerometer.intervals[i];
    if (interval.start < 0 || interval.end >= n || interval.end < interval.start) {
      return Status::Error(StringPrintf(
          "the accelerometer's static interval %zu (samples %d..%d) is not inside this log of %d "
          "samples; calibrate the accelerometer on the same log",
          i + 1, interval.start, interval.end, n));
    }
    if (accelerometer.interval_used[i]) ++*used;
  }
  if (*used < kImuTkGyroscopeMinIntervals) {
    return Status::Error(StringPrintf(
        "the accelerometer's calibration used %d static intervals, fewer than the %d the "
        "gyroscope's needs: each turn between consecutive poses gives 2 equations, and its 9 "
        "angles and gains need %d turns; record more poses, turning about different axes",
        *used, kImuTkGyroscopeMinIntervals, kImuTkGyroscopeMinIntervals - 1));
  }
  return Status::Ok();
}

}  // namespace

Status CalibrateImuTkGyroscope(const TriadLog& log, const ImuTkResult& accelerometer,
                               const ImuTkGyroscopeOptions& options, ImuTkGyroscopeResult* result) {
  *result = ImuTkGyroscopeResult();
  int used = 0;
  ACCELCAL_RETURN_IF_ERROR(CheckInputs(log, accelerometer, &used));

  // Step 2: the offset, the mean of the initial rest (summed in order, then divided).
  result->rest_end = accelerometer.rest_end;
  for (int i = 0; i <= result->rest_end; ++i) {
    for (int k = 0; k < 3; ++k) result->offset[k] += log.gyroscope[i][k];
  }
  for (int k = 0; k < 3; ++k) result->offset[k] /= result->rest_end + 1;

  // Step 1: the used intervals and their gravity directions.
  const TriadParameters& acceleration = accelerometer.best().parameters;
  std::vector<int> used_intervals;
  std::vector<std::array<double, 3>> directions;
  for (size_t i = 0; i < accelerometer.intervals.size(); ++i) {
    if (!accelerometer.interval_used[i]) continue;
    const StaticInterval& interval = accelerometer.intervals[i];
    used_intervals.push_back(static_cast<int>(i));
    directions.push_back(GravityDirection(log, acceleration, interval.start, interval.end));
  }

  // Step 3: one residual per turn. On one strictly increasing clock (TriadLog) imu_tk's time
  // search lands on the earlier interval's last sample and the sample before the later one's
  // first.
  result->parameters = options.initial;
  ceres::Problem problem;
  for (size_t p = 0; p + 1 < used_intervals.size(); ++p) {
    ImuTkGyroscopeTurn turn;
    turn.interval_before = used_intervals[p];
    turn.interval_after = used_intervals[p + 1];
    turn.first_sample = accelerometer.intervals[turn.interval_before].end;
    turn.last_sample = accelerometer.intervals[turn.interval_after].start - 1;
    turn.gravity_before = directions[p];
    turn.gravity_after = directions[p + 1];
    turn.turn_angle_rad = AngleBetween(turn.gravity_before, turn.gravity_after);
    std::vector<std::array<double, 3>> raw(log.gyroscope.begin() + turn.first_sample,
                                           log.gyroscope.begin() + turn.last_sample + 1);
    std::vector<double> step_s;
    for (int i = turn.first_sample; i < turn.last_sample; ++i) {
      step_s.push_back(options.data_period_s > 0.0 ? options.data_period_s
                                                   : log.timestamp_s[i + 1] - log.timestamp_s[i]);
    }
    problem.AddResidualBlock(
        ImuTkGyroscopeResidual::Create(turn.gravity_before, turn.gravity_after, std::move(raw),
                                       std::move(step_s), result->offset),
        nullptr, result->parameters.data());
    result->turns.push_back(turn);
  }

  // Step 4.
  ImuTkOptions solver_settings;
  solver_settings.max_iterations = options.max_iterations;
  solver_settings.function_tolerance = options.function_tolerance;
  solver_settings.gradient_tolerance = options.gradient_tolerance;
  solver_settings.parameter_tolerance = options.parameter_tolerance;
  ceres::Solve(ImuTkSolverOptions(solver_settings), &problem, &result->summary);
  if (result->summary.termination_type == ceres::FAILURE ||
      !std::isfinite(result->summary.final_cost)) {
    return Status::Error("the gyroscope's imu_tk fit failed: " + result->summary.message);
  }
  result->cost = result->summary.final_cost;
  result->initial_cost = result->summary.initial_cost;

  // The residual of each turn at the solution.
  std::vector<ceres::ResidualBlockId> blocks;
  problem.GetResidualBlocks(&blocks);
  for (size_t p = 0; p < blocks.size(); ++p) {
    ImuTkGyroscopeTurn& turn = result->turns[p];
    double cost = 0.0;
    problem.EvaluateResidualBlock(blocks[p], false, &cost, turn.residual.data(), nullptr);
    const std::array<double, 3> predicted = {turn.residual[0] + turn.gravity_after[0],
                                             turn.residual[1] + turn.gravity_after[1],
                                             turn.residual[2] + turn.gravity_after[2]};
    turn.residual_angle_rad = AngleBetween(predicted, turn.gravity_after);
  }
  return Status::Ok();
}

}  // namespace accelcal
