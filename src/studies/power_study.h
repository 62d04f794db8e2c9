#ifndef ACCELCAL_STUDIES_POWER_STUDY_H_
#define ACCELCAL_STUDIES_POWER_STUDY_H_

// How often does discovery name an effect of a given size? For each effect of the
// catalogue and each size in units of that effect's own sigma (measured by a joint fit on
// the scenario), simulate K datasets with the effect hidden and count how often
// discovery names it (exactly that effect, alone or among others).

#include <vector>

#include "common/progress.h"
#include "models/effects.h"
#include "simulation/scenario.h"

namespace accelcal {

struct PowerOptions {
  std::vector<double> sizes_sigma = {2.0, 3.0, 4.0, 6.0};
  int trials = 40;
  uint64_t seed = 1;
  double alpha = 0.01;
  int threads = 0;
  ProgressFn progress;  // the trials of every cell together, PowerStudyTrials(options) of them
};

struct PowerRow {
  Parameter effect;
  double sigma = 0.0;                 // the effect's sigma on this scenario, in its unit
  std::vector<double> detection;      // per size: fraction of trials that named the effect
  std::vector<double> other_effects;  // per size: fraction that named some other effect too
};

// Every effect of the catalogue outside the baseline, times every size, times options.trials.
int64_t PowerStudyTrials(const PowerOptions& options);

// Run bias shifts are studied with the true endpoint among decoys 400 m away (see
// discovery_test: with the course's landmarks a large shift lands on another landmark).
std::vector<PowerRow> RunPowerStudy(const Scenario& scenario, const PowerOptions& options);

}  // namespace accelcal

#endif  // ACCELCAL_STUDIES_POWER_STUDY_H_
