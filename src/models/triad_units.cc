#include "models/triad_units.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "common/format.h"
#include "common/statistics.h"

namespace accelcal {
namespace {

constexpr double kStandardGravity = 9.80665;  // m/s^2 per g, by definition
constexpr double kLowestPlausible = 0.8;      // gain / nominal
constexpr double kHighestPlausible = 1.25;

bool NearNominal(double gain, double nominal) {
  const double ratio = gain / nominal;
  return ratio >= kLowestPlausible && ratio <= kHighestPlausible;
}

}  // namespace

const char* TriadOutputUnitName(TriadOutputUnit unit) {
  switch (unit) {
    case TriadOutputUnit::kCount:
      return "count";
    case TriadOutputUnit::kMps2:
      return "m/s^2";
    case TriadOutputUnit::kG:
      return "g";
  }
  return "count";
}

Status ParseTriadOutputUnit(const std::string& name, TriadOutputUnit* unit) {
  for (const TriadOutputUnit candidate :
       {TriadOutputUnit::kCount, TriadOutputUnit::kMps2, TriadOutputUnit::kG}) {
    if (name == TriadOutputUnitName(candidate)) {
      *unit = candidate;
      return Status::Ok();
    }
  }
  return Status::Error("'" + name +
                       "' is not an output unit; say count (raw ADC counts), m/s^2 or g");
}

std::string TriadParameterUnit(int index, TriadOutputUnit unit) {
  if (index >= kTriadOffsetX && index <= kTriadOffsetZ) return TriadOutputUnitName(unit);
  if (index >= kTriadGainX && index <= kTriadGainZ) {
    if (unit == TriadOutputUnit::kMps2) return "1";
    return std::string("(m/s^2)/") + TriadOutputUnitName(unit);
  }
  return TriadParameterInfos()[index].unit;
}

double OutputMagnitude(const std::array<double, 3>& u, double offset) {
  return std::hypot(u[0] - offset, u[1] - offset, u[2] - offset);
}

Status CheckOutputsMatchUnit(const TriadLog& log, TriadOutputUnit unit, double offset) {
  if (log.output.empty()) return Status::Ok();
  std::vector<double> magnitude;
  magnitude.reserve(log.output.size());
  for (const std::array<double, 3>& u : log.output) magnitude.push_back(OutputMagnitude(u, offset));
  return CheckMedianMagnitudeMatchesUnit(UpperMedian(std::move(magnitude)), unit, offset);
}

Status CheckMedianMagnitudeMatchesUnit(double median, TriadOutputUnit unit, double offset) {
  const bool looks_mps2 = median >= 0.5 * kStandardGravity && median <= 2.0 * kStandardGravity;
  const bool looks_g = median >= 0.5 && median <= 2.0;
  const char* stated = TriadOutputUnitName(unit);
  const std::string measured =
      StringPrintf("the median magnitude of the outputs (less the offset %g) is %.4g %s", offset,
                   median, stated);
  if (unit == TriadOutputUnit::kCount && (looks_mps2 || looks_g)) {
    const char* looks = looks_mps2 ? "m/s^2" : "g";
    return Status::Error(measured + ", about 1 g in " + looks +
                         ": the log looks already converted to " + looks +
                         ", not raw counts; say --unit=" + looks);
  }
  // Near zero in a physical unit: no gravity in the outputs at all.
  const double one_g = unit == TriadOutputUnit::kMps2 ? kStandardGravity : 1.0;
  if (unit != TriadOutputUnit::kCount && median < 0.05 * one_g) {
    return Status::Error(
        measured +
        StringPrintf(
            ", under 5%% of 1 g (%g %s): the outputs hold no gravity, as a log with gravity "
            "removed "
            "(Android's or phyphox's 'linear acceleration', a 'user acceleration') or a "
            "gyroscope's "
            "does; calibrate from the accelerometer's raw log, which a static pose shows as 1 g",
            one_g, stated));
  }
  if (unit == TriadOutputUnit::kMps2 && !looks_mps2) {
    return Status::Error(measured +
                         ", not about 9.8 as 1 g is in m/s^2: the log is in another "
                         "unit (raw counts? say --unit=count, or --unit=g)");
  }
  if (unit == TriadOutputUnit::kG && !looks_g) {
    return Status::Error(measured +
                         ", not about 1 as 1 g is in g: the log is in another unit "
                         "(raw counts? say --unit=count, or --unit=m/s^2)");
  }
  return Status::Ok();
}

double AdcMidScale(const TriadLog& log) {
  double highest = 0.0;
  for (const std::array<double, 3>& output : log.output) {
    for (const double value : output) {
      if (value < 0.0) return 0.0;
      highest = std::max(highest, value);
    }
  }
  return AdcMidScale(0.0, highest);
}

double AdcMidScale(double lowest, double highest) {
  if (lowest < 0.0) return 0.0;
  double range = 2.0;  // 2^n > highest, n >= 1
  while (range <= highest) range *= 2.0;
  return range / 2.0;
}

Status CheckGainsMatchUnit(const TriadParameters& parameters, TriadOutputUnit unit) {
  if (unit == TriadOutputUnit::kCount) {
    // A log already in m/s^2 or g gives every gain near 1 or g; one or two axes there, the
    // others in counts' range, is an axis the poses did not determine (its gain left near a
    // start of 1), not a unit.
    int nominal = 0;
    int undetermined = -1;
    for (int axis = 0; axis < 3; ++axis) {
      const double gain = parameters[kTriadGainX + axis];
      if (NearNominal(gain, 1.0) || NearNominal(gain, kStandardGravity)) {
        ++nominal;
        if (undetermined < 0) undetermined = axis;
      }
    }
    if (nominal == 1 || nominal == 2) {
      const char name = "xyz"[undetermined];
      return Status::Error(StringPrintf(
          "gain_%c = %.6g (m/s^2)/count while the other axes' gains are those of counts: the "
          "poses do not determine the gains (poses all in a plane, or too few); hold the sensor "
          "with each axis up and down (--mode=ml names what the poses cannot determine)",
          name, parameters[kTriadGainX + undetermined]));
    }
  }
  for (int axis = 0; axis < 3; ++axis) {
    const double gain = parameters[kTriadGainX + axis];
    const char name = "xyz"[axis];
    switch (unit) {
      case TriadOutputUnit::kCount:
        if (NearNominal(gain, 1.0) || NearNominal(gain, kStandardGravity)) {
          return Status::Error(StringPrintf(
              "gain_%c = %.6g (m/s^2)/count: the log looks already converted to %s, not raw "
              "counts; say --unit=%s",
              name, gain, NearNominal(gain, 1.0) ? "m/s^2" : "g",
              NearNominal(gain, 1.0) ? "m/s^2" : "g"));
        }
        break;
      case TriadOutputUnit::kMps2:
      case TriadOutputUnit::kG: {
        const double nominal = unit == TriadOutputUnit::kMps2 ? 1.0 : kStandardGravity;
        if (!NearNominal(gain, nominal)) {
          return Status::Error(StringPrintf(
              "gain_%c = %.6g (m/s^2) per unit of output: a log in %s would give about %g; the "
              "log is in another unit (raw counts? say --unit=count%s)",
              name, gain, TriadOutputUnitName(unit), nominal,
              unit == TriadOutputUnit::kMps2 ? ", or --unit=g" : ", or --unit=m/s^2"));
        }
        break;
      }
    }
  }
  return Status::Ok();
}

}  // namespace accelcal
