#ifndef ACCELCAL_SIMULATION_EMBEDDED_SCENARIOS_H_
#define ACCELCAL_SIMULATION_EMBEDDED_SCENARIOS_H_

// data/scenarios/tp2-2018.json compiled into the library, so that the binaries' embedded
// default does not depend on the working directory. Read by LoadDefaultScenario and
// LoadScenarioOrDefault (io/scenario_json.h).

namespace accelcal {

const char* DefaultScenarioJson();

}  // namespace accelcal

#endif  // ACCELCAL_SIMULATION_EMBEDDED_SCENARIOS_H_
