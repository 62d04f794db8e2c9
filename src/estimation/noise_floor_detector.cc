#include "estimation/noise_floor_detector.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/format.h"
#include "estimation/chi_square.h"

namespace accelcal {
namespace {

// The assumption and checks of the header, in one place.
constexpr double kFloorQuantile = 0.05;       // provisional floor from this quantile of V
constexpr double kMinStillFraction = 0.10;    // the assumption: this much of the log is still
constexpr double kShapeLowQuantile = 0.10;    // the shape check compares this quantile ...
constexpr double kMinFloorShape = 0.5;        // ... to the median, relative to white noise's
constexpr double kMaxWhiteFalseAlarm = 1e-6;  // per window and axis, for the factor's minimum

const char kAxisNames[] = "xyz";

// The element of rank round(q (n - 1)) in increasing order; `values` is reordered.
double Quantile(std::vector<double>* values, double q) {
  const size_t rank = static_cast<size_t>(q * (values->size() - 1) + 0.5);
  std::nth_element(values->begin(), values->begin() + rank, values->end());
  return (*values)[rank];
}

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

Status ZeroFloor(int axis, int window) {
  return Status::Error(StringPrintf(
      "axis %c is constant to its last digit over much of the log (%d-sample windows of zero "
      "variance): stuck, saturated, or noise below the output's resolution, so there is no "
      "noise floor to set a still threshold from; check that axis of the sensor",
      kAxisNames[axis], window));
}

// " (2.8 to 51.4 s, median 7.8 s)", or nothing for no intervals.
std::string DescribeDurations(const std::vector<StaticInterval>& intervals) {
  if (intervals.empty()) return "";
  std::vector<double> durations;
  for (const StaticInterval& interval : intervals) durations.push_back(interval.duration_s);
  const double median = Quantile(&durations, 0.5);
  const auto [shortest, longest] = std::minmax_element(durations.begin(), durations.end());
  return StringPrintf(" (%.1f to %.1f s, median %.1f s)", *shortest, *longest, median);
}

Status CheckOptions(const NoiseFloorOptions& options) {
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
        "%d samples (crossed by still windows with probability %.2g); use at least %.3g",
        factor, window, ChiSquareSurvival(factor * dof, dof), minimum));
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

// The run of still centres [first, last] (window indices) as an interval of samples.
StaticInterval IntervalOfRun(const TriadLog& log, int half, int first, int last) {
  StaticInterval interval;
  interval.start = first + half;
  interval.end = last + half;
  DescribeInterval(log, &interval);
  return interval;
}

}  // namespace

double ChiSquareQuantile(double p, double dof) {
  // The mean is dof and the spread sqrt(2 dof); expand the bracket until it holds p.
  double low = 0.0;
  double high = dof + 10.0 * std::sqrt(2.0 * dof) + 10.0;
  while (ChiSquareCdf(high, dof) < p) high *= 2.0;
  while (high - low > 1e-12 * high) {
    const double middle = 0.5 * (low + high);
    if (ChiSquareCdf(middle, dof) < p) {
      low = middle;
    } else {
      high = middle;
    }
  }
  return 0.5 * (low + high);
}

std::vector<std::array<double, 3>> WindowVariances(const TriadLog& log, int window) {
  const int n = static_cast<int>(log.size());
  if (n < window) return {};
  const int count = n - window + 1;
  std::vector<std::array<double, 3>> variances(count);
  for (int axis = 0; axis < 3; ++axis) {
    double reference = 0.0;
    double sum = 0.0;
    double sum_squares = 0.0;
    for (int j = 0; j < count; ++j) {
      if (j % window == 0) {
        // Deviations from a sample of the window keep sum_squares - sum^2 / w free of the
        // cancellation a large offset (32768 counts) would cause.
        reference = log.output[j][axis];
        sum = 0.0;
        sum_squares = 0.0;
        for (int i = j; i < j + window; ++i) {
          const double deviation = log.output[i][axis] - reference;
          sum += deviation;
          sum_squares += deviation * deviation;
        }
      } else {
        const double leaving = log.output[j - 1][axis] - reference;
        const double entering = log.output[j + window - 1][axis] - reference;
        sum += entering - leaving;
        sum_squares += entering * entering - leaving * leaving;
      }
      variances[j][axis] = std::max(0.0, (sum_squares - sum * sum / window) / (window - 1));
    }
  }
  return variances;
}

Status DetectStaticIntervalsFromNoiseFloor(const TriadLog& log, const NoiseFloorOptions& options,
                                           NoiseFloorDetection* detection) {
  *detection = NoiseFloorDetection();
  ACCELCAL_RETURN_IF_ERROR(CheckOptions(options));
  const int window = options.window_samples;
  const int half = window / 2;
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
  auto white_quantile = [dof](double q) { return ChiSquareQuantile(q, dof) / dof; };

  std::array<double, 3> provisional_threshold{};
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<double> column = Column(variances, axis, nullptr);
    provisional_threshold[axis] =
        factor * Quantile(&column, kFloorQuantile) / white_quantile(kFloorQuantile);
    if (!(provisional_threshold[axis] > 0.0)) return ZeroFloor(axis, window);
  }
  std::vector<bool> still = StillWindows(variances, provisional_threshold);
  const bool any_still = std::find(still.begin(), still.end(), true) != still.end();
  if (any_still) {
    for (int axis = 0; axis < 3; ++axis) {
      std::vector<double> column = Column(variances, axis, &still);
      detection->floor_variance[axis] = Quantile(&column, 0.5) / white_quantile(0.5);
      if (!(detection->floor_variance[axis] > 0.0)) return ZeroFloor(axis, window);
      detection->floor_stddev[axis] = std::sqrt(detection->floor_variance[axis]);
      detection->threshold_variance[axis] = factor * detection->floor_variance[axis];
    }
    still = StillWindows(variances, detection->threshold_variance);
  }
  const long still_count = std::count(still.begin(), still.end(), true);
  detection->still_fraction = static_cast<double>(still_count) / still.size();

  if (still_count > 0) {
    const double white_shape = white_quantile(kShapeLowQuantile) / white_quantile(0.5);
    for (int axis = 0; axis < 3; ++axis) {
      std::vector<double> column = Column(variances, axis, &still);
      const double median = Quantile(&column, 0.5);
      const double low = Quantile(&column, kShapeLowQuantile);
      detection->floor_shape[axis] = median > 0.0 ? low / median / white_shape : 0.0;
    }
    for (int axis = 0; axis < 3; ++axis) {
      if (detection->floor_shape[axis] >= kMinFloorShape) continue;
      return Status::Error(StringPrintf(
          "the quietest windows of the log do not look like sensor noise (on axis %c their "
          "%.0f%% quantile of variance is %.2f of their median, white noise gives %.2f): the "
          "sensor never rests; hold it still in each pose",
          kAxisNames[axis], 100 * kShapeLowQuantile, detection->floor_shape[axis] * white_shape,
          white_shape));
    }
  }
  if (detection->still_fraction < kMinStillFraction) {
    return Status::Error(StringPrintf(
        "only %.1f%% of the log's %d-sample windows are still (below %g times the noise floor on "
        "every axis); the noise floor can only be told from motion when at least %.0f%% are: "
        "hold the sensor still in each pose",
        100 * detection->still_fraction, window, factor, 100 * kMinStillFraction));
  }

  for (int j = 0; j < static_cast<int>(still.size());) {
    if (!still[j]) {
      ++j;
      continue;
    }
    int last = j;
    while (last + 1 < static_cast<int>(still.size()) && still[last + 1]) ++last;
    StaticInterval interval = IntervalOfRun(log, half, j, last);
    bool moving = false;
    for (int axis = 0; axis < 3; ++axis) {
      const double stddev = interval.noise_stddev[axis];
      moving = moving || stddev * stddev > detection->threshold_variance[axis];
    }
    if (moving) {
      detection->moving_intervals.push_back(interval);
    } else if (interval.duration_s >= options.min_interval_s) {
      detection->intervals.push_back(interval);
    } else {
      detection->short_intervals.push_back(interval);
    }
    j = last + 1;
  }

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

}  // namespace accelcal
