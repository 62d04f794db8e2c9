#ifndef ACCELCAL_IO_RUN_CONDITIONS_H_
#define ACCELCAL_IO_RUN_CONDITIONS_H_

// Initial conditions and stated noise variances of the run, from either layout:
// the course's datos.txt (io/datos_txt.h) or the CSV layout's scenario.json:
//
//   {"initial_position": [0, 0],        (m)
//    "initial_velocity": [1, 3],        (m/s)
//    "noise_variance":   [0.25, 0.64],  ((m/s^2)^2, stated sigma_x^2 and sigma_y^2)
//    "gravity": 9.8}                    (m/s^2, optional)

#include <string>

#include "common/measurements.h"
#include "common/status.h"

namespace accelcal {

// Reads `path` (a regular file of at most kMaxConditionsFileBytes, io/input_file.h) by its
// extension, in any case (.json: scenario.json; anything else: datos.txt).
Status LoadRunConditions(const std::string& path, RunConditions* conditions);

// A key given twice is refused (ParseJsonStrict, io/json_file.h), as is any key but the four.
Status ParseScenarioJson(const std::string& text, RunConditions* conditions);

// What any statement of the conditions must meet, whichever file it came from: finite
// positions within 1e9 m, velocities within 1e5 m/s, noise variances in [1e-12, 1e4]
// (m/s^2)^2 (a variance of 1e300 or 1e-320 passes "positive" but turns every covariance
// into overflow or NaN), gravity in [1, 100] m/s^2. LoadRunConditions applies it.
Status CheckRunConditions(const RunConditions& conditions);

// Serialises `conditions` as the scenario.json above (used to write the CSV layout).
std::string ScenarioJson(const RunConditions& conditions);

}  // namespace accelcal

#endif  // ACCELCAL_IO_RUN_CONDITIONS_H_
