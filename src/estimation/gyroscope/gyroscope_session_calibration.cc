#include "estimation/gyroscope/gyroscope_session_calibration.h"

#include "estimation/gyroscope/gyroscope_turn_scale.h"

namespace accelcal {

Status CalibrateGyroscopeSession(const TriadLog& log, const std::vector<StaticInterval>& intervals,
                                 const TriadMlOptions& accelerometer_options,
                                 const TriadMlResult& accelerometer,
                                 const GyroscopeSessionOptions& options,
                                 GyroscopeSessionCalibration* calibration) {
  GyroscopeMlOptions& ml = calibration->ml_options;
  ml = GyroscopeMlOptions();
  ml.gravity_mps2 = options.gravity_mps2;
  ml.unit = options.unit;
  ml.initial = options.initial;
  ml.quantisation_step = options.unit == GyroscopeOutputUnit::kCount ? 1.0 : 0.0;
  ml.latitude_given = options.latitude_given;
  ml.latitude_rad = options.latitude_rad;
  // The unit and the start's gains against the turns, before any fit can hide them.
  ACCELCAL_RETURN_IF_ERROR(CheckGyroscopeTurnScale(
      MeasureGyroscopeTurnScale(log, intervals, accelerometer.directions, options.initial),
      options.initial, options.unit));
  GyroscopeDiscoveryOptions& discovery = calibration->discovery_options;
  discovery = GyroscopeDiscoveryOptions();
  discovery.alpha = options.alpha;
  discovery.fit = ml;
  discovery.turn_sampling = options.turn_sampling;
  ACCELCAL_RETURN_IF_ERROR(DiscoverGyroscope(log, intervals, accelerometer_options, accelerometer,
                                             discovery, &calibration->discovery));
  calibration->ml = calibration->discovery.baseline;
  return Status::Ok();
}

}  // namespace accelcal
