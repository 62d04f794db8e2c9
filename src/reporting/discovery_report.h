#ifndef ACCELCAL_REPORTING_DISCOVERY_REPORT_H_
#define ACCELCAL_REPORTING_DISCOVERY_REPORT_H_

// Discovery as one screen a person reads (the verdict first), JSON a program reads, and
// the binned residual with each named effect's signature as CSV for
// tools/plot_discovery.py.

#include <nlohmann/json.hpp>
#include <string>

#include "estimation/discovery.h"

namespace accelcal {

std::string DiscoveryText(const DiscoveryResult& result, double alpha);
nlohmann::json DiscoveryJson(const DiscoveryResult& result, double alpha);
std::string DiscoveryBinsCsv(const DiscoveryResult& result);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_DISCOVERY_REPORT_H_
