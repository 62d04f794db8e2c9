#include "estimation/triad/accelerometer_outputs.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "common/format.h"
#include "common/statistics.h"
#include "estimation/triad/noise_floor_detector.h"

namespace accelcal {
namespace {

const char kAxisNames[] = "xyz";

// A window of a turn: louder than this times the quiet windows' typical variance sum.
constexpr double kTurnLoudness = 100.0;

// The stretches of consecutive samples at which `axis` equals `value`.
struct Stretches {
  long samples = 0;
  int count = 0;
  long longest = 0;
  size_t longest_start = 0;
};

Stretches StretchesAt(const TriadLog& log, int axis, double value) {
  Stretches stretches;
  long run = 0;
  for (size_t i = 0; i <= log.size(); ++i) {
    if (i < log.size() && log.output[i][axis] == value) {
      ++run;
      continue;
    }
    if (run > 0) {
      ++stretches.count;
      stretches.samples += run;
      if (run > stretches.longest) {
        stretches.longest = run;
        stretches.longest_start = i - run;
      }
    }
    run = 0;
  }
  return stretches;
}

// The fraction of consecutive samples, neither at `low` nor at `high`, whose output on `axis` is
// the same: small for an output whose noise spans steps, near 1 for one quantised below its
// noise.
double RepeatedFraction(const TriadLog& log, int axis, double low, double high) {
  long pairs = 0;
  long repeated = 0;
  for (size_t i = 1; i < log.size(); ++i) {
    const double a = log.output[i - 1][axis];
    const double b = log.output[i][axis];
    if (a == low || a == high || b == low || b == high) continue;
    ++pairs;
    repeated += a == b ? 1 : 0;
  }
  return pairs > 0 ? static_cast<double>(repeated) / pairs : 1.0;
}

}  // namespace

Status CheckNotClipped(const TriadLog& log) {
  if (log.size() < 2 * kMinClippedRun) return Status::Ok();
  for (int axis = 0; axis < 3; ++axis) {
    double low = log.output[0][axis];
    double high = low;
    for (const std::array<double, 3>& u : log.output) {
      low = std::min(low, u[axis]);
      high = std::max(high, u[axis]);
    }
    if (!(high > low)) continue;  // constant throughout: the detector says stuck
    // Clipping is only told where the noise moves the output by a step most of the time.
    if (RepeatedFraction(log, axis, low, high) > 0.5) continue;
    for (const bool maximum : {true, false}) {
      const double end = maximum ? high : low;
      const Stretches at = StretchesAt(log, axis, end);
      if (at.longest < kMinClippedRun) continue;
      return Status::Error(StringPrintf(
          "clipped samples: axis %c sits at its %s %.10g for %ld samples (%d stretch%s, the "
          "longest %ld samples from t = %.6g s), while elsewhere its noise moves it from one "
          "sample to the next: an output saturated at the end of its range, so the poses held "
          "there have means that are the range's end, not the specific force; hold the sensor "
          "so that no axis reaches the end of its range, or record with a wider range",
          kAxisNames[axis], maximum ? "maximum" : "minimum", end, at.samples, at.count,
          at.count == 1 ? "" : "es", at.longest, log.timestamp_s[at.longest_start]));
    }
  }
  return Status::Ok();
}

Status CheckOutputsFollowOrientation(const TriadLog& log) {
  const int window = DefaultNoiseFloorWindow(log);
  const size_t windows = log.size() / window;
  if (windows < 10) return Status::Ok();
  // Each non-overlapping window's mean and variance per axis.
  std::vector<std::array<double, 3>> means(windows), variances(windows);
  std::vector<double> loudness(windows);
  for (size_t w = 0; w < windows; ++w) {
    loudness[w] = 0.0;
    for (int k = 0; k < 3; ++k) {
      double sum = 0.0;
      for (int i = 0; i < window; ++i) sum += log.output[w * window + i][k];
      const double mean = sum / window;
      double squares = 0.0;
      for (int i = 0; i < window; ++i) {
        const double d = log.output[w * window + i][k] - mean;
        squares += d * d;
      }
      means[w][k] = mean;
      variances[w][k] = squares / (window - 1);
      loudness[w] += variances[w][k];
    }
  }
  // The quietest half: the poses (and any rest) of an accelerometer's session, a gyroscope's
  // rests. The turns: runs of windows louder than kTurnLoudness times the quiet half's median.
  // Only a log turned several times between rests says anything: a log of one pose and a rest
  // does not change with the pose either, and is left to the calibration's own refusal.
  std::vector<double> sorted = loudness;
  const double quiet = RankQuantile(&sorted, 0.5);
  const double quiet_median = RankQuantile(&sorted, 0.25);
  int turns = 0;
  for (size_t w = 0; w < windows; ++w) {
    const bool loud = loudness[w] > kTurnLoudness * quiet_median;
    const bool previous_loud = w > 0 && loudness[w - 1] > kTurnLoudness * quiet_median;
    if (loud && !previous_loud) ++turns;
  }
  if (turns < kMinTurns) return Status::Ok();
  const std::array<double, 3> step = OutputSteps(log);
  double largest_ratio = 0.0;
  std::array<double, 3> spread{}, noise{};
  for (int k = 0; k < 3; ++k) {
    std::vector<double> quiet_means, quiet_variances;
    for (size_t w = 0; w < windows; ++w) {
      if (loudness[w] > quiet) continue;
      quiet_means.push_back(means[w][k]);
      quiet_variances.push_back(variances[w][k]);
    }
    spread[k] = RankQuantile(&quiet_means, 0.98) - RankQuantile(&quiet_means, 0.02);
    // The noise of one sample, at least the quantisation's.
    noise[k] = std::max(std::sqrt(RankQuantile(&quiet_variances, 0.5)), step[k] / std::sqrt(12.0));
    if (!(noise[k] > 0.0)) return Status::Ok();
    largest_ratio = std::max(largest_ratio, spread[k] / noise[k]);
  }
  if (largest_ratio >= kMinOrientationSpread) return Status::Ok();
  return Status::Error(StringPrintf(
      "the outputs do not follow the pose: after each of the log's %d turns they rest where they "
      "were (the quietest windows' means spread by %.3g, %.3g, %.3g on x, y, z, at most %.1f "
      "times their noise s = %.3g, %.3g, %.3g), where an accelerometer's move by up to 2 g from "
      "pose to pose: is this a gyroscope's log (at rest it reads its offset whatever the pose)? "
      "give the accelerometer's",
      turns, spread[0], spread[1], spread[2], largest_ratio, noise[0], noise[1], noise[2]));
}

Status CheckAccelerometerOutputs(const TriadLog& log) {
  ACCELCAL_RETURN_IF_ERROR(CheckNotClipped(log));
  return CheckOutputsFollowOrientation(log);
}

}  // namespace accelcal
