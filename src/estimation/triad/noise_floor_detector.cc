#include "estimation/triad/noise_floor_detector.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "common/format.h"
#include "common/statistics.h"
#include "estimation/statistics/chi_square.h"
#include "estimation/triad/window_variance_stream.h"

namespace accelcal {
namespace {

using noise_floor::kFloorQuantile;
using noise_floor::kMaxWhiteFalseAlarm;
using noise_floor::kMinFloorShape;
using noise_floor::kMinStillFraction;
using noise_floor::kPoseFloorSpread;
using noise_floor::kShapeLowQuantile;
// When neither rule finds the poses, the second rule's refusal is added only while the message
// stays this short (calibrate_imu adds the file and imu_tk's fallback within a 600-byte line).
constexpr size_t kMaxCombinedRefusalBytes = 380;

const char kAxisNames[] = "xyz";

std::vector<double> Column(const std::vector<std::array<double, 3>>& variances, int axis,
                           const std::vector<bool>* keep) {
  std::vector<double> column;
  column.reserve(variances.size());
  for (size_t j = 0; j < variances.size(); ++j) {
    if (keep == nullptr || (*keep)[j]) column.push_back(variances[j][axis]);
  }
  return column;
}

std::vector<bool> StillWindows(const std::vector<std::array<double, 3>>& variances,
                               const std::array<double, 3>& threshold) {
  std::vector<bool> still(variances.size());
  for (size_t j = 0; j < variances.size(); ++j) {
    still[j] = variances[j][0] < threshold[0] && variances[j][1] < threshold[1] &&
               variances[j][2] < threshold[2];
  }
  return still;
}

// "steps of one count" for an output in whole numbers, else "steps of 0.0096".
std::string StepText(double step) {
  return step == 1.0 ? std::string("steps of one count") : StringPrintf("steps of %.4g", step);
}

// Called once StuckAxis has passed every axis: the axis changes through the motion, so its
// constant still windows are noise below the output's step (a quantised output), not a fault.
Status ZeroFloor(int axis, int window, double step) {
  return Status::Error(StringPrintf(
      "axis %c is constant over much of the log's %d-sample windows while it changes through the "
      "motion: its noise is below the output's resolution, %s (quantised), so one noise floor "
      "for the log cannot be set from it",
      kAxisNames[axis], window, StepText(step).c_str()));
}

// " (2.8 to 51.4 s, median 7.8 s)", or nothing for no intervals.
std::string DescribeDurations(const std::vector<StaticInterval>& intervals) {
  if (intervals.empty()) return "";
  std::vector<double> durations;
  for (const StaticInterval& interval : intervals) durations.push_back(interval.duration_s);
  const double median = RankQuantile(&durations, 0.5);
  const auto [shortest, longest] = std::minmax_element(durations.begin(), durations.end());
  return StringPrintf(" (%.1f to %.1f s, median %.1f s)", *shortest, *longest, median);
}

}  // namespace

Status CheckNoiseFloorOptions(const NoiseFloorOptions& options) {
  const int window = options.window_samples;
  if (window < 3 || window % 2 == 0) {
    return Status::Error(StringPrintf(
        "the static detector's window of %d samples must be odd and at least 3", window));
  }
  const double dof = window - 1;
  const double factor = options.threshold_factor;
  const double minimum = ChiSquareQuantile(1.0 - kMaxWhiteFalseAlarm, dof) / dof;
  if (!(factor >= minimum) || !std::isfinite(factor)) {
    return Status::Error(StringPrintf(
        "a threshold factor of %g times the noise floor is within white noise's own spread over "
        "%d samples (crossed by still windows with probability %.2g); use at least %.2f",
        factor, window, ChiSquareSurvival(factor * dof, dof), std::ceil(minimum * 100.0) / 100.0));
  }
  if (!(options.min_interval_s >= 0.0) || !std::isfinite(options.min_interval_s)) {
    return Status::Error(StringPrintf("the minimum interval duration of %g s must be 0 s or more",
                                      options.min_interval_s));
  }
  if (options.min_intervals < 0) {
    return Status::Error(
        StringPrintf("the minimum interval count %d must be 0 or more", options.min_intervals));
  }
  return Status::Ok();
}

namespace {

// The run of still centres [first, last] (window indices) as an interval of samples.
StaticInterval IntervalOfRun(const TriadLog& log, int half, int first, int last) {
  StaticInterval interval;
  interval.start = first + half;
  interval.end = last + half;
  DescribeInterval(log, &interval);
  return interval;
}

}  // namespace

std::vector<std::array<double, 3>> WindowVariances(const TriadLog& log, int window) {
  if (static_cast<int>(log.size()) < window) return {};
  std::vector<std::array<double, 3>> variances;
  variances.reserve(log.size() - window + 1);
  WindowVarianceStream stream(window);
  for (const std::array<double, 3>& output : log.output)
    if (stream.Add(output)) variances.push_back(stream.variance());
  return variances;
}

namespace {

// The runs of still windows as intervals: moving when the run's output varies, about its own
// mean, more than its threshold (thresholds[j], per window) allows on some axis; else used or
// short by duration.
void SortRuns(const TriadLog& log, const NoiseFloorOptions& options, int half,
              const std::vector<bool>& still, const std::vector<std::array<double, 3>>& thresholds,
              NoiseFloorDetection* detection) {
  for (int j = 0; j < static_cast<int>(still.size());) {
    if (!still[j]) {
      ++j;
      continue;
    }
    int last = j;
    while (last + 1 < static_cast<int>(still.size()) && still[last + 1]) ++last;
    FileInterval(IntervalOfRun(log, half, j, last), thresholds[j], options, detection);
    j = last + 1;
  }
}

Status CountIntervals(const TriadLog& log, const NoiseFloorOptions& options,
                      NoiseFloorDetection* detection);

// c(q) of the header: chi2_{w-1}'s quantile q over w - 1.
double WhiteQuantile(double q, int window) {
  return ChiSquareQuantile(q, window - 1) / (window - 1);
}

// The shape check on one axis: quantile_0.1 / median of `values` over white noise's, stored in
// *shape; a refusal naming `whose` windows below kMinFloorShape. `median_variance` is the still
// windows' median variance on the axis and `step` its output's: when the step is as large as
// their standard deviation, a few level changes make a window's variance, and the refusal says
// the output's resolution rather than motion alone.
Status CheckShape(std::vector<double> values, int axis, double white_shape, const char* whose,
                  double step, double median_variance, double* shape) {
  const double median = RankQuantile(&values, 0.5);
  const double low = RankQuantile(&values, kShapeLowQuantile);
  *shape = median > 0.0 ? low / median / white_shape : 0.0;
  if (*shape >= kMinFloorShape) return Status::Ok();
  const std::string finding = StringPrintf(
      "the quietest windows of %s do not look like sensor noise (on axis %c their %.0f%% quantile "
      "of variance is %.2f of their median, white noise gives %.2f)",
      whose, kAxisNames[axis], 100 * kShapeLowQuantile, *shape * white_shape, white_shape);
  if (step > 0.0 && median_variance <= step * step) {
    return Status::Error(StringPrintf(
        "%s: the output's resolution, %s, dominates its noise (s = %.2g): a few level changes "
        "make each variance; hold the sensor still, or record at a finer resolution",
        finding.c_str(), StepText(step).c_str(), std::sqrt(median_variance)));
  }
  return Status::Error(finding + ": the sensor never rests; hold it still in each pose");
}

// The median variance on `axis` of the windows `still` marks.
double MedianVariance(const std::vector<std::array<double, 3>>& variances, int axis,
                      const std::vector<bool>& still) {
  std::vector<double> column = Column(variances, axis, &still);
  return column.empty() ? 0.0 : RankQuantile(&column, 0.5);
}

// The rule of the header's first part: one noise floor for the whole log.
Status GlobalFloorRule(const TriadLog& log, const NoiseFloorOptions& options,
                       const std::vector<std::array<double, 3>>& variances,
                       const std::array<double, 3>& step, NoiseFloorDetection* detection) {
  const int window = options.window_samples;
  const int half = window / 2;
  const double dof = window - 1;
  const double factor = options.threshold_factor;
  auto white_quantile = [dof](double q) { return ChiSquareQuantile(q, dof) / dof; };

  std::array<double, 3> provisional_threshold{};
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<double> column = Column(variances, axis, nullptr);
    provisional_threshold[axis] =
        factor * RankQuantile(&column, kFloorQuantile) / white_quantile(kFloorQuantile);
    if (!(provisional_threshold[axis] > 0.0)) return ZeroFloor(axis, window, step[axis]);
  }
  std::vector<bool> still = StillWindows(variances, provisional_threshold);
  const bool any_still = std::find(still.begin(), still.end(), true) != still.end();
  if (any_still) {
    for (int axis = 0; axis < 3; ++axis) {
      std::vector<double> column = Column(variances, axis, &still);
      detection->floor_variance[axis] = RankQuantile(&column, 0.5) / white_quantile(0.5);
      if (!(detection->floor_variance[axis] > 0.0)) return ZeroFloor(axis, window, step[axis]);
      detection->floor_stddev[axis] = std::sqrt(detection->floor_variance[axis]);
      detection->threshold_variance[axis] = factor * detection->floor_variance[axis];
    }
    still = StillWindows(variances, detection->threshold_variance);
  }
  const long still_count = std::count(still.begin(), still.end(), true);
  detection->still_fraction = static_cast<double>(still_count) / still.size();

  if (still_count > 0) {
    const double white_shape = white_quantile(kShapeLowQuantile) / white_quantile(0.5);
    std::array<Status, 3> shape;
    for (int axis = 0; axis < 3; ++axis) {
      shape[axis] =
          CheckShape(Column(variances, axis, &still), axis, white_shape, "the log", step[axis],
                     MedianVariance(variances, axis, still), &detection->floor_shape[axis]);
    }
    for (const Status& status : shape) ACCELCAL_RETURN_IF_ERROR(status);
  }
  if (detection->still_fraction < kMinStillFraction) {
    return Status::Error(StringPrintf(
        "only %.1f%% of the log's %d-sample windows are still (below %g times the noise floor on "
        "every axis); the noise floor can only be told from motion when at least %.0f%% are: "
        "hold the sensor still in each pose",
        100 * detection->still_fraction, window, factor, 100 * kMinStillFraction));
  }

  const std::vector<std::array<double, 3>> thresholds(still.size(), detection->threshold_variance);
  SortRuns(log, options, half, still, thresholds, detection);
  return CountIntervals(log, options, detection);
}

Status CountIntervals(const TriadLog& log, const NoiseFloorOptions& options,
                      NoiseFloorDetection* detection) {
  const int window = options.window_samples;
  const int found = static_cast<int>(detection->intervals.size());
  if (found >= options.min_intervals) return Status::Ok();
  const double span_s = log.timestamp_s.back() - log.timestamp_s.front();
  const double window_s = span_s > 0.0 ? span_s * (window - 1) / (log.size() - 1) : 0.0;
  const double hold_s = options.min_interval_s + window_s;
  const int total = found + static_cast<int>(detection->short_intervals.size());
  if (found == 0 && detection->short_intervals.empty() && !detection->moving_intervals.empty()) {
    return Status::Error(StringPrintf(
        "the sensor never rests: the log's %zu quiet stretches%s drift far beyond their "
        "windows' noise (the output turns slowly through them), so there is no static pose to "
        "calibrate from; hold the sensor still in each pose",
        detection->moving_intervals.size(),
        DescribeDurations(detection->moving_intervals).c_str()));
  }
  detection->too_few_intervals = true;
  const std::string advice =
      total >= options.min_intervals
          ? StringPrintf(
                "hold each pose still for at least %.1f s (%g s plus the %d-sample window)", hold_s,
                options.min_interval_s, window)
          : StringPrintf("record at least %d more poses, each held still for at least %.1f s",
                         options.min_intervals - found, hold_s);
  return Status::Error(StringPrintf(
      "found %d static intervals of at least %g s%s and %zu shorter ones%s%s; the calibration "
      "needs at least %d poses: %s",
      found, options.min_interval_s, DescribeDurations(detection->intervals).c_str(),
      detection->short_intervals.size(), DescribeDurations(detection->short_intervals).c_str(),
      detection->moving_intervals.empty()
          ? ""
          : StringPrintf(" (and %zu quiet stretches through which the sensor turned slowly)",
                         detection->moving_intervals.size())
                .c_str(),
      options.min_intervals, advice.c_str()));
}

}  // namespace

void UpdateOutputSteps(const std::array<double, 3>& previous, const std::array<double, 3>& output,
                       std::array<double, 3>* step) {
  for (int k = 0; k < 3; ++k) {
    const double change = std::abs(output[k] - previous[k]);
    if (change > 0.0 && ((*step)[k] == 0.0 || change < (*step)[k])) (*step)[k] = change;
  }
}

std::array<double, 3> OutputSteps(const TriadLog& log) {
  std::array<double, 3> step{};
  for (size_t i = 1; i < log.size(); ++i)
    UpdateOutputSteps(log.output[i - 1], log.output[i], &step);
  return step;
}

void FileInterval(const StaticInterval& interval, const std::array<double, 3>& threshold,
                  const NoiseFloorOptions& options, NoiseFloorDetection* detection) {
  bool moving = false;
  for (int axis = 0; axis < 3; ++axis) {
    const double stddev = interval.noise_stddev[axis];
    moving = moving || stddev * stddev > threshold[axis];
  }
  if (moving) {
    detection->moving_intervals.push_back(interval);
  } else if (interval.duration_s >= options.min_interval_s) {
    detection->intervals.push_back(interval);
  } else {
    detection->short_intervals.push_back(interval);
  }
}

std::string MorePosesReason(size_t global_poses, size_t pose_floor_poses, double factor) {
  return StringPrintf(
      "one noise floor for the log found %zu poses, a floor per pose %zu: the others are louder "
      "than %g times the quietest",
      global_poses, pose_floor_poses, factor);
}

namespace {

// A stuck or saturated axis is constant through the motion too: over the windows where another
// axis moves (above `loud` there), it has zero variance in more than half. A quantised axis is
// constant only while still (a turn that leaves an axis's share of gravity unchanged is a turn
// about that axis, and a session turns about every axis).
int StuckAxis(const std::vector<std::array<double, 3>>& variances,
              const std::array<double, 3>& step, const std::array<double, 3>& loud) {
  for (int axis = 0; axis < 3; ++axis) {
    if (step[axis] == 0.0) return axis;
    long moving = 0;
    long constant = 0;
    for (const std::array<double, 3>& v : variances) {
      bool other_moves = false;
      for (int other = 0; other < 3; ++other)
        other_moves = other_moves || (other != axis && v[other] > loud[other]);
      if (!other_moves) continue;
      ++moving;
      if (v[axis] == 0.0) ++constant;
    }
    if (moving > 0 && 2 * constant > moving) return axis;
  }
  return -1;
}

// The rule of the header's second part: a floor per pose, each at most kPoseFloorSpread times
// the quietest windows' floor, none below the output's step.
Status PoseFloorRule(const TriadLog& log, const NoiseFloorOptions& options,
                     const std::vector<std::array<double, 3>>& variances,
                     const std::array<double, 3>& step, NoiseFloorDetection* detection) {
  const int half = options.window_samples / 2;
  const double factor = options.threshold_factor;
  auto white_quantile = [&options](double q) { return WhiteQuantile(q, options.window_samples); };
  std::array<double, 3> resolution{};
  std::array<double, 3> loose{};
  for (int axis = 0; axis < 3; ++axis) {
    resolution[axis] = step[axis] * step[axis] / 12.0;
    std::vector<double> column = Column(variances, axis, nullptr);
    detection->floor_variance[axis] = std::max(
        RankQuantile(&column, kFloorQuantile) / white_quantile(kFloorQuantile), resolution[axis]);
    detection->floor_stddev[axis] = std::sqrt(detection->floor_variance[axis]);
    loose[axis] = factor * kPoseFloorSpread * detection->floor_variance[axis];
    detection->threshold_variance[axis] = loose[axis];
  }
  const std::vector<bool> candidate = StillWindows(variances, loose);
  const int count = static_cast<int>(variances.size());
  std::vector<bool> still(count, false);
  std::vector<std::array<double, 3>> thresholds(count, loose);
  // Each candidate run: its own floor from the median of its windows (twice: the second on the
  // windows the first kept), and only the windows below factor times it are still.
  for (int j = 0; j < count;) {
    if (!candidate[j]) {
      ++j;
      continue;
    }
    int last = j;
    while (last + 1 < count && candidate[last + 1]) ++last;
    std::vector<bool> keep(count, false);
    for (int i = j; i <= last; ++i) keep[i] = true;
    std::array<double, 3> threshold = loose;
    for (int pass = 0; pass < 2; ++pass) {
      for (int axis = 0; axis < 3; ++axis) {
        std::vector<double> run;
        for (int i = j; i <= last; ++i)
          if (keep[i]) run.push_back(variances[i][axis]);
        if (run.empty()) break;
        const double floor =
            std::max(RankQuantile(&run, 0.5) / white_quantile(0.5), resolution[axis]);
        threshold[axis] = std::min(loose[axis], factor * floor);
      }
      for (int i = j; i <= last; ++i)
        keep[i] = keep[i] && variances[i][0] < threshold[0] && variances[i][1] < threshold[1] &&
                  variances[i][2] < threshold[2];
    }
    for (int i = j; i <= last; ++i) {
      still[i] = keep[i];
      thresholds[i] = threshold;
    }
    j = last + 1;
  }
  const long still_count = std::count(still.begin(), still.end(), true);
  detection->still_fraction = static_cast<double>(still_count) / count;
  // The shape check on each window's variance over its own pose's floor, at least the step's.
  if (still_count > 0) {
    const double white_shape = white_quantile(kShapeLowQuantile) / white_quantile(0.5);
    for (int axis = 0; axis < 3; ++axis) {
      std::vector<double> ratio;
      for (int i = 0; i < count; ++i) {
        if (still[i])
          ratio.push_back(std::max(variances[i][axis], resolution[axis]) / thresholds[i][axis]);
      }
      ACCELCAL_RETURN_IF_ERROR(CheckShape(std::move(ratio), axis, white_shape, "each stretch",
                                          step[axis], MedianVariance(variances, axis, still),
                                          &detection->floor_shape[axis]));
    }
  }
  if (detection->still_fraction < kMinStillFraction) {
    return Status::Error(StringPrintf(
        "only %.1f%% of the windows are still below their own stretch's floor (%g times it, at "
        "most %g times the quietest windows' s = %.3g, %.3g, %.3g): hold the sensor still in each "
        "pose",
        100 * detection->still_fraction, factor, kPoseFloorSpread, detection->floor_stddev[0],
        detection->floor_stddev[1], detection->floor_stddev[2]));
  }
  SortRuns(log, options, half, still, thresholds, detection);
  return CountIntervals(log, options, detection);
}

// One detection with the window of options (already resolved, not 0).
Status DetectWithWindow(const TriadLog& log, const NoiseFloorOptions& options,
                        NoiseFloorDetection* detection) {
  *detection = NoiseFloorDetection();
  ACCELCAL_RETURN_IF_ERROR(CheckNoiseFloorOptions(options));
  const int window = options.window_samples;
  const double dof = window - 1;
  const double factor = options.threshold_factor;
  detection->window_samples = window;
  detection->white_false_alarm = ChiSquareSurvival(factor * dof, dof);
  if (static_cast<int>(log.size()) < window) {
    return Status::Error(StringPrintf(
        "the log has %zu samples, fewer than the static detector's window of %d: record a longer "
        "session or use a shorter window",
        log.size(), window));
  }
  const std::vector<std::array<double, 3>> variances = WindowVariances(log, window);
  const std::array<double, 3> step = OutputSteps(log);
  NoiseFloorDetection pose_floors = *detection;
  pose_floors.rule = kPoseFloorsRule;
  const Status per_pose = PoseFloorRule(log, options, variances, step, &pose_floors);
  const int stuck = StuckAxis(variances, step, pose_floors.threshold_variance);
  if (stuck >= 0) {
    return Status::Error(StringPrintf(
        "axis %c is constant through the motion too (zero variance over most %d-sample windows "
        "in which another axis moves, or over the whole log): stuck or saturated, not noise "
        "below the output's resolution; check that axis of the sensor",
        kAxisNames[stuck], window));
  }
  detection->rule = kGlobalFloorRule;
  const Status global = GlobalFloorRule(log, options, variances, step, detection);
  // The single floor unless it refuses or drops poses that their own floors find (the louder
  // poses of a session whose noise differs from pose to pose).
  if (global.ok() && !(per_pose.ok() && pose_floors.intervals.size() > detection->intervals.size()))
    return global;
  if (per_pose.ok()) {
    pose_floors.rule_reason =
        global.ok() ? MorePosesReason(detection->intervals.size(), pose_floors.intervals.size(),
                                      options.threshold_factor)
                    : global.message();
    *detection = std::move(pose_floors);
    return per_pose;
  }
  // Neither rule: the refusal of the one that found more intervals (one noise floor on a tie),
  // with what it saw kept for the caller to show; the other's refusal only when it differs and
  // the line stays short, so that the advice at the end of the first is never cut.
  const bool per_pose_better = pose_floors.intervals.size() > detection->intervals.size();
  const Status& better = per_pose_better ? per_pose : global;
  const Status& other = per_pose_better ? global : per_pose;
  const char* better_rule = per_pose_better ? "a floor per pose" : "one noise floor for the log";
  const char* other_rule = per_pose_better ? "one noise floor for the log" : "a floor per pose";
  std::string message;
  if (global.message() == per_pose.message()) {
    message = "neither one noise floor for the log nor a floor per pose finds the poses: " +
              global.message();
  } else {
    message = std::string(better_rule) + ": " + better.message();
    const std::string other_text = std::string("; ") + other_rule + ": " + other.message();
    message += message.size() + other_text.size() <= kMaxCombinedRefusalBytes
                   ? other_text
                   : std::string(" (") + other_rule + " refuses too)";
  }
  if (per_pose_better) {
    *detection = std::move(pose_floors);
  } else {
    detection->too_few_intervals = detection->too_few_intervals || pose_floors.too_few_intervals;
  }
  return Status::Error(message);
}

}  // namespace

int DefaultNoiseFloorWindow(const TriadLog& log) {
  return DefaultNoiseFloorWindow(
      log.size(), log.size() < 2 ? 0.0 : log.timestamp_s.back() - log.timestamp_s.front());
}

int DefaultNoiseFloorWindow(size_t samples, double span_s) {
  constexpr int kImuTkWindow = 101;
  constexpr double kImuTkWindowMinRateHz = 60.0;  // 101 samples span at most 1.7 s
  constexpr int kShortestWindow = 11;
  if (samples < 2) return kImuTkWindow;
  if (!(span_s > 0.0)) return kImuTkWindow;
  const double rate_hz = (samples - 1) / span_s;
  if (rate_hz >= kImuTkWindowMinRateHz) return kImuTkWindow;
  int window = static_cast<int>(std::lround(rate_hz));
  if (window % 2 == 0) ++window;
  return std::max(window, kShortestWindow);
}

Status DetectStaticIntervalsFromNoiseFloor(const TriadLog& log, const NoiseFloorOptions& options,
                                           NoiseFloorDetection* detection) {
  NoiseFloorOptions resolved = options;
  if (resolved.window_samples == 0) resolved.window_samples = DefaultNoiseFloorWindow(log);
  const Status status = DetectWithWindow(log, resolved, detection);
  if (status.ok() || !detection->too_few_intervals || detection->short_intervals.empty() ||
      log.size() < 2) {
    return status;
  }
  // The holds are short for the window: of the smaller windows (about 15 % apart, down to 11
  // samples), each with intervals as short as itself, the one with which the same detector finds
  // the most poses (the larger window on a tie).
  const double span_s = log.timestamp_s.back() - log.timestamp_s.front();
  if (!(span_s > 0.0)) return status;
  const double period_s = span_s / (log.size() - 1);
  int previous = resolved.window_samples;
  NoiseFloorOptions best;
  size_t best_count = 0;
  for (double scaled = resolved.window_samples * 0.85; previous > 11; scaled *= 0.85) {
    int window = std::max(11, static_cast<int>(std::lround(scaled)) | 1);
    if (window >= previous) window = previous - 2;
    previous = window;
    NoiseFloorOptions trial = resolved;
    trial.window_samples = window;
    trial.min_interval_s =
        std::min(resolved.min_interval_s, std::floor(10.0 * (window - 1) * period_s) / 10.0);
    NoiseFloorDetection found;
    if (!DetectWithWindow(log, trial, &found).ok() || found.intervals.size() <= best_count)
      continue;
    best = trial;
    best_count = found.intervals.size();
  }
  if (best_count == 0) return status;
  detection->suggested_window_samples = best.window_samples;
  detection->suggested_min_interval_s = best.min_interval_s;
  detection->suggested_pose_count = static_cast<int>(best_count);
  std::string flags = StringPrintf("--window=%d", best.window_samples);
  if (best.min_interval_s != resolved.min_interval_s)
    flags += StringPrintf(" --min_interval_s=%g", best.min_interval_s);
  return Status::Error(StringPrintf(
      "the holds are short for the %d-sample window (%.3g s): it finds %zu static intervals of at "
      "least %g s%s and %zu shorter ones%s, and the calibration needs at least %d; %s finds "
      "%zu, or hold each pose still for at least %.1f s (%g s plus the window)",
      resolved.window_samples, (resolved.window_samples - 1) * period_s,
      detection->intervals.size(), resolved.min_interval_s,
      DescribeDurations(detection->intervals).c_str(), detection->short_intervals.size(),
      DescribeDurations(detection->short_intervals).c_str(), resolved.min_intervals, flags.c_str(),
      best_count, resolved.min_interval_s + (resolved.window_samples - 1) * period_s,
      resolved.min_interval_s));
}

}  // namespace accelcal
