#ifndef ACCELCAL_SIMULATION_EMBEDDED_SCENARIOS_H_
#define ACCELCAL_SIMULATION_EMBEDDED_SCENARIOS_H_

// data/scenarios/tp2-2018.json compiled into the library, so that the binaries' embedded
// default does not depend on the working directory.

#include "common/status.h"
#include "simulation/scenario.h"

namespace accelcal {

const char* DefaultScenarioJson();
Status LoadDefaultScenario(Scenario* scenario);

// The scenario in `path` (the embedded one when `path` is empty) with `assignments`
// (name=value,..., as ApplyScenarioOverrides) applied: what every --scenario/--set means.
Status LoadScenarioOrDefault(const std::string& path, const std::string& assignments,
                             Scenario* scenario);

}  // namespace accelcal

#endif  // ACCELCAL_SIMULATION_EMBEDDED_SCENARIOS_H_
