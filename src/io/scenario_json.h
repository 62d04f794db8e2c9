#ifndef ACCELCAL_IO_SCENARIO_JSON_H_
#define ACCELCAL_IO_SCENARIO_JSON_H_

// Scenario files (data/scenarios/*.json) and --set assignments, read into a Scenario
// (simulation/scenario.h):
//
// {
//   "name": "tp2-2018", "description": "...",
//   "gravity": 9.8,                              m/s^2
//   "noise_variance": [0.25, 0.64],              stated sigma_x^2, sigma_y^2, (m/s^2)^2
//   "initial_position": [0, 0],                  m
//   "initial_velocity": [1, 3],                  m/s
//   "tilt": {"schedule": "uniform", "samples": 20001, "from_rad": 0, "to_rad": 6.283185307179586}
//        or {"schedule": "static", "positions_rad": [0, 1.5708, 3.1416, 4.7124], "samples": 2000}
//        or {"schedule": "list", "angles_rad": [...]},
//   "run": {"dt": 0.01, "duration": 60,          s; samples t_j = j dt, j < duration/dt
//           "profile": {"segments": [{"duration": 20, "acceleration": [0.5, 0]}, ...],
//                       "smoothing": 1.0}        moving-average window, s (0: none)
//                   or {"csv": "profile.csv"}},  columns t,ax,ay (m/s^2), one row per sample
//   "landmarks": {"listed": [{"name": "A", "position": [353.6, 73.2]}, ...]}
//             or {"decoys": {"count": 3, "min_distance": 100}},  the true endpoint + decoys
//   "truth": {"bias_x": 0.07667, "angle_offset": 0.004, ...},   any name of models/effects.h
//   "disturbances": {                            truths outside the catalogue, each optional
//                                                (simulation/disturbances.h states them)
//     "noise_ar1": [0.5, 0],                     lag-1 correlation of each axis's noise
//     "noise_student_t_dof": 5,                  Student-t noise, nu in (2, 1000]
//     "outlier_fraction": 0.01,                  of the tilt test's samples, in [0, 0.2]
//     "outlier_sigma": 10,                       an outlier's size in noise sigmas
//     "theta_harmonic": {"order": 2, "amplitude": [0.01, 0], "phase": 0},   m/s^2, rad
//     "bias_step": {"at": 0.5, "size": [0.02, 0]},   from sample floor(at N), m/s^2
//     "scale_cubic": [1e-4, 0]}                  c_k f_k^3, 1/(m/s^2)^2
// }
//
// Every key is checked; an unknown one is an error (a typo must not silently simulate
// the wrong experiment). Omitted truths and disturbances are neutral (no effect).

#include <string>

#include "common/status.h"
#include "io/provenance.h"
#include "simulation/scenario.h"

namespace accelcal {

// `base_dir` resolves a relative profile CSV path.
Status ParseScenario(const std::string& json_text, const std::string& base_dir, Scenario* scenario);
Status LoadScenario(const std::string& path, Scenario* scenario);

// Applies "name=value,name=value": any parameter of models/effects.h, one of the
// settings gravity, noise_variance_x_stated, noise_variance_y_stated, tilt_samples,
// run_duration, run_dt, or a disturbance (simulation/disturbances.h): noise_ar1_x,
// noise_ar1_y, noise_student_t_dof, outlier_fraction, outlier_sigma, theta_harmonic_order,
// theta_harmonic_x, theta_harmonic_y, theta_harmonic_phase, bias_step_at, bias_step_x,
// bias_step_y, scale_cubic_x, scale_cubic_y, bias_warmup_x, bias_warmup_y, bias_hysteresis_x,
// bias_hysteresis_y, position_offset_at, position_offset_x, position_offset_y, full_scale_x,
// full_scale_y.
Status ApplyScenarioOverrides(const std::string& assignments, Scenario* scenario);

// data/scenarios/tp2-2018.json, compiled into the library (simulation/embedded_scenarios.h),
// so that the binaries' embedded default does not depend on the working directory.
Status LoadDefaultScenario(Scenario* scenario);

// The scenario in `path` (the embedded one when `path` is empty) with `assignments`
// (name=value,..., as ApplyScenarioOverrides) applied: what every --scenario/--set means.
Status LoadScenarioOrDefault(const std::string& path, const std::string& assignments,
                             Scenario* scenario);

// The source of data simulated from `scenario` (read from `scenario_file`, hashed, or the
// embedded one when empty) with `seed`: what it hides beyond the baseline is every catalogue
// parameter away from its neutral value except bias and scale, and every disturbance away
// from its default.
Status DescribeSimulation(const Scenario& scenario, const std::string& scenario_file, uint64_t seed,
                          DataSource* source);

}  // namespace accelcal

#endif  // ACCELCAL_IO_SCENARIO_JSON_H_
