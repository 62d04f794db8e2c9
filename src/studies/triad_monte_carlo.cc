#include "studies/triad_monte_carlo.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "common/format.h"
#include "estimation/triad/triad_ml_calibration.h"
#include "simulation/monte_carlo.h"
#include "simulation/random.h"
#include "simulation/triad_simulator.h"
#include "studies/sigma_check.h"

namespace accelcal {
namespace {

// The random pose set's stream, apart from the trials' streams 0, 1, 2, ...
constexpr uint64_t kPoseStream = uint64_t{1} << 62;
constexpr int kClaimTrials = 1000;
constexpr double kRatioBand = 0.1;  // the issue's [0.9, 1.1]
constexpr double kBandSd = 3.0;     // coverages and the p < 0.01 rate: within 3 binomial sd

std::vector<std::array<double, 3>> PoseDirections(const TriadMonteCarloOptions& options,
                                                  int parameter_count) {
  RandomSource random(options.seed, kPoseStream);
  switch (options.pose_set) {
    case TriadPoseSet::kRandom:
      return RandomPoseDirections(options.poses, &random);
    case TriadPoseSet::kPlanar:
      return PlanarPoseDirections(options.poses, 0);
    case TriadPoseSet::kSix:
      return SixPoseDirections();
    case TriadPoseSet::kFew:
      return RandomPoseDirections(parameter_count - 1, &random);
  }
  return {};
}

struct Trial {
  bool ok = false;
  std::string failure;
  std::vector<double> estimate;
  std::vector<double> stddev;
  double chi2_per_dof = 0.0;
  double p_value = 1.0;
};

// The estimated parameters in output order: the 9 of the triad, then k2 when estimated.
void Flatten(const TriadMlResult& fit, Trial* trial) {
  trial->estimate.assign(fit.parameters.begin(), fit.parameters.end());
  trial->stddev.assign(fit.stddev.begin(), fit.stddev.end());
  for (const int c : fit.effects_estimated) {
    trial->estimate.push_back(fit.effects[c]);
    trial->stddev.push_back(fit.effects_stddev[c]);
  }
}

Status CheckOptions(const TriadMonteCarloOptions& options) {
  if (options.trials < 1) return Status::Error("the study needs at least 1 trial");
  if (options.samples_per_pose < 2) {
    return Status::Error("every pose needs at least 2 samples (its noise is estimated from them)");
  }
  if ((options.pose_set == TriadPoseSet::kRandom || options.pose_set == TriadPoseSet::kPlanar) &&
      options.poses < 1) {
    return Status::Error("the pose set needs at least 1 pose");
  }
  for (const double sigma : options.noise_stddev) {
    if (!(sigma > 0.0) || !std::isfinite(sigma))
      return Status::Error("every axis needs a positive, finite noise sd (counts)");
  }
  if (!(options.gravity_mps2 > 0.0) || !std::isfinite(options.gravity_mps2))
    return Status::Error("g must be positive and finite (m/s^2)");
  for (int k = 0; k < 3; ++k) {
    if (!(options.truth[kTriadGainX + k] > 0.0) || !std::isfinite(options.truth[kTriadGainX + k])) {
      return Status::Error(StringPrintf("the truth's %s must be positive and finite",
                                        TriadParameterInfos()[kTriadGainX + k].name));
    }
  }
  return Status::Ok();
}

// Within kBandSd binomial sd of `expected`.
bool WithinBinomialBand(double fraction, double expected, int n) {
  return accelcal::WithinBinomialBand(fraction, expected, n, kBandSd);
}

void Summarise(const TriadMonteCarloOptions& options, const std::vector<Trial>& trials,
               TriadMonteCarloResult* result) {
  std::vector<const Trial*> good;
  for (int i = 0; i < static_cast<int>(trials.size()); ++i) {
    if (trials[i].ok) {
      good.push_back(&trials[i]);
    } else if (result->trials_failed++ == 0) {
      result->first_failure = StringPrintf("trial %d: ", i) + trials[i].failure;
    }
  }
  result->trials_ok = static_cast<int>(good.size());
  if (good.empty()) {
    result->failures.push_back("every trial failed (" + result->first_failure + ")");
    return;
  }
  const double n = static_cast<double>(good.size());
  std::vector<double> truth(options.truth.begin(), options.truth.end());
  if (options.scale_nonlinearity) {
    truth.insert(truth.end(), options.truth_scale_nonlinearity.begin(),
                 options.truth_scale_nonlinearity.end());
  }
  for (int p = 0; p < result->parameter_count; ++p) {
    TriadParameterStudy row;
    const TriadParameterInfo& info = p < kTriadParameterCount
                                         ? TriadParameterInfos()[p]
                                         : TriadScaleNonlinearityInfos()[p - kTriadParameterCount];
    row.name = info.name;
    row.unit = info.unit;
    row.truth = truth[p];
    static_cast<SigmaCheck&>(row) = CheckSigma(
        static_cast<int>(good.size()), row.truth, [&](int i) { return good[i]->estimate[p]; },
        [&](int i) { return good[i]->stddev[p]; });
    result->parameters.push_back(row);
  }
  for (const Trial* trial : good) {
    result->chi2_per_dof_mean += trial->chi2_per_dof / n;
    result->p_below_001 += (trial->p_value < 0.01) / n;
  }
  result->chi2_per_dof_mean_stderr = std::sqrt(2.0 / result->degrees_of_freedom / n);
  result->p_below_001_stderr = std::sqrt(0.01 * 0.99 / n);

  const int count = result->trials_ok;
  for (const TriadParameterStudy& row : result->parameters) {
    // With fewer than ~500 trials the ratio's own sd exceeds 0.1 / 3, and a ratio outside
    // [0.9, 1.1] may be chance: the band widens to 3 of its sd.
    const double ratio_band = std::max(kRatioBand, kBandSd * row.ratio_stderr);
    if (!(std::abs(row.ratio - 1.0) <= ratio_band)) {
      result->failures.push_back(
          StringPrintf("%s: reported sigma / spread = %.3f, outside [%.3f, %.3f]", row.name.c_str(),
                       row.ratio, 1.0 - ratio_band, 1.0 + ratio_band));
    }
    // One line per parameter whose coverage is off at any level, with all three levels.
    bool coverage_off = false;
    std::string seen, expected, band;
    for (int level = 0; level < 3; ++level) {
      const double p = TriadMonteCarloResult::kExpectedCoverage[level];
      coverage_off = coverage_off || !WithinBinomialBand(row.coverage[level], p, count);
      const char* separator = level == 0 ? "" : ", ";
      seen += StringPrintf("%s%.1f", separator, 100.0 * row.coverage[level]);
      expected += StringPrintf("%s%.1f", separator, 100.0 * p);
      band += StringPrintf("%s%.1f", separator, 100.0 * kBandSd * std::sqrt(p * (1.0 - p) / count));
    }
    if (coverage_off) {
      result->failures.push_back(StringPrintf(
          "%s: truth within 1, 2, 3 sigma in %s%% of trials, expected %s%% +- %s (3 sd)",
          row.name.c_str(), seen.c_str(), expected.c_str(), band.c_str()));
    }
  }
  if (!WithinBinomialBand(result->p_below_001, 0.01, count)) {
    result->failures.push_back(
        StringPrintf("fit statistic: p < 0.01 in %.1f%% of trials, expected 1.0%% +- %.1f%% (3 sd)",
                     100.0 * result->p_below_001, 100.0 * kBandSd * result->p_below_001_stderr));
  }
  if (result->trials_failed > 0) {
    result->failures.push_back(StringPrintf("%d of %zu trials failed (first: %s)",
                                            result->trials_failed, trials.size(),
                                            result->first_failure.c_str()));
  }
}

}  // namespace

const std::vector<std::string>& TriadPoseSetNames() {
  static const std::vector<std::string> names = {"random", "planar", "six", "few"};
  return names;
}

const char* TriadPoseSetName(TriadPoseSet pose_set) {
  return TriadPoseSetNames()[static_cast<int>(pose_set)].c_str();
}

Status ParseTriadPoseSet(const std::string& name, TriadPoseSet* pose_set) {
  const std::vector<std::string>& names = TriadPoseSetNames();
  const auto found = std::find(names.begin(), names.end(), name);
  if (found == names.end()) {
    return Status::Error("unknown pose set '" + name.substr(0, 40) +
                         "' (known: random, planar, six, few)");
  }
  *pose_set = static_cast<TriadPoseSet>(found - names.begin());
  return Status::Ok();
}

TriadParameters XsensLikeTriad() {
  TriadParameters truth = TriadParametersWithOffset(33124.0, 33275.0, 32364.0);
  const double angles_rad[3] = {0.0035, -0.009, 0.021};  // yz, zy, zx
  const double counts_per_mps2[3] = {414.5, 412.0, 414.6};
  for (int k = 0; k < 3; ++k) {
    truth[kTriadMisalignmentYz + k] = angles_rad[k];
    truth[kTriadGainX + k] = 1.0 / counts_per_mps2[k];
  }
  return truth;
}

TriadScaleNonlinearity ExampleScaleNonlinearity() { return {2e-4, -1e-4, 3e-4}; }

TriadParameters TriadStudyInitialGuess(const TriadParameters& truth) {
  double gain = 0.0;
  double offset = 0.0;
  for (int k = 0; k < 3; ++k) {
    gain += truth[kTriadGainX + k] / 3.0;
    offset += truth[kTriadOffsetX + k] / 3.0;
  }
  TriadParameters initial = TriadParametersWithOffset(offset, offset, offset);
  for (int k = 0; k < 3; ++k) initial[kTriadGainX + k] = gain;
  return initial;
}

Status RunTriadMonteCarlo(const TriadMonteCarloOptions& options, TriadMonteCarloResult* result) {
  *result = TriadMonteCarloResult();
  ACCELCAL_RETURN_IF_ERROR(CheckOptions(options));
  const auto start = std::chrono::steady_clock::now();
  TriadMlOptions ml;
  ml.gravity_mps2 = options.gravity_mps2;
  ml.initial = TriadStudyInitialGuess(options.truth);
  ml.scale_nonlinearity = options.scale_nonlinearity;
  result->parameter_count = TriadEstimatedParameterCount(ml);
  result->directions = PoseDirections(options, result->parameter_count);

  TriadSimulationOptions simulation;
  simulation.truth = options.truth;
  const int first_k2 = TriadEffectCoefficientIndex("scale_nonlinearity_x");
  for (int k = 0; k < kTriadScaleNonlinearityCount; ++k)
    simulation.effects[first_k2 + k] = options.truth_scale_nonlinearity[k];
  simulation.gravity_mps2 = options.gravity_mps2;
  simulation.samples_per_pose = options.samples_per_pose;
  simulation.noise_stddev = options.noise_stddev;

  std::vector<Trial> trials(options.trials);
  // What the poses cannot determine does not depend on the noise: the first session decides.
  auto run_trial = [&](int index) {
    RandomSource random(options.seed, static_cast<uint64_t>(index));
    TriadMlResult fit;
    const Status status =
        CalibrateTriadMl(SimulateTriadPoses(simulation, result->directions, &random), ml, &fit);
    Trial& trial = trials[index];
    if (!status.ok()) {
      trial.failure = status.message();
      if (index == 0) {
        result->unidentifiable = fit.unidentifiable;
        result->suggested_directions = fit.suggested_directions;
      }
      return;
    }
    trial.ok = true;
    Flatten(fit, &trial);
    trial.chi2_per_dof = fit.chi2_per_dof;
    trial.p_value = fit.p_value;
    if (index == 0) result->degrees_of_freedom = fit.degrees_of_freedom;
  };
  ProgressCounter progress(options.progress, options.trials);
  run_trial(0);
  progress.Advance();
  if (!trials[0].ok) {
    result->refused = true;
    result->refusal = trials[0].failure;
    return Status::Ok();
  }
  MonteCarloOptions monte_carlo;
  monte_carlo.trials = options.trials - 1;
  monte_carlo.threads = options.threads;
  monte_carlo.progress = &progress;
  const MonteCarloTiming timing = RunTrials(monte_carlo, [&](int index) { run_trial(index + 1); });
  result->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result->threads = timing.threads;

  Summarise(options, trials, result);
  result->claim_possible = result->trials_ok >= kClaimTrials;
  result->passed = result->failures.empty();
  return Status::Ok();
}

}  // namespace accelcal
