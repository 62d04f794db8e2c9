#include "estimation/imu_tk_calibration.h"

#include <ceres/ceres.h>

#include <cmath>
#include <limits>

#include "common/format.h"
#include "residuals/imu_tk_residual.h"

namespace accelcal {

ImuTkSweepEntry SolveImuTkProblem(const TriadLog& log, const std::vector<int>& samples,
                                  const ImuTkOptions& options, std::string* brief_report) {
  ImuTkSweepEntry entry;
  entry.parameters = options.initial;
  ceres::Problem problem;
  for (const int i : samples) {
    problem.AddResidualBlock(ImuTkResidual::Create(log.output[i], options.gravity_mps2), nullptr,
                             entry.parameters.data());
  }
  ceres::Solver::Options solver_options;
  solver_options.minimizer_type = ceres::TRUST_REGION;
  solver_options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.function_tolerance = options.function_tolerance;
  solver_options.gradient_tolerance = options.gradient_tolerance;
  solver_options.parameter_tolerance = options.parameter_tolerance;
  solver_options.num_threads = 1;
  solver_options.logging_type = ceres::SILENT;
  solver_options.minimizer_progress_to_stdout = false;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  entry.solved = true;
  entry.cost = summary.final_cost;
  entry.initial_cost = summary.initial_cost;
  entry.iterations = summary.num_successful_steps + summary.num_unsuccessful_steps;
  entry.termination = ceres::TerminationTypeToString(summary.termination_type) + std::string(": ") +
                      summary.message;
  if (brief_report != nullptr) *brief_report = summary.BriefReport();
  return entry;
}

Status CalibrateImuTk(const TriadLog& log, const ImuTkOptions& options, ImuTkResult* result) {
  *result = ImuTkResult();
  // imu_tk's own adjustment of the window: at least 11 samples, odd.
  int window = std::max(options.window_samples, 11);
  if (window % 2 == 0) ++window;
  const int n = static_cast<int>(log.size());
  if (n <= window) {
    return Status::Error(StringPrintf(
        "the log has %d samples, no more than the static detector's window of %d; record a "
        "longer session",
        n, window));
  }
  if (!(options.init_rest_s > 0.0)) {
    return Status::Error("the initial rest must last more than 0 s");
  }
  result->rest_end = InitialRestEnd(log, options.init_rest_s);
  if (result->rest_end < 2) {
    return Status::Error(StringPrintf(
        "the initial rest of %g s holds %d samples; at least 3 are needed for its variance",
        options.init_rest_s, result->rest_end + 1));
  }
  result->rest_variance = IntervalVariance(log, 0, result->rest_end);
  const std::array<double, 3>& v = result->rest_variance;
  result->rest_variance_norm = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);

  const std::vector<double> variance_norm = SlidingVarianceNorm(log, window);
  double best_cost = std::numeric_limits<double>::max();
  std::vector<StaticInterval> best_intervals;
  for (int k = options.min_multiplier; k <= options.max_multiplier; ++k) {
    const double threshold = k * result->rest_variance_norm;
    const std::vector<StaticInterval> intervals =
        DetectStaticIntervals(log, variance_norm, window, threshold);
    std::vector<int> samples;
    int used = 0;
    for (const StaticInterval& interval : intervals) {
      if (interval.sample_count() < options.interval_samples) continue;
      ++used;
      for (int i = interval.start; i < interval.start + options.interval_samples; ++i)
        samples.push_back(i);
    }
    ImuTkSweepEntry entry;
    std::string brief_report;
    if (used >= options.min_intervals) {
      entry = SolveImuTkProblem(log, samples, options, &brief_report);
    }
    entry.multiplier = k;
    entry.threshold = threshold;
    entry.detected_intervals = static_cast<int>(intervals.size());
    entry.used_intervals = used;
    result->sweep.push_back(entry);
    if (entry.solved && entry.cost < best_cost) {
      best_cost = entry.cost;
      result->chosen = static_cast<int>(result->sweep.size()) - 1;
      best_intervals = intervals;
      result->brief_report = brief_report;
    }
  }
  if (result->chosen < 0) {
    int most = 0;
    for (const ImuTkSweepEntry& entry : result->sweep) most = std::max(most, entry.used_intervals);
    return Status::Error(StringPrintf(
        "no threshold k = %d..%d times the initial rest's variance norm finds %d static "
        "intervals of at least %d samples (at most %d); hold the sensor still in more poses, "
        "each for at least %d samples, and start with a rest of at least %g s",
        options.min_multiplier, options.max_multiplier, options.min_intervals,
        options.interval_samples, most, options.interval_samples, options.init_rest_s));
  }
  result->intervals = best_intervals;
  for (const StaticInterval& interval : best_intervals)
    result->interval_used.push_back(interval.sample_count() >= options.interval_samples);
  return Status::Ok();
}

}  // namespace accelcal
