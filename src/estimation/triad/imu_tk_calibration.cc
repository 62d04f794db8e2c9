#include "estimation/triad/imu_tk_calibration.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <utility>

#include "common/format.h"
#include "common/statistics.h"
#include "residuals/imu_tk_residual.h"

namespace accelcal {

int ImuTkWindow(const ImuTkOptions& options) {
  const int window = std::max(options.window_samples, 11);
  return window % 2 == 0 ? window + 1 : window;
}

std::vector<int> ImuTkSamples(const std::vector<StaticInterval>& intervals, int interval_samples,
                              int* used) {
  std::vector<int> samples;
  *used = 0;
  for (const StaticInterval& interval : intervals) {
    if (interval.sample_count() < interval_samples) continue;
    ++*used;
    for (int i = interval.start; i < interval.start + interval_samples; ++i) samples.push_back(i);
  }
  return samples;
}

ceres::Solver::Options ImuTkSolverOptions(const ImuTkOptions& options) {
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
  return solver_options;
}

ImuTkSweepEntry SolveImuTkProblem(const TriadLog& log, const std::vector<int>& samples,
                                  const ImuTkOptions& options, std::string* brief_report) {
  ImuTkSweepEntry entry;
  entry.parameters = options.initial;
  std::vector<std::array<double, 3>> raw;
  raw.reserve(samples.size());
  for (const int i : samples) raw.push_back(log.output[i]);
  ceres::Problem problem;
  problem.AddResidualBlock(new ImuTkBatchResidual(std::move(raw), options.gravity_mps2), nullptr,
                           entry.parameters.data());
  ceres::Solver::Summary summary;
  ceres::Solve(ImuTkSolverOptions(options), &problem, &summary);
  entry.solved = true;
  entry.cost = summary.final_cost;
  entry.initial_cost = summary.initial_cost;
  entry.iterations = summary.num_successful_steps + summary.num_unsuccessful_steps;
  entry.termination = ceres::TerminationTypeToString(summary.termination_type) + std::string(": ") +
                      summary.message;
  if (brief_report != nullptr) *brief_report = summary.BriefReport();
  return entry;
}

namespace {

// The thresholds scale with the rest's variance norm, so a rest that holds motion (a session
// whose rest is shorter than init_rest_s) inflates every threshold and the sweep silently
// merges poses. White noise gives a rest norm equal to the median norm of the windows inside
// it, to a few percent (1.02 on imu_tk's Xsens log); above kMaxRestRatio (imu_tk's smallest
// multiplier) even k = 2 would let motion through.
constexpr double kMaxRestRatio = 2.0;

// The rule on the rest of samples 0..rest_end: its variance norm at most kMaxRestRatio times the
// median norm of the windows inside it. `median` gets that median (0 when no window fits).
bool RestPasses(const TriadLog& log, const std::vector<double>& variance_norm, int window,
                int rest_end, double* median, double* rest_norm) {
  const int half = window / 2;
  *median = 0.0;
  *rest_norm = 0.0;
  std::vector<double> inside;
  for (int i = half; i + half <= rest_end; ++i) inside.push_back(variance_norm[i]);
  if (inside.empty()) return false;
  *median = UpperMedian(inside);
  const std::array<double, 3> v = IntervalVariance(log, 0, rest_end);
  *rest_norm = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return *median > 0.0 && *rest_norm <= kMaxRestRatio * *median;
}

// The shortest --init_rest_s whose rest holds one window: rounded up to 0.01 s, then checked
// by parsing the printed value back, as the flag would be.
std::string ShortestRest(const TriadLog& log, int window) {
  const double t0 = log.timestamp_s.front();
  double value = std::ceil((log.timestamp_s[window - 1] - t0) * 100.0) / 100.0;
  for (int step = 0; step < 1000; ++step, value += 0.01) {
    const std::string printed = StringPrintf("%.2f", value);
    if (InitialRestEnd(log, std::strtod(printed.c_str(), nullptr)) >= window - 1) return printed;
  }
  return StringPrintf("%.2f", log.timestamp_s.back() - t0);
}

// The longest --init_rest_s that the rest check accepts, as printed ("" when none does): the
// boundary found by bisection over the check itself between a rest of two windows and
// `failing_end`, then written with 0.01 s digits rounded down and parsed back, and lowered by
// 0.01 s until the rest that the printed value selects passes the same check. Two windows, not
// one: a rest of one window passes whatever it holds (its only window is itself), so the check
// could not tell a log that moves from its first sample from one that starts still.
std::string LongestPassingRest(const TriadLog& log, const std::vector<double>& variance_norm,
                               int window, int failing_end, int last_still) {
  double median = 0.0;
  double norm = 0.0;
  const int shortest = 2 * window - 1;
  int low = shortest - 1;
  if (low >= failing_end || !RestPasses(log, variance_norm, window, low, &median, &norm)) return "";
  int high = failing_end;
  while (high - low > 1) {
    const int middle = low + (high - low) / 2;
    if (RestPasses(log, variance_norm, window, middle, &median, &norm)) {
      low = middle;
    } else {
      high = middle;
    }
  }
  // No further than the last sample before the first loud window, when the check allows that
  // far: the check tolerates the first tenths of a second of motion, the advice does not.
  const double t0 = log.timestamp_s.front();
  const int end = std::min(low, std::max(last_still, 2 * window - 2));
  double value = std::floor((log.timestamp_s[end] - t0) * 100.0) / 100.0;
  for (; value > 0.0; value -= 0.01) {
    const std::string printed = StringPrintf("%.2f", value);
    const double parsed = std::strtod(printed.c_str(), nullptr);
    if (!(parsed > 0.0)) break;
    const int selected = InitialRestEnd(log, parsed);
    if (selected < shortest - 1) break;
    if (RestPasses(log, variance_norm, window, selected, &median, &norm)) return printed;
  }
  return "";
}

Status CheckInitialRest(const TriadLog& log, const std::vector<double>& variance_norm, int window,
                        const ImuTkOptions& options, const ImuTkResult& result) {
  const int half = window / 2;
  double median = 0.0;
  double rest_norm = 0.0;
  if (RestPasses(log, variance_norm, window, result.rest_end, &median, &rest_norm))
    return Status::Ok();
  if (result.rest_end + 1 < window) {
    return Status::Error(StringPrintf(
        "the initial rest of %g s holds %d samples, fewer than the static detector's window of "
        "%d; give --init_rest_s=%s or more (the log must start with the sensor still)",
        options.init_rest_s, result.rest_end + 1, window, ShortestRest(log, window).c_str()));
  }
  if (!(median > 0.0)) {
    return Status::Error(StringPrintf(
        "the output is constant over the initial rest of %g s (zero variance): no noise to "
        "scale the thresholds from; is the log a real sensor's?",
        options.init_rest_s));
  }
  int moving = half;
  while (moving + 1 < static_cast<int>(variance_norm.size()) &&
         variance_norm[moving] <= kMaxRestRatio * median)
    ++moving;
  if (variance_norm[moving] <= kMaxRestRatio * median) {
    // No window is above the limit: every window is as quiet as the rest's, yet the rest as a
    // whole varies far more than its windows. The sensor turns slowly through it, and through
    // the log.
    return Status::Error(StringPrintf(
        "the initial rest of %g s drifts: its variance norm is %.3g times the median of its "
        "windows (at most %g when still), while no window of the log is louder than those of the "
        "rest, so the sensor turns slowly through it and never rests; start the log with the "
        "sensor still, and hold it still in each pose",
        options.init_rest_s, rest_norm / median, kMaxRestRatio));
  }
  // The first window above the limit ends at the first moving sample. The advice is not that
  // time (the motion's onset raises the rest's variance before a window crosses the limit, and
  // the limit moves with the rest's own median) but the longest rest the same check accepts.
  const int first_moving = std::min(moving + half, static_cast<int>(log.size()) - 1);
  const std::string longest =
      LongestPassingRest(log, variance_norm, window, result.rest_end, first_moving - 1);
  const int shortest_rest = 2 * window - 1;
  const std::string advice =
      longest.empty()
          ? StringPrintf(
                "no initial rest of this log passes the check (not even its first %d samples, two "
                "windows), so imu_tk's thresholds cannot be scaled from it; start the log with "
                "the sensor still, or use mode ml's noise-floor detector, which needs no rest",
                shortest_rest)
          : "give --init_rest_s=" + longest +
                ", the longest initial rest before the motion that this check accepts";
  return Status::Error(StringPrintf(
      "the initial rest of %g s is not at rest: its variance norm is %.3g times the median of "
      "its windows (at most %g when still), and the sensor moves from t = %.6g s; %s",
      options.init_rest_s, rest_norm / median, kMaxRestRatio, log.timestamp_s[first_moving],
      advice.c_str()));
}

}  // namespace

Status CalibrateImuTk(const TriadLog& log, const ImuTkOptions& options, ImuTkResult* result) {
  *result = ImuTkResult();
  const int window = ImuTkWindow(options);
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
  ACCELCAL_RETURN_IF_ERROR(CheckInitialRest(log, variance_norm, window, options, *result));
  double best_cost = std::numeric_limits<double>::max();
  std::vector<StaticInterval> best_intervals;
  for (int k = options.min_multiplier; k <= options.max_multiplier; ++k) {
    const double threshold = k * result->rest_variance_norm;
    const std::vector<StaticInterval> intervals =
        DetectStaticIntervals(log, variance_norm, window, threshold);
    int used = 0;
    const std::vector<int> samples = ImuTkSamples(intervals, options.interval_samples, &used);
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
  // imu_tk's cost depends on |T K (u - b)| alone, so it cannot tell a gain's sign, and from a
  // start far from the output at zero g it can end at a negative gain with a fine cost.
  const ImuTkSweepEntry& best = result->best();
  for (int axis = 0; axis < 3; ++axis) {
    if (best.parameters[kTriadGainX + axis] <= 0.0) {
      return Status::Error(StringPrintf(
          "imu_tk's fit at k = %d ends at a negative gain_%c = %.6g with offset %.6g: its cost "
          "cannot tell a gain's sign, and the start (offset %.6g) was too far from the output at "
          "zero specific force; start from an offset nearer it (--initial_offset=auto)",
          best.multiplier, "xyz"[axis], best.parameters[kTriadGainX + axis],
          best.parameters[kTriadOffsetX + axis], options.initial[kTriadOffsetX + axis]));
    }
  }
  result->intervals = best_intervals;
  for (const StaticInterval& interval : best_intervals)
    result->interval_used.push_back(interval.sample_count() >= options.interval_samples);
  return Status::Ok();
}

}  // namespace accelcal
