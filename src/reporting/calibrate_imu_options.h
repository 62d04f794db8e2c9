#ifndef ACCELCAL_REPORTING_CALIBRATE_IMU_OPTIONS_H_
#define ACCELCAL_REPORTING_CALIBRATE_IMU_OPTIONS_H_

// calibrate_imu's numeric options and their allowed ranges, stated once for every caller: the
// binary's flags and the Python module's keywords of accelcal.calibrate (docs/python.md), so
// that a value one refuses the other refuses too, in the same words:
//
//   --threshold_factor='nan' is not a valid double in [1, 1000000]
//
// A NaN is in no range, and an infinity only in one that has no end (none here).

#include <string>
#include <vector>

#include "common/status.h"

namespace accelcal {

struct OptionRange {
  const char* name;  // the flag's name without "--" (and the Python keyword)
  const char* type;  // "double" or "int32", as gflags names the flag's type
  double low = 0.0;
  double high = 0.0;
  bool open = false;  // open: low < value < high; closed: low <= value <= high

  bool Contains(double value) const;
  std::string Text() const;  // "[1, 1000000]" or "(0, 1000000)"
};

// The numeric options of calibrate_imu with a range, in the order of its flags.
const std::vector<OptionRange>& CalibrateImuOptionRanges();

// The range of option `name`, or nullptr.
const OptionRange* FindCalibrateImuOptionRange(const std::string& name);

// The refusal of `value` for option `name` when it is outside its range (OK otherwise, and for
// an option without a range). `value_text` is the value as given; empty: the shortest decimal
// that reads back as `value` (nan, inf for those).
Status CheckCalibrateImuOption(const std::string& name, double value,
                               const std::string& value_text = "");

// Every option calibrate_imu --mode=ml validates before reading the log, as its values.
struct CalibrateImuOptionValues {
  double g = 9.81;
  double alpha = 0.01;
  int window = 0;  // 0: not given (the detector's default)
  double init_rest_s = 50.0;
  int interval_samples = 100;
  int min_intervals = 12;
  double threshold_factor = 10.0;
  double min_interval_s = 1.0;
  double initial_gyro_gain = 0.0;
  std::string initial_offset = "auto";
};

// The ranges above, then calibrate_imu's own rules in its words: alpha in (0, 0.5), an odd
// window, initial_offset auto or a finite number within +-1e9. The first refusal, or OK.
Status ValidateCalibrateImuOptions(const CalibrateImuOptionValues& values);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_CALIBRATE_IMU_OPTIONS_H_
