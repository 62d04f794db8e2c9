#ifndef ACCELCAL_REPORTING_TRIAD_DISCOVERY_REPORT_H_
#define ACCELCAL_REPORTING_TRIAD_DISCOVERY_REPORT_H_

// What discovery on a triad found (estimation/triad_discovery.h), as a table a person reads
// and as the JSON object `discovery` of calibrate_imu's ml mode (docs/json.md).

#include <nlohmann/json.hpp>
#include <string>

#include "estimation/triad_discovery.h"

namespace accelcal {

std::string TriadDiscoveryTable(const TriadDiscoveryResult& result,
                                const TriadDiscoveryOptions& options);
nlohmann::json TriadDiscoveryJson(const TriadDiscoveryResult& result,
                                  const TriadDiscoveryOptions& options);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_TRIAD_DISCOVERY_REPORT_H_
