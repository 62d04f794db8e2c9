#ifndef ACCELCAL_REPORTING_TRIAD_DISCOVERY_REPORT_H_
#define ACCELCAL_REPORTING_TRIAD_DISCOVERY_REPORT_H_

// What discovery on a triad found (estimation/triad/triad_discovery.h), as a table a person reads
// and as the JSON object `discovery` of calibrate_imu's ml mode (docs/json.md).

#include <nlohmann/json.hpp>
#include <string>

#include "estimation/triad/triad_discovery.h"

namespace accelcal {

// The fit of the calibration (the parameters' sigmas) described, never judged: chi2, dof, p,
// chi2/dof, the noise model that weighted the pose means (allan_noise: the Allan variance of
// their samples, else white), that the sigmas are not scaled, and what the one verdict,
// discovery's, implies for them (conservative when the chi-square's lower tail is noted;
// understated by about sqrt(chi2/dof) when the verdict finds excess scatter; discovery's
// noise model when it differs from the fit's). It cannot contradict the verdict: it states
// none.
// The factor by which the reported fit's sigmas understate the uncertainty when the verdict finds
// the pose means scatter more than the noise model allows (unexplained, its chi2 check flagged):
// sqrt(chi2/dof) of the reported fit, were the excess scatter white; 1 otherwise.
double SigmaUnderstatement(const TriadMlResult& ml, const TriadDiscoveryResult& discovery);

std::string FitDescription(const TriadMlResult& ml, bool allan_noise,
                           const TriadDiscoveryResult& discovery);

// The one verdict of a run, "Verdict (code): sentence", as the table, the HTML report and the
// calibration file give it.
std::string VerdictLine(const TriadDiscoveryResult& discovery);

std::string TriadDiscoveryTable(const TriadDiscoveryResult& result,
                                const TriadDiscoveryOptions& options);
nlohmann::json TriadDiscoveryJson(const TriadDiscoveryResult& result,
                                  const TriadDiscoveryOptions& options);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_TRIAD_DISCOVERY_REPORT_H_
