#ifndef ACCELCAL_MODELS_TRIAD_UNITS_H_
#define ACCELCAL_MODELS_TRIAD_UNITS_H_

// The unit of a triad's output u, which sets the units of its gains and offsets
// (docs/triad.md): a = T K (u - b) is in m/s^2 whatever u is in, so K is in (m/s^2) per unit
// of u and b in the unit of u. A log does not say its unit; the user does (calibrate_imu
// --unit), and a calibration whose gains contradict the stated unit is refused: a log in m/s^2
// read as counts would otherwise give "gains" near 1 and a calibration that looks fine.

#include <string>

#include "common/status.h"
#include "common/triad_log.h"
#include "models/triad.h"

namespace accelcal {

enum class TriadOutputUnit {
  kCount,  // raw ADC counts: gains of a real sensor are far from 1 (m/s^2)/count
  kMps2,   // already in m/s^2: gains near 1
  kG,      // in standard gravities: gains near 9.80665 (m/s^2)/g
};

// "count", "m/s^2" or "g": the names the flag, the JSON and the calibration file use.
const char* TriadOutputUnitName(TriadOutputUnit unit);
Status ParseTriadOutputUnit(const std::string& name, TriadOutputUnit* unit);

// The unit of parameter `index` (models/triad.h's block order) for this output unit:
// rad for an angle, "(m/s^2)/count", "1" or "(m/s^2)/g" for a gain, the output's unit for an
// offset.
std::string TriadParameterUnit(int index, TriadOutputUnit unit);

// Refuses gains that contradict the stated unit. A physical unit's gain is its nominal value
// (1 or 9.80665) within [0.8, 1.25] times, since no accelerometer worth calibrating is 20%
// off; a gain of counts within those ranges means the log was already converted. The message
// names the axis, the gain and the unit the data look like.
Status CheckGainsMatchUnit(const TriadParameters& parameters, TriadOutputUnit unit);

// Refuses, before any fit, a log whose outputs contradict the stated unit: at rest or in
// ordinary motion an accelerometer's output is near 1 g in magnitude, so the median over the
// samples of |u - offset| is within [0.5, 2] g in a physical unit, and far from both 1 and
// 9.8 in counts (a real ADC has many counts per m/s^2). `offset` is the start's (AdcMidScale
// or the user's).
Status CheckOutputsMatchUnit(const TriadLog& log, TriadOutputUnit unit, double offset);

// |u - offset| of one sample, whose median CheckOutputsMatchUnit takes.
double OutputMagnitude(const std::array<double, 3>& u, double offset);

// CheckOutputsMatchUnit from that median, found elsewhere (a log too long to hold).
Status CheckMedianMagnitudeMatchesUnit(double median, TriadOutputUnit unit, double offset);

// The output of an ideal ADC at zero input: for outputs that are all non-negative, the
// mid-scale 2^(n-1) of the smallest unsigned n-bit range [0, 2^n) that holds them (32768 for
// imu_tk's 16-bit Xsens log); 0 when any output is negative (a signed ADC is centred at 0).
double AdcMidScale(const TriadLog& log);

// The same from the outputs' smallest and largest values.
double AdcMidScale(double lowest, double highest);

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_TRIAD_UNITS_H_
