#ifndef ACCELCAL_REPORTING_GYROSCOPE_REPORT_H_
#define ACCELCAL_REPORTING_GYROSCOPE_REPORT_H_

// calibrate_imu --mode=ml's gyroscope part (estimation/gyroscope/gyroscope_ml_calibration.h):
// every unknown +- sigma beside imu_tk's result on the same session and the datasheet's on imu_tk's
// Xsens pair, the inverse gains, the fit statistic, the turns' residual angles, and where the
// Earth's rate stands against the noise. The table's block and the JSON's "gyroscope_ml" object.

#include <nlohmann/json.hpp>
#include <string>

namespace accelcal {

struct CalibrateImuReport;
struct GyroscopeDiscoveryResult;

std::string GyroscopeMlTable(const CalibrateImuReport& report);
nlohmann::json GyroscopeMlJson(const CalibrateImuReport& report);

// Discovery on the gyroscope (estimation/gyroscope/gyroscope_discovery.h): its steps and the
// gyroscope's verdict line, and the same as JSON.
std::string GyroscopeDiscoveryTable(const GyroscopeDiscoveryResult& discovery, double alpha);
nlohmann::json GyroscopeDiscoveryJson(const GyroscopeDiscoveryResult& discovery, double alpha);

// The turns' rotation about each body axis, and the unknowns the session determines too poorly
// to vouch for (estimation/gyroscope/gyroscope_determination.h), as the accelerometer's
// PoorlyDeterminedTable prints its own: the table's lines (also the HTML report's).
std::string GyroscopePoorlyDeterminedTable(const CalibrateImuReport& report);

// One sentence: where the Earth's rate (7.29e-5 rad/s) is below the noise and where it is not.
std::string EarthRateSentence(const CalibrateImuReport& report);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_GYROSCOPE_REPORT_H_
