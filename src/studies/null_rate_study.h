#ifndef ACCELCAL_STUDIES_NULL_RATE_STUDY_H_
#define ACCELCAL_STUDIES_NULL_RATE_STUDY_H_

// Is discovery's false-discovery rate at most alpha? On null data (the baseline is the
// truth: Table 1's bias and scale, every other effect and disturbance neutral, white
// Gaussian noise of exactly the stated variance) any verdict but "explained" is a false
// discovery, and DiscoveryOptions::alpha promises it happens with probability <= alpha.
//
// For each tilt-test design and each noise level (stated and true variance both scaled by
// a factor, so the statement stays right) the study simulates `datasets` null datasets
// and runs discovery on each at every alpha (the same datasets for all alphas). A cell
// counts the false discoveries and what they claimed; pooled over the cells of one alpha,
// the rate p of n datasets is compared with
//
//   bound = alpha + 2 sqrt(alpha (1 - alpha) / n),
//
// two binomial sd above alpha when the rate is exactly alpha.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "simulation/scenario.h"

namespace accelcal {

// The tilt-test designs, each the course scenario with another schedule:
//   course           the scenario's own (tp2-2018: 20001 samples uniform over [0, 2 pi])
//   n2000            2000 samples uniform over [0, 2 pi)
//   eight_positions  2000 samples at 8 static positions 2 pi k / 8, k = 0..7
//   half_circle      2000 samples uniform over [0, pi], both ends included
const std::vector<std::string>& NullRateDesignNames();

// One line saying what the design is, for the reports ("" for an unknown name).
std::string NullRateDesignDescription(const std::string& name);

// The null scenario of design `name` for `noise_factor`: `course` with its run, landmarks,
// g, bias and scale kept, every other parameter at its neutral value, no disturbance, the
// design's tilt schedule and the stated variances times `noise_factor`. An unknown name or
// a factor that is not finite and positive is an error.
Status MakeNullScenario(const Scenario& course, const std::string& name, double noise_factor,
                        Scenario* scenario);

struct NullRateOptions {
  std::vector<std::string> designs = {"course", "n2000", "eight_positions", "half_circle"};
  std::vector<double> noise_factors = {0.25, 1.0, 4.0};
  std::vector<double> alphas = {0.01, 0.05};
  // Per (design, noise factor): 12 cells of 170 give 2040 datasets per alpha, enough to
  // tell a rate of 1% from 1.5% (the bound at alpha = 0.01 is 1.44%).
  int datasets = 170;
  uint64_t seed = 1;
  int threads = 2;      // 0: all cores; the counts do not depend on it
  ProgressFn progress;  // per finished dataset, of designs x noise factors x datasets
};

// Discovery on the datasets of one (design, noise factor) at one alpha.
struct NullRateCell {
  std::string design;
  double noise_factor = 1.0;
  double alpha = 0.01;
  int datasets = 0;       // simulated
  int errors = 0;         // Discover returned an error (no verdict); not in `verdicts`
  int verdicts = 0;       // datasets - errors: the rate's denominator
  int not_explained = 0;  // verdict other than "explained": the false discoveries
  double rate = 0.0;      // not_explained / verdicts
  // What the false discoveries claimed (a dataset may count in several):
  int with_effects = 0;         // an effect of the catalogue (noise_variance_k included)
  int with_noise_findings = 0;  // correlation, outliers or heavy tails
  int with_flagged_checks = 0;  // a residual check flagged: structure outside the catalogue
  int cannot_tell_apart = 0;    // verdict kCannotTellApart
  std::map<std::string, int> verdict_counts;  // by VerdictCode
  // How many datasets named each effect, raised each noise finding, flagged each check.
  std::map<std::string, int> effects_named;
  std::map<std::string, int> noise_findings_named;
  std::map<std::string, int> checks_flagged;
};

// Every cell of one alpha together.
struct PooledNullRate {
  double alpha = 0.01;
  int verdicts = 0;
  int errors = 0;
  int not_explained = 0;
  double rate = 0.0;
  double rate_stddev = 0.0;   // sqrt(p (1 - p) / n): the measured rate's Monte Carlo sd
  double alpha_stddev = 0.0;  // sqrt(alpha (1 - alpha) / n): its sd were the rate alpha
  double bound = 0.0;         // alpha + 2 alpha_stddev
  bool within = true;         // rate <= bound
};

struct NullRateResult {
  std::vector<NullRateCell> cells;     // by design, then noise factor, then alpha
  std::vector<PooledNullRate> pooled;  // one per alpha, in the options' order
  double seconds = 0.0;
  int threads = 1;
};

// Dataset i of (design, noise factor) is simulated from the noise streams of (seed, a key
// of the design's name, the factor's value and i), so a cell's counts depend neither on the
// thread count nor on which other designs and factors run beside it.
Status RunNullRateStudy(const Scenario& course, const NullRateOptions& options,
                        NullRateResult* result);

}  // namespace accelcal

#endif  // ACCELCAL_STUDIES_NULL_RATE_STUDY_H_
