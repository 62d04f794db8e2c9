#include "estimation/triad/triad_session_calibration.h"

#include <algorithm>
#include <string>

#include "estimation/triad/accelerometer_outputs.h"
#include "estimation/triad/triad_initial_guess.h"

namespace accelcal {

Status TriadStartOffset(const TriadLog& log, TriadOutputUnit unit, const TriadOffsetStart& start,
                        double* offset) {
  *offset = start.value;
  if (start.automatic) *offset = unit == TriadOutputUnit::kCount ? AdcMidScale(log) : 0.0;
  // What the log is (clipped, a gyroscope's) before what its size says of the unit.
  ACCELCAL_RETURN_IF_ERROR(CheckAccelerometerOutputs(log));
  return CheckOutputsMatchUnit(log, unit, *offset);
}

namespace {

// The text up to its first ': ' or '; ' (the finding, without the reasoning or advice after it),
// at most max_bytes (cut at a space, with "...").
std::string FirstClause(const std::string& text, size_t max_bytes) {
  size_t end = std::min(text.find(": "), text.find("; "));
  std::string clause = text.substr(0, end);
  if (clause.size() > max_bytes) {
    const size_t space = clause.rfind(' ', max_bytes - 4);
    clause = clause.substr(0, space == std::string::npos ? max_bytes - 4 : space) + " ...";
  }
  return clause;
}

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
  ml_options.quantisation_variance = calibration->pose_noise.quantisation_variance;
  ACCELCAL_RETURN_IF_ERROR(CalibrateTriadMl(poses, ml_options, &calibration->ml));
  ACCELCAL_RETURN_IF_ERROR(CheckGainsMatchUnit(calibration->ml.parameters, options.unit));
  TriadDiscoveryOptions& discovery = calibration->discovery_options;
  discovery = TriadDiscoveryOptions();
  discovery.alpha = options.alpha;
  discovery.fit.gravity_mps2 = options.gravity_mps2;
  discovery.fit.initial = ml_options.initial;
  discovery.fit.solve = options.solve;
  discovery.fit.quantisation_variance = ml_options.quantisation_variance;
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
    // The noise floor's finding and advice first; imu_tk's refusal in one clause after it (its
    // advice, an initial rest to give, would only lead to the same refusal here), dropped when
    // the line would pass calibrate_imu's 600 bytes with the file's name.
    constexpr size_t kMaxRefusalBytes = 520;
    constexpr size_t kMaxClauseBytes = 140;
    std::string message =
        "no static detector finds the poses: the noise floor's: " + detected.message();
    std::string clause = FirstClause(fallback_refusal, kMaxClauseBytes);
    std::string fallback =
        clause.empty() ? "; imu_tk's intervals, the fallback, give none either"
                       : "; imu_tk's intervals, the fallback, give none either (" + clause + ")";
    if (message.size() + fallback.size() > kMaxRefusalBytes)
      fallback = "; imu_tk's intervals, the fallback, give none either";
    return Status::Error(message + fallback);
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
