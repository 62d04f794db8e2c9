// Prints the catalogue's units as JSON, {"bias_x": "m/s^2", ...}, and the triad's and the
// gyroscope's for a log in counts: what every `units` map of the binaries' JSON must agree with
// (tests/json_schema_test.py, docs/json.md).

#include <iostream>
#include <nlohmann/json.hpp>

#include "models/effects.h"
#include "models/gyroscope_effect_list.h"
#include "models/gyroscope_units.h"
#include "models/triad.h"
#include "models/triad_units.h"

int main() {
  nlohmann::json units = nlohmann::json::object();
  for (const accelcal::ParameterInfo& info : accelcal::ParameterCatalogue()) {
    units[info.name] = info.unit;
  }
  // The triad's, for outputs in counts (the logs the schema test runs on); its second-order
  // scale terms are the catalogue's quantity on a third axis.
  for (int p = 0; p < accelcal::kTriadParameterCount; ++p) {
    units[accelcal::TriadParameterInfos()[p].name] =
        accelcal::TriadParameterUnit(p, accelcal::TriadOutputUnit::kCount);
  }
  units["scale_nonlinearity_z"] = units["scale_nonlinearity_x"];
  // The gyroscope's (imu_tk's calibration of it, a calibration file's gyroscope section: the
  // block's 9 and the offsets), for outputs in counts.
  for (int p = 0; p < accelcal::kGyroscopeCalibrationParameterCount; ++p) {
    units[accelcal::GyroscopeCalibrationParameterName(p)] =
        accelcal::GyroscopeParameterUnit(p, accelcal::GyroscopeOutputUnit::kCount);
  }
  // The gyroscope's effect terms (models/gyroscope_effect_list.h), which a calibration of the model
  // discovery settled on carries.
  for (int c = 0; c < accelcal::kGyroscopeEffectCoefficientCount; ++c) {
    units[accelcal::GyroscopeEffectCoefficientName(c)] =
        accelcal::GyroscopeEffectCoefficientUnit(c);
  }
  std::cout << units.dump() << "\n";
  return 0;
}
