#ifndef ACCELCAL_REPORTING_TRIAD_STUDY_REPORT_H_
#define ACCELCAL_REPORTING_TRIAD_STUDY_REPORT_H_

// What triad_study prints and writes: what was simulated (truth, poses, noise), the verdict,
// then per parameter the truth, the mean estimate, its bias in reported sigma, the Monte
// Carlo spread, the mean reported sigma, their ratio with its standard error and the
// coverage at 1, 2, 3 sigma; the fit statistic's mean and its p < 0.01 rate. For a pose set
// the calibration refuses: the refusal, the unidentifiable parameters and the poses to add.

#include <nlohmann/json.hpp>
#include <string>

#include "studies/triad_discovery_study.h"
#include "studies/triad_monte_carlo.h"

namespace accelcal {

struct TriadStudyReport {
  TriadMonteCarloOptions options;
  TriadMonteCarloResult result;
};

std::string TriadStudyText(const TriadStudyReport& report);

// {"problem": "triad_study", "options", "directions", "refused", "refusal", "unidentifiable",
// "suggested_directions", "parameters" (one object each), "fit_statistic", "verdict",
// "seconds", "threads"}.
nlohmann::json TriadStudyJson(const TriadStudyReport& report);

// triad_study --discovery_alpha: what was simulated, the verdicts, the level (or, with an effect
// hidden, the power) and the Allan terms the sessions' poses gave; the same numbers as JSON
// ({"problem": "triad_study", "study": "discovery", "options", "verdicts", ...}).
std::string TriadDiscoveryStudyText(const TriadDiscoveryStudyOptions& options,
                                    const TriadDiscoveryStudyResult& result);
nlohmann::json TriadDiscoveryStudyJson(const TriadDiscoveryStudyOptions& options,
                                       const TriadDiscoveryStudyResult& result);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_TRIAD_STUDY_REPORT_H_
