#include "estimation/triad/triad_session_calibration.h"

#include "estimation/triad/triad_initial_guess.h"

namespace accelcal {

Status TriadStartOffset(const TriadLog& log, TriadOutputUnit unit, const TriadOffsetStart& start,
                        double* offset) {
  *offset = start.value;
  if (start.automatic) *offset = unit == TriadOutputUnit::kCount ? AdcMidScale(log) : 0.0;
  return CheckOutputsMatchUnit(log, unit, *offset);
}

namespace {

// Steps 2 to 5 on the poses of `intervals`, the log's unit already checked.
Status CalibrateOnPoses(const TriadLog& log, const std::vector<StaticInterval>& intervals,
                        const TriadSessionOptions& options, TriadSessionCalibration* calibration) {
  calibration->pose_intervals = intervals;
  const std::vector<TriadPoseMean> poses =
      PoseMeansOfIntervals(log, calibration->pose_intervals, 2);
  calibration->sample_count = 0;
  for (const TriadPoseMean& pose : poses) calibration->sample_count += pose.sample_count;
  ACCELCAL_RETURN_IF_ERROR(
      SelectTriadPoseNoise(log, calibration->pose_intervals, poses, options.noise, options.alpha,
                           &calibration->pose_noise, &calibration->allan_noise));
  TriadMlOptions& ml_options = calibration->ml_options;
  ml_options = TriadMlOptions();
  ml_options.gravity_mps2 = options.gravity_mps2;
  ml_options.initial = TriadStartFromPoses(poses, options.gravity_mps2);
  ml_options.solve = options.solve;
  ml_options.scale_nonlinearity = options.scale_nonlinearity;
  if (calibration->allan_noise)
    ml_options.pose_mean_variance = calibration->pose_noise.candidate.pose_mean_variance;
  ACCELCAL_RETURN_IF_ERROR(CalibrateTriadMl(poses, ml_options, &calibration->ml));
  ACCELCAL_RETURN_IF_ERROR(CheckGainsMatchUnit(calibration->ml.parameters, options.unit));
  TriadDiscoveryOptions& discovery = calibration->discovery_options;
  discovery = TriadDiscoveryOptions();
  discovery.alpha = options.alpha;
  discovery.fit.gravity_mps2 = options.gravity_mps2;
  discovery.fit.initial = ml_options.initial;
  discovery.fit.solve = options.solve;
  discovery.unit = TriadOutputUnitName(options.unit);
  discovery.coloured_noise = calibration->pose_noise.candidate;
  for (int k = 0; k < 3; ++k)
    discovery.gain_mps2_per_unit[k] = calibration->ml.parameters[kTriadGainX + k];
  return DiscoverTriad(poses, discovery, &calibration->discovery);
}

}  // namespace

Status CalibrateTriadSession(const TriadLog& log, const TriadSessionOptions& options,
                             TriadSessionCalibration* calibration) {
  double offset = 0.0;
  ACCELCAL_RETURN_IF_ERROR(TriadStartOffset(log, options.unit, options.offset, &offset));
  ACCELCAL_RETURN_IF_ERROR(
      DetectStaticIntervalsFromNoiseFloor(log, options.detector, &calibration->detection));
  return CalibrateOnPoses(log, calibration->detection.intervals, options, calibration);
}

Status CalibrateTriadSessionWithFallback(const TriadLog& log, const TriadSessionOptions& options,
                                         const std::vector<StaticInterval>* fallback_intervals,
                                         const std::string& fallback_refusal,
                                         TriadSessionCalibration* calibration,
                                         std::string* fallback_reason) {
  fallback_reason->clear();
  double offset = 0.0;
  ACCELCAL_RETURN_IF_ERROR(TriadStartOffset(log, options.unit, options.offset, &offset));
  const Status detected =
      DetectStaticIntervalsFromNoiseFloor(log, options.detector, &calibration->detection);
  if (detected.ok()) {
    return CalibrateOnPoses(log, calibration->detection.intervals, options, calibration);
  }
  if (fallback_intervals == nullptr) {
    return Status::Error(
        "no static detector finds the poses. The noise floor's (--threshold_factor, "
        "--min_interval_s): " +
        detected.message() + ". imu_tk's, the fallback (--init_rest_s, --window, --min_intervals): " +
        fallback_refusal);
  }
  *fallback_reason = detected.message();
  return CalibrateOnPoses(log, *fallback_intervals, options, calibration);
}

Status CalibrateTriadSessionOnIntervals(const TriadLog& log,
                                        const std::vector<StaticInterval>& intervals,
                                        const TriadSessionOptions& options,
                                        TriadSessionCalibration* calibration) {
  double offset = 0.0;
  ACCELCAL_RETURN_IF_ERROR(TriadStartOffset(log, options.unit, options.offset, &offset));
  return CalibrateOnPoses(log, intervals, options, calibration);
}

}  // namespace accelcal
