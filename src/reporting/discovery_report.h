#ifndef ACCELCAL_REPORTING_DISCOVERY_REPORT_H_
#define ACCELCAL_REPORTING_DISCOVERY_REPORT_H_

// Discovery as one screen a person reads (the verdict first), JSON a program reads, and
// two CSV files for tools/plot_discovery.py: the baseline's binned residual with each named
// effect's signature, and the final model's residual per sample (what remains, against
// theta and against time).
//
// Figures that are undefined (a kurtosis of too few samples, a z-score with no spread) are
// printed as "n/a" and written to the JSON as null; nothing prints or writes NaN.

#include <nlohmann/json.hpp>
#include <string>

#include "estimation/tilt_table/discovery.h"

namespace accelcal {

std::string DiscoveryText(const DiscoveryResult& result, double alpha);
nlohmann::json DiscoveryJson(const DiscoveryResult& result, double alpha);
std::string DiscoveryBinsCsv(const DiscoveryResult& result);

// sample,theta_rad,residual_x,residual_y,outlier_x,outlier_y: the final model's tilt-test
// residual (m/s^2, measured minus predicted) per sample, and 1 where the noise model set the
// sample aside. A test longer than `max_rows` is decimated evenly to `max_rows` samples
// (the first and the last always kept), plus the samples set aside (up to max_rows / 5 of
// them). An empty cell is a residual that is not finite. `test` is the one discovery ran on.
std::string DiscoveryResidualsCsv(const DiscoveryResult& result, const CalibrationTest& test,
                                  int max_rows = 5000);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_DISCOVERY_REPORT_H_
