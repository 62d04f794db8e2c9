#ifndef ACCELCAL_ESTIMATION_TRIAD_NOISE_FLOOR_DETECTOR_H_
#define ACCELCAL_ESTIMATION_TRIAD_NOISE_FLOOR_DETECTOR_H_

// Static intervals of a triad log, with thresholds from the log's own noise floor (issue 20,
// item 2): no initial rest is assumed, and the threshold does not depend on how still the
// first seconds were. imu_tk's detector (estimation/triad/static_intervals.h, k times the variance
// norm of a mandatory initial rest) stays as it is for `--mode=imu_tk`.
//
// Window variances. For every sample i whose centred window [i - h, i + h] of w = 2h + 1
// samples lies in the log, V_i,k is the sample variance (divided by w - 1) of axis k over the
// window, in the log's unit squared. For white noise of variance s_k^2,
//   (w - 1) V_i,k / s_k^2 ~ chi2_{w-1},
// so V / s^2 has median c(0.5) and 5 % quantile c(0.05), c(q) = chi2_{w-1} quantile(q) / (w-1)
// (c(0.05) = 0.78, c(0.5) = 0.99 for w = 101).
//
// Noise floor s_k^2, per axis. Assumption: at least 10 % of the windows lie inside static
// poses, and a moving window's variance exceeds a still one's. Then the 5 % quantile of all
// V_k lies in the still population, and
//   provisional s_k^2 = quantile_0.05(V_k) / c(0.05)
// is at most c(0.5)/c(0.05) = 1.27 times too large (when only 10 % of the log is still) and
// unbiased when all of it is. The windows below the threshold (next paragraph) with that
// provisional floor are the still ones; the floor is then their median over c(0.5), which does
// not depend on the still fraction and is not moved by the few disturbed windows (taps,
// vibration) that real poses contain. Moving windows never enter it.
//
// Threshold: a window is still when V_i,k < m s_k^2 on every axis, m = threshold_factor
// (default 10).
//   False alarms (a still window called moving, which splits or shortens a pose): for white
//   noise their probability per window and axis is P(chi2_{w-1} > m (w - 1)), 2e-148 for
//   m = 10, w = 101; factors that white noise alone crosses with probability above 1e-6 are
//   refused. Real poses also carry small disturbances: on imu_tk's Xsens log the still
//   windows reach 2 to 7 times the floor (hand taps, vibration) while moving windows reach
//   10^2 to 10^5 times; m = 10 lies in that gap.
//   Misses (motion called still): a step of A in the mean at the window's centre adds about
//   A^2 / 4 to V, a ramp of A across it about A^2 / 12, so steps below 2 sqrt(m - 1) s = 6 s
//   and ramps below 10 s go unseen with m = 10 (20 and 33 counts, 0.05 and 0.08 m/s^2, on the
//   Xsens log). For a calibration such misses are harmless: a pose whose direction moved by
//   theta within it has a mean of magnitude at least g cos(theta / 2): at most 3e-6 g short
//   for a missed 0.3 degrees, far below the noise of a pose mean.
// An interval is a run of still windows' centres (as imu_tk reports its intervals): every
// sample of an interval is at least h samples away from any motion the window saw, so a pose
// held T s gives an interval of about T - w / rate.
//
// Checks, each a refusal naming what to do (the first rule's; see the second rule below):
//   - an axis whose floor is zero (output constant to its last digit over 5 % of the windows:
//     stuck, saturated, or noise below the resolution): no threshold can be set from it;
//   - the still windows must look like noise: for white noise, quantile_0.1(V_k) / median(V_k)
//     over them equals c(0.1) / c(0.5) (0.83 for w = 101; 0.80 on the Xsens log); the slowest
//     stretches of a log that never rests spread much more (measured 0.1 to 0.17 of the white
//     value). Below half the white value the log is refused as never resting;
//   - fewer than 10 % of the windows still: the assumption above fails;
//   - fewer than `min_intervals` intervals of at least `min_interval_s` (10: the
//     maximum-likelihood fit's minimum, estimation/triad/triad_ml_calibration.h); the message says
//     how many were found, how long they are, and whether to hold poses longer or add poses.
// On a refusal the detection holds what was found, for the caller to show.
//
// A second rule, a floor per pose (issue 30, item 2), for the sessions the single floor above
// refuses or thins: a quantised sensor whose noise is below one step (most windows of a pose
// constant: zero floor, and a shape far from white), and a session whose noise differs from
// pose to pose (the louder poses above 10 times the quietest floor are dropped as motion).
//   - r_k = q_k^2 / 12, q_k the output's step (the smallest nonzero change between samples):
//     no floor is set below it, so constant windows are quantisation, not a zero floor;
//   - f_k = max(quantile_0.05(V_k) / c(0.05), r_k), the quietest windows' floor; candidate
//     windows are below P m f_k on every axis, P = 16 (poses up to 4 times apart in noise
//     standard deviation);
//   - each run of candidates gets its own floor F_k = max(median of its V_k / c(0.5), r_k),
//     twice (the second on the windows the first kept), and its still windows are those below
//     m F_k (never above P m f_k); intervals, moving runs and the counts as above, each run
//     against its own threshold;
//   - the shape check on every still window's max(V_k, r_k) over its run's threshold.
//   False alarms: within a run, as the single floor (white noise crosses m F with probability
//   2e-148); a pose whose noise is above P times the quietest pose's is lost (a refusal or one
//   pose fewer, never a wrong pose). A window of two values one step q apart has V <= q^2/4
//   (w/(w-1)), below m r = 0.83 q^2: a still quantised window is never called moving.
//   Misses: a pose's own floor replaces s in the single floor's bounds (steps below 6 F^(1/2),
//   ramps below 10 F^(1/2) go unseen), and no floor is below r, so with q = 1 count steps
//   below 1.7 counts; a run that is motion all through passes only if every window of it is
//   below P m f and it stays, about its own mean, within its own threshold: the moving-run and
//   shape checks refuse the never-resting and steadily turning logs as before (tests).
// The single floor is used unless it refuses or the per-pose floors find more intervals;
// `rule` says which chose the poses and `rule_reason` why. When neither finds enough poses the
// message gives both refusals and what the per-pose rule saw. Before either, an axis constant
// through the motion too (zero variance over most windows in which another axis moves above
// P m f, or over the whole log) is refused as stuck or saturated.

#include <array>
#include <string>
#include <vector>

#include "common/status.h"
#include "common/triad_log.h"
#include "estimation/statistics/chi_square.h"
#include "estimation/triad/static_intervals.h"

namespace accelcal {

struct NoiseFloorOptions {
  // w, odd, >= 3; 0: from the log's rate (DefaultNoiseFloorWindow).
  int window_samples = 0;
  double threshold_factor = 10;  // m: still when V < m s^2 on every axis
  double min_interval_s = 1.0;   // shorter intervals are reported apart, not used
  int min_intervals = 10;        // fewer is a refusal; 0 accepts any number
};

// The assumption and checks of the header, in one place (the streamed detector's too,
// estimation/triad/noise_floor_stream.h).
namespace noise_floor {
inline constexpr double kFloorQuantile = 0.05;       // provisional floor from this quantile of V
inline constexpr double kMinStillFraction = 0.10;    // the assumption: this much is still
inline constexpr double kShapeLowQuantile = 0.10;    // the shape check compares this quantile ...
inline constexpr double kMinFloorShape = 0.5;        // ... to the median, relative to white's
inline constexpr double kMaxWhiteFalseAlarm = 1e-6;  // per window and axis, factor's minimum
// The second rule: a pose's floor may be up to this many times the quietest windows' (poses
// whose noise differs by 4 times in standard deviation, as vibration or a hand's grip makes).
inline constexpr double kPoseFloorSpread = 16.0;
}  // namespace noise_floor

inline constexpr char kGlobalFloorRule[] = "global_floor";
inline constexpr char kPoseFloorsRule[] = "pose_floors";

struct NoiseFloorDetection {
  // Which rule chose the poses: kGlobalFloorRule, or kPoseFloorsRule when the first refused
  // (rule_reason: its refusal).
  std::string rule;
  std::string rule_reason;
  int window_samples = 0;
  std::array<double, 3> floor_variance{};      // s_k^2, the log's unit squared
  std::array<double, 3> floor_stddev{};        // s_k
  std::array<double, 3> threshold_variance{};  // m s_k^2
  double white_false_alarm = 0.0;              // P(chi2_{w-1} > m (w - 1))
  double still_fraction = 0.0;                 // of the windows, still on every axis
  // quantile_0.1 / median of the still windows' V_k, over the white-noise value (1 for white
  // noise; refused below 0.5).
  std::array<double, 3> floor_shape{};
  std::vector<StaticInterval> intervals;        // at least min_interval_s, in time order
  std::vector<StaticInterval> short_intervals;  // the shorter ones
  // Runs of still windows whose output, about its own mean, varies more than the threshold
  // allows a window on some axis: the sensor turned slowly through them (each window quiet,
  // the run not). Not poses; a log that only has these never rests.
  std::vector<StaticInterval> moving_intervals;
  // Refused only for too few intervals (the holds or their number), not for the log's noise.
  bool too_few_intervals = false;
  // On a refusal for too few intervals: the window and shortest interval with which this
  // detector finds the poses, and how many it finds (0 when no smaller window does).
  int suggested_window_samples = 0;
  double suggested_min_interval_s = 0.0;
  int suggested_pose_count = 0;
};

// The window when options.window_samples is 0: about one second of samples, as imu_tk's 101 at
// its 100 Hz, while a window covers whole holds at low rates. imu_tk's 101 samples are kept
// wherever they span at most 1.7 s (rates of 60 Hz and up: 1.01 s at imu_tk's 100 Hz, 1.6 s at
// 62.5 Hz, 0.1 s at 1 kHz); below 60 Hz, the rate's samples per second rounded to the next odd
// number, at least 11 (25 at 25 Hz, 11 at 10 Hz and below). A window longer than the holds
// never sees a still stretch: at 25 Hz, 101 samples are 4 s.
int DefaultNoiseFloorWindow(const TriadLog& log);
// The same from the log's sample count and span (last minus first time stamp).
int DefaultNoiseFloorWindow(size_t samples, double span_s);

// Fails, saying what is wrong, on options (with the window resolved) the detector refuses.
Status CheckNoiseFloorOptions(const NoiseFloorOptions& options);

// A described run of still windows into detection's intervals: moving when its output, about
// its own mean, varies more than `threshold` (its windows') allows on some axis; else used or
// short by duration.
void FileInterval(const StaticInterval& interval, const std::array<double, 3>& threshold,
                  const NoiseFloorOptions& options, NoiseFloorDetection* detection);

// The per-pose rule's reason when it finds more poses than the single floor (rule_reason).
std::string MorePosesReason(size_t global_poses, size_t pose_floor_poses, double factor);

// The output's step on each axis: the smallest nonzero change between consecutive samples
// (1 for counts, 16 for a 12-bit sensor left-aligned in 16 bits; tiny for a float log). 0 for an
// axis constant over the whole log.
std::array<double, 3> OutputSteps(const TriadLog& log);
// One step of OutputSteps: *step updated with the change from `previous` to `output`.
void UpdateOutputSteps(const std::array<double, 3>& previous, const std::array<double, 3>& output,
                       std::array<double, 3>* step);

// Fails, in one line saying what to do, on the checks above, on an invalid option, or on a log
// shorter than the window. When too few intervals are found but shorter ones are (the holds are
// short for the window), smaller windows are tried, each with the shortest interval lowered to
// the window's duration (rounded down to 0.1 s) if that is below options.min_interval_s; the
// largest that this detector accepts is named in the message and in detection->suggested_*.
Status DetectStaticIntervalsFromNoiseFloor(const TriadLog& log, const NoiseFloorOptions& options,
                                           NoiseFloorDetection* detection);

// V_i,k for the centres i = h .. n - h - 1, at index i - h (empty when n < w): the values of
// WindowVarianceStream (estimation/triad/window_variance_stream.h) over the log.
std::vector<std::array<double, 3>> WindowVariances(const TriadLog& log, int window);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TRIAD_NOISE_FLOOR_DETECTOR_H_
