#ifndef ACCELCAL_SIMULATION_MONTE_CARLO_H_
#define ACCELCAL_SIMULATION_MONTE_CARLO_H_

// Runs K independent trials on all cores. Each trial is a function of its index alone
// (it seeds its simulation from (seed, trial)) and writes only its own result slot, so
// the results do not depend on the number of threads or on scheduling. Nothing is
// printed: each finished trial advances `progress`, which the caller shows or not.

#include <functional>

#include "common/progress.h"

namespace accelcal {

struct MonteCarloOptions {
  int trials = 1000;
  int threads = 0;                      // 0: std::thread::hardware_concurrency()
  ProgressCounter* progress = nullptr;  // advanced once per finished trial; may be shared
};

struct MonteCarloTiming {
  double seconds = 0.0;
  double trials_per_second = 0.0;
  int threads = 1;
};

// Calls trial(i) once for every i in [0, options.trials).
MonteCarloTiming RunTrials(const MonteCarloOptions& options,
                           const std::function<void(int trial)>& trial);

}  // namespace accelcal

#endif  // ACCELCAL_SIMULATION_MONTE_CARLO_H_
