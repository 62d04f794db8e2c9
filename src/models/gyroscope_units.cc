#include "models/gyroscope_units.h"

#include <cmath>

#include "common/format.h"

namespace accelcal {

const char* GyroscopeOutputUnitName(GyroscopeOutputUnit unit) {
  switch (unit) {
    case GyroscopeOutputUnit::kCount:
      return "count";
    case GyroscopeOutputUnit::kRadPerS:
      return "rad/s";
    case GyroscopeOutputUnit::kDegPerS:
      return "deg/s";
  }
  return "count";
}

Status ParseGyroscopeOutputUnit(const std::string& name, GyroscopeOutputUnit* unit) {
  for (const GyroscopeOutputUnit candidate :
       {GyroscopeOutputUnit::kCount, GyroscopeOutputUnit::kRadPerS,
        GyroscopeOutputUnit::kDegPerS}) {
    if (name == GyroscopeOutputUnitName(candidate)) {
      *unit = candidate;
      return Status::Ok();
    }
  }
  return Status::Error("'" + name +
                       "' is not a gyroscope unit; say count (raw ADC counts), rad/s or deg/s");
}

double GyroscopeNominalGain(GyroscopeOutputUnit unit) {
  switch (unit) {
    case GyroscopeOutputUnit::kRadPerS:
      return 1.0;
    case GyroscopeOutputUnit::kDegPerS:
      return M_PI / 180.0;
    case GyroscopeOutputUnit::kCount:
      return 0.0;
  }
  return 0.0;
}

std::string GyroscopeParameterUnit(int index, GyroscopeOutputUnit unit) {
  if (index >= kGyroscopeCalibrationOffsetX) return GyroscopeOutputUnitName(unit);
  if (index >= kGyroscopeGainX && index <= kGyroscopeGainZ) {
    if (unit == GyroscopeOutputUnit::kRadPerS) return "1";
    if (unit == GyroscopeOutputUnit::kDegPerS) return "(rad/s)/(deg/s)";
    return "(rad/s)/count";
  }
  return GyroscopeParameterInfos()[index].unit;
}

Status CheckGyroscopeMatchesUnit(const GyroscopeParameters& parameters,
                                 const GyroscopeOffset& offset, GyroscopeOutputUnit unit) {
  const auto near = [](double gain, double nominal) {
    return gain / nominal >= 0.8 && gain / nominal <= 1.25;
  };
  constexpr double kLargestOffsetRadPerS = 10.0;
  for (int k = 0; k < 3; ++k) {
    if (unit != GyroscopeOutputUnit::kCount &&
        std::fabs(offset[k]) * GyroscopeNominalGain(unit) > kLargestOffsetRadPerS) {
      return Status::Error(StringPrintf(
          "the gyroscope's output at rest averages %.6g %s on its %c axis, more than any "
          "gyroscope's offset (%g rad/s): are the outputs raw counts? give --gyro_unit=count and "
          "--initial_gyro_gain",
          offset[k], GyroscopeOutputUnitName(unit), "xyz"[k], kLargestOffsetRadPerS));
    }
  }
  for (int k = 0; k < 3; ++k) {
    const double gain = parameters[kGyroscopeGainX + k];
    const char axis = "xyz"[k];
    if (unit != GyroscopeOutputUnit::kCount && !near(gain, GyroscopeNominalGain(unit))) {
      return Status::Error(StringPrintf(
          "the gyroscope's gain_%c came out %.6g (rad/s) per %s, not near the %.6g of a "
          "gyroscope in %s: %s",
          axis, gain, GyroscopeOutputUnitName(unit), GyroscopeNominalGain(unit),
          GyroscopeOutputUnitName(unit),
          gain < 0.1 * GyroscopeNominalGain(unit)
              ? "are the outputs raw counts? give --gyro_unit=count and --initial_gyro_gain"
              : "give the unit the gyroscope's outputs are in, --gyro_unit=count, rad/s or deg/s"));
    }
    if (unit == GyroscopeOutputUnit::kCount) {
      for (const GyroscopeOutputUnit physical :
           {GyroscopeOutputUnit::kRadPerS, GyroscopeOutputUnit::kDegPerS}) {
        // Converted outputs also rest near 0 (a start far from the gain can end there too).
        if (near(gain, GyroscopeNominalGain(physical)) &&
            std::fabs(offset[k]) * GyroscopeNominalGain(physical) <= kLargestOffsetRadPerS) {
          return Status::Error(StringPrintf(
              "the gyroscope's gain_%c came out %.6g (rad/s) per count, as a gyroscope in %s "
              "would: the outputs look already converted; give --gyro_unit=%s",
              axis, gain, GyroscopeOutputUnitName(physical), GyroscopeOutputUnitName(physical)));
        }
      }
    }
  }
  return Status::Ok();
}

}  // namespace accelcal
