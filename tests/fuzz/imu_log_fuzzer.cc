// libFuzzer target: the IMU log reader (io/imu_log.h) on arbitrary bytes, with the layout told
// from the text as calibrate_imu does, and with the options a user may add (--rate_hz,
// --columns, --time_unit). It must return a Status for every input; a crash, a sanitizer
// report, or a log whose columns disagree in length or hold a value that is not finite is a
// finding.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "io/imu_log.h"

namespace {

void Check(const accelcal::TriadLog& log) {
  const size_t n = log.timestamp_s.size();
  if (log.output.size() != n && !log.output.empty()) std::abort();
  if (log.gyroscope.size() != n && !log.gyroscope.empty()) std::abort();
  for (size_t j = 0; j < n; ++j) {
    if (!std::isfinite(log.timestamp_s[j])) std::abort();
    if (j > 0 && !(log.timestamp_s[j] > log.timestamp_s[j - 1])) std::abort();
    for (int k = 0; k < 3; ++k) {
      if (!log.output.empty() && !std::isfinite(log.output[j][k])) std::abort();
      if (!log.gyroscope.empty() && !std::isfinite(log.gyroscope[j][k])) std::abort();
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  accelcal::ImuLogReadOptions options[4];
  options[1].rate_hz = 100.0;
  options[2].columns = "t:1,ax:2,ay:3,az:4";
  options[3].time_unit = "ms";
  for (const accelcal::ImuLogReadOptions& option : options) {
    accelcal::TriadLog log;
    if (accelcal::ParseImuLog(text, option, &log, accelcal::ImuLogSpacing::kAny).ok()) Check(log);
  }
  return 0;
}
