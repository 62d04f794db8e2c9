// libFuzzer target: the calibration file reader (io/calibration_file.h, what apply and
// trajectory --calibration read) on arbitrary bytes. It must return a Status for every input,
// nested or large as it may be (issue 35: a file nested thousands of levels deep crashed apply).
// A crash, a sanitizer report, or a file it accepts that breaks what its readers rely on is a
// finding: parameters and covariance of the geometry's size and finite, a triad's or a
// gyroscope's block convertible, and the file written back from the record read again to the
// same parameters (what the reader accepts, the writer can write).

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "io/calibration_file.h"
#include "io/json_file.h"

namespace {

void Check(const accelcal::CalibrationRecord& record) {
  const size_t n = record.parameter_order.size();
  if (n == 0 || static_cast<size_t>(record.values.size()) != n) std::abort();
  if (record.covariance.rows() != static_cast<int>(n) ||
      record.covariance.cols() != static_cast<int>(n))
    std::abort();
  if (!record.values.allFinite() || !record.covariance.allFinite()) std::abort();
  if (record.geometry == "triad") {
    accelcal::TriadParameters parameters;
    Eigen::MatrixXd covariance;
    accelcal::TriadOutputUnit unit;
    if (!accelcal::TriadCalibration(record, "fuzz", &parameters, &covariance, &unit).ok())
      std::abort();
  } else {
    Eigen::Vector4d parameters;
    Eigen::Matrix4d covariance;
    if (!accelcal::TwoAxisBaseline(record, "fuzz", &parameters, &covariance).ok()) std::abort();
  }
  if (record.has_gyroscope) {
    accelcal::GyroscopeParameters parameters;
    accelcal::GyroscopeOffset offset;
    Eigen::MatrixXd covariance;
    accelcal::GyroscopeOutputUnit unit;
    if (!accelcal::GyroscopeCalibration(record.gyroscope, &parameters, &offset, &covariance, &unit)
             .ok())
      std::abort();
  }
  // Written back and read again: the same parameters.
  std::string text;
  if (!accelcal::JsonText(accelcal::CalibrationJson(record), &text).ok()) std::abort();
  accelcal::CalibrationRecord again;
  if (!accelcal::ParseCalibration(text, "fuzz (written back)", &again).ok()) std::abort();
  if (again.parameter_order != record.parameter_order || again.values != record.values ||
      again.has_gyroscope != record.has_gyroscope)
    std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  accelcal::CalibrationRecord record;
  if (accelcal::ParseCalibration(text, "fuzz", &record).ok()) Check(record);
  return 0;
}
