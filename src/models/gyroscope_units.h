#ifndef ACCELCAL_MODELS_GYROSCOPE_UNITS_H_
#define ACCELCAL_MODELS_GYROSCOPE_UNITS_H_

// The unit of a gyroscope's output u, which sets the units of its gains and offset
// (docs/gyroscope.md): w = T K (u - b) is in rad/s whatever u is in, so K is in (rad/s) per unit
// of u and b in the unit of u. The counterpart of models/triad_units.h for the accelerometer.

#include <string>

#include "common/status.h"
#include "models/gyroscope.h"

namespace accelcal {

enum class GyroscopeOutputUnit {
  kCount,    // raw ADC counts: the gain is the datasheet's 1/sensitivity, far from 1
  kRadPerS,  // already in rad/s: gains near 1
  kDegPerS,  // in deg/s: gains near pi/180
};

// "count", "rad/s" or "deg/s": the names the flag (--gyro_unit), the JSON and the column names'
// units (io/imu_log_format.cc) use.
const char* GyroscopeOutputUnitName(GyroscopeOutputUnit unit);
Status ParseGyroscopeOutputUnit(const std::string& name, GyroscopeOutputUnit* unit);

// The gain of an ideal gyroscope in this unit, (rad/s) per unit: 1 for rad/s, pi/180 for deg/s;
// 0 for counts, which have no nominal gain (the datasheet's sensitivity gives it).
double GyroscopeNominalGain(GyroscopeOutputUnit unit);

// The unit of parameter `index` of a gyroscope's calibration (models/gyroscope.h: the block's 9,
// then the offsets) for this output unit: rad for an angle; "(rad/s)/count", "1" or
// "(rad/s)/(deg/s)" for a gain; the output's unit for an offset.
std::string GyroscopeParameterUnit(int index, GyroscopeOutputUnit unit);

// Refuses a calibration that contradicts the stated unit, as CheckGainsMatchUnit does the
// accelerometer's (models/triad_units.h): in a physical unit the offset (the output at rest) is
// within 10 rad/s of 0, since no gyroscope worth calibrating is biased by more, and each gain is
// its nominal value within [0.8, 1.25] times; a gain of counts within that range of 1 or pi/180,
// with an offset that is within 10 rad/s of 0 in that unit, means the log was already converted.
// The message names the axis, the value and the unit the data look like.
Status CheckGyroscopeMatchesUnit(const GyroscopeParameters& parameters,
                                 const GyroscopeOffset& offset, GyroscopeOutputUnit unit);

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_GYROSCOPE_UNITS_H_
