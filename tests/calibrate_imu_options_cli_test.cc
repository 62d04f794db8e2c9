// calibrate_imu's numeric options are checked by one validation (reporting/calibrate_imu_options.h)
// that the Python module's accelcal.calibrate calls (issue 45): the binary refuses exactly the
// values outside the shared ranges, in the shared words, and the shared validation refuses the
// values of the probe (NaN, negative, zero, infinite).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "common/format.h"
#include "reporting/calibrate_imu_options.h"
#include "test_support.h"

namespace accelcal {
namespace {

using testing::RunBinaryArgs;

// What calibrate_imu prints for `--name=text` (with a log that does not exist, so that a value
// the flags accept ends in another refusal than the range's).
std::string BinaryRefusal(const std::string& name, const std::string& text) {
  const auto result = RunBinaryArgs(
      "calibrate_imu", {"--log=/nonexistent/accelcal.csv", "--mode=ml", "--" + name + "=" + text});
  EXPECT_EQ(result.exit_status, 2) << result.stderr_text;
  return result.stderr_text;
}

// A value just outside `range` at its low (or high) end, as text both sides read the same.
std::string JustOutside(const OptionRange& range, bool low) {
  const double end = low ? range.low : range.high;
  if (std::string(range.type) == "int32")
    return std::to_string(static_cast<int>(end) + (low ? -1 : 1));
  if (range.open) return RoundTripDouble(end);
  return RoundTripDouble(end + (low ? -1.0 : 1.0) * 1e-6 * std::max(1.0, std::fabs(end)));
}

TEST(CalibrateImuOptions, TheBinaryRefusesExactlyTheSharedRangesInTheSharedWords) {
  for (const OptionRange& range : CalibrateImuOptionRanges()) {
    for (const bool low : {true, false}) {
      const std::string text = JustOutside(range, low);
      const double value = std::strtod(text.c_str(), nullptr);
      const Status shared = CheckCalibrateImuOption(range.name, value, text);
      ASSERT_FALSE(shared.ok()) << range.name << "=" << text;
      EXPECT_EQ(BinaryRefusal(range.name, text),
                "calibrate_imu: error: " + shared.message() + "; see calibrate_imu --help\n");
    }
    // The ends of a closed range are in it: the binary goes on (to the missing log, or to a rule
    // of its own: --initial_gyro_gain=0 given is not a gain).
    if (!range.open) {
      const std::string text = std::string(range.type) == "int32"
                                   ? std::to_string(static_cast<int>(range.low))
                                   : RoundTripDouble(range.low);
      EXPECT_TRUE(CheckCalibrateImuOption(range.name, range.low, text).ok()) << range.name;
      EXPECT_EQ(BinaryRefusal(range.name, text).find("is not a valid"), std::string::npos)
          << range.name;
    }
  }
}

TEST(CalibrateImuOptions, RefusesTheValuesTheProbeGaveThePythonModule) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const auto refused = [](CalibrateImuOptionValues values) {
    return !ValidateCalibrateImuOptions(values).ok();
  };
  CalibrateImuOptionValues values;
  EXPECT_TRUE(ValidateCalibrateImuOptions(values).ok());
  values.threshold_factor = nan;
  EXPECT_TRUE(refused(values));
  values = {};
  values.threshold_factor = -3;
  EXPECT_TRUE(refused(values));
  values = {};
  values.interval_samples = 0;
  EXPECT_TRUE(refused(values));
  values.interval_samples = -5;
  EXPECT_TRUE(refused(values));
  values = {};
  values.min_intervals = -1;
  EXPECT_TRUE(refused(values));
  values = {};
  values.init_rest_s = -5;
  EXPECT_TRUE(refused(values));
  values.init_rest_s = nan;
  EXPECT_TRUE(refused(values));
  values = {};
  values.min_interval_s = inf;
  EXPECT_TRUE(refused(values));
  values = {};
  values.window = 12;
  EXPECT_EQ(ValidateCalibrateImuOptions(values).message(),
            "--window=12 is even; the window is centred on its sample, give an odd number");
  values = {};
  values.threshold_factor = nan;
  EXPECT_EQ(ValidateCalibrateImuOptions(values).message(),
            "--threshold_factor='nan' is not a valid double in [1, 1000000]");
}

}  // namespace
}  // namespace accelcal
