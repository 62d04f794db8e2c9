#ifndef ACCELCAL_ESTIMATION_TRIAD_TRIAD_SESSION_CALIBRATION_H_
#define ACCELCAL_ESTIMATION_TRIAD_TRIAD_SESSION_CALIBRATION_H_

// One session's maximum-likelihood calibration of a triad, the one sequence behind
// `calibrate_imu --mode=ml` (one log), `calibrate_imu --log=S1,S2,...` (each session of a device)
// and triad_repeatability (each session of an array):
//
//   1. the log's outputs checked to be an accelerometer's (not clipped, following the pose) and
//      against the stated unit, with the offsets' start (TriadStartOffset);
//   2. the static poses: from the log's own noise floor (estimation/triad/noise_floor_detector.h),
//   or
//      the intervals of a detector the caller ran (imu_tk's at its chosen k), each pose the mean
//      of all its samples;
//   3. the noise model of the pose means, white or Allan (estimation/triad/triad_pose_noise.h);
//   4. the maximum-likelihood fit (estimation/triad/triad_ml_calibration.h) started from the poses'
//      own spread (estimation/triad/triad_initial_guess.h), its gains checked against the unit;
//   5. discovery of what the 9-parameter model misses (estimation/triad/triad_discovery.h), offered
//      the Allan model whichever the fit used.
//
// It lives apart from triad_sessions.h, which combines many sessions' results, because a single
// log's calibration needs none of that; and apart from the binaries, so the two calibrate_imu
// paths cannot drift apart.

#include <string>
#include <vector>

#include "common/status.h"
#include "common/triad_log.h"
#include "estimation/solver/ceres_solve.h"
#include "estimation/triad/noise_floor_detector.h"
#include "estimation/triad/static_intervals.h"
#include "estimation/triad/triad_discovery.h"
#include "estimation/triad/triad_ml_calibration.h"
#include "estimation/triad/triad_pose_noise.h"
#include "models/triad.h"
#include "models/triad_units.h"

namespace accelcal {

// The offsets' start, in the log's unit: a number, or `automatic`: the output of an ideal
// sensor at zero specific force, 0 for a physical unit; for counts the ADC's mid-scale
// (AdcMidScale: 2^(n-1) for outputs all in [0, 2^n), imu_tk's 32768 on its 16-bit Xsens
// example; 0 for a signed ADC).
struct TriadOffsetStart {
  bool automatic = true;
  double value = 0.0;  // when !automatic
};

// The start's offset for `log` in `unit`, after refusing a log whose outputs are not an
// accelerometer's poses (clipped, or a gyroscope's: estimation/triad/accelerometer_outputs.h) or
// contradict the unit (CheckOutputsMatchUnit; the caller adds the file name).
Status TriadStartOffset(const TriadLog& log, TriadOutputUnit unit, const TriadOffsetStart& start,
                        double* offset);

struct TriadSessionOptions {
  double gravity_mps2 = 9.81;
  TriadOutputUnit unit = TriadOutputUnit::kCount;
  TriadOffsetStart offset;
  NoiseFloorOptions detector;  // CalibrateTriadSession's poses
  QuietSolveOptions solve;
  // Estimate the second-order scale terms too (TriadMlOptions::scale_nonlinearity); discovery
  // still starts from the 9 parameters.
  bool scale_nonlinearity = false;
  // The noise model of the pose means and discovery's family-wise error rate.
  TriadNoiseChoice noise = TriadNoiseChoice::kAuto;
  double alpha = 0.01;
};

struct TriadSessionCalibration {
  NoiseFloorDetection detection;               // CalibrateTriadSession's only
  std::vector<StaticInterval> pose_intervals;  // one per pose of the fit, in time order
  int sample_count = 0;                        // samples in the poses' means
  TriadPoseNoise pose_noise;
  bool allan_noise = false;   // the fit weights the pose means by the Allan model
  TriadMlOptions ml_options;  // as run: g, the start from the poses, the pose means' weights
  TriadMlResult ml;
  TriadDiscoveryOptions discovery_options;  // as run, for its report
  TriadDiscoveryResult discovery;
};

// The poses from the log's own noise floor (options.detector), then the sequence above.
// Fails as calibrate_imu does, in one line; the caller adds the file name.
Status CalibrateTriadSession(const TriadLog& log, const TriadSessionOptions& options,
                             TriadSessionCalibration* calibration);

// The default detector with its fallback: the noise floor's poses, or, when that detector
// refuses and another detector's intervals are at hand (`fallback_intervals`: imu_tk's at its
// chosen k, or null when its rules gave none), those, with the noise floor's refusal in
// `*fallback_reason` (empty when not used). A session refused only when neither finds enough
// poses: the message gives both refusals, with the flags that set each detector
// (`fallback_refusal`: why the other gave none).
Status CalibrateTriadSessionWithFallback(const TriadLog& log, const TriadSessionOptions& options,
                                         const std::vector<StaticInterval>* fallback_intervals,
                                         const std::string& fallback_refusal,
                                         TriadSessionCalibration* calibration,
                                         std::string* fallback_reason);

// The same sequence on the poses of `intervals`, found by the caller's detector (options.detector
// is not used; calibration->detection stays empty).
Status CalibrateTriadSessionOnIntervals(const TriadLog& log,
                                        const std::vector<StaticInterval>& intervals,
                                        const TriadSessionOptions& options,
                                        TriadSessionCalibration* calibration);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TRIAD_TRIAD_SESSION_CALIBRATION_H_
