#include "reporting/calibrate_imu_options.h"

#include <cmath>

#include "common/format.h"
#include "io/csv_reader.h"

namespace accelcal {

bool OptionRange::Contains(double value) const {
  return open ? (value > low && value < high) : (value >= low && value <= high);
}

std::string OptionRange::Text() const {
  return StringPrintf(open ? "(%.10g, %.10g)" : "[%.10g, %.10g]", low, high);
}

const std::vector<OptionRange>& CalibrateImuOptionRanges() {
  // The values problems/calibrate_imu.cc declares beside its flags (ACCELCAL_FLAG_RANGE);
  // tests/calibrate_imu_options_cli_test.cc checks that the binary refuses exactly these.
  static const std::vector<OptionRange> ranges = {
      {"g", "double", 9.7, 9.9, false},
      {"init_rest_s", "double", 0.0, 1e6, true},
      {"window", "int32", 11, 100001, false},
      {"interval_samples", "int32", 2, 1000000, false},
      {"min_intervals", "int32", 3, 100000, false},
      {"threshold_factor", "double", 1.0, 1e6, false},
      {"min_interval_s", "double", 0.0, 1e6, false},
      {"sampling_rate_hz", "double", 0.0, 1e6, false},
      {"initial_gyro_gain", "double", 0.0, 100.0, false},
  };
  return ranges;
}

const OptionRange* FindCalibrateImuOptionRange(const std::string& name) {
  for (const OptionRange& range : CalibrateImuOptionRanges())
    if (name == range.name) return &range;
  return nullptr;
}

Status CheckCalibrateImuOption(const std::string& name, double value,
                               const std::string& value_text) {
  const OptionRange* range = FindCalibrateImuOptionRange(name);
  if (range == nullptr || range->Contains(value)) return Status::Ok();
  const std::string text = value_text.empty() ? RoundTripDouble(value) : value_text;
  return Status::Error("--" + name + "='" + text + "' is not a valid " + range->type + " in " +
                       range->Text());
}

Status ValidateCalibrateImuOptions(const CalibrateImuOptionValues& values) {
  const auto integer = [](int value) { return std::to_string(value); };
  ACCELCAL_RETURN_IF_ERROR(CheckCalibrateImuOption("g", values.g));
  ACCELCAL_RETURN_IF_ERROR(CheckCalibrateImuOption("init_rest_s", values.init_rest_s));
  if (values.window != 0) {
    ACCELCAL_RETURN_IF_ERROR(
        CheckCalibrateImuOption("window", values.window, integer(values.window)));
  }
  ACCELCAL_RETURN_IF_ERROR(CheckCalibrateImuOption("interval_samples", values.interval_samples,
                                                   integer(values.interval_samples)));
  ACCELCAL_RETURN_IF_ERROR(CheckCalibrateImuOption("min_intervals", values.min_intervals,
                                                   integer(values.min_intervals)));
  ACCELCAL_RETURN_IF_ERROR(CheckCalibrateImuOption("threshold_factor", values.threshold_factor));
  ACCELCAL_RETURN_IF_ERROR(CheckCalibrateImuOption("min_interval_s", values.min_interval_s));
  ACCELCAL_RETURN_IF_ERROR(CheckCalibrateImuOption("initial_gyro_gain", values.initial_gyro_gain));
  if (!(values.alpha > 0.0 && values.alpha < 0.5)) {
    return Status::Error(
        StringPrintf("--alpha=%g is not in (0, 0.5); give e.g. --alpha=0.01", values.alpha));
  }
  if (values.window % 2 == 0 && values.window != 0) {
    return Status::Error("--window=" + std::to_string(values.window) +
                         " is even; the window is centred on its sample, give an odd number");
  }
  double offset = 0.0;
  if (values.initial_offset != "auto" &&
      (!ParseFiniteNumber(values.initial_offset, &offset) || std::fabs(offset) > 1e9)) {
    return Status::Error("--initial_offset='" + values.initial_offset +
                         "' is neither auto nor a finite number within +-1e9 (the log's unit)");
  }
  return Status::Ok();
}

}  // namespace accelcal
