#include "studies/gyroscope_monte_carlo.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "common/format.h"
#include "simulation/monte_carlo.h"
#include "simulation/random.h"
#include "simulation/triad_simulator.h"
#include "studies/sigma_check.h"
#include "studies/triad_monte_carlo.h"

namespace accelcal {
namespace {

constexpr int kClaimTrials = 1000;
constexpr double kRatioBand = 0.1;  // the issue's [0.9, 1.1]
constexpr double kBandSd = 3.0;

bool WithinBinomialBand(double fraction, double expected, int n) {
  return accelcal::WithinBinomialBand(fraction, expected, n, kBandSd);
}

struct Trial {
  bool ok = false;
  std::string failure;
  int verdict = -1;  // with discovery
  int clipped_turns = 0;
  std::array<bool, kGyroscopeEffectCount> found{};
  std::vector<std::string> checks_flagged;  // discovery's what-remains checks that flagged
  std::vector<double> estimate;
  std::vector<double> stddev;
  double chi2_per_dof = 0.0;
  double p_value = 1.0;
};

// The truth of every unknown of the fit, in GyroscopeMlResult's order.
std::vector<double> Truths(const GyroscopeSessionDesign& design, const std::vector<int>& effects) {
  std::vector<double> truth(design.truth.begin(), design.truth.end());
  truth.insert(truth.end(), design.offset.begin(), design.offset.end());
  for (int c : effects) truth.push_back(design.effects[c]);
  return truth;
}

}  // namespace

Status ParseGyroscopeTurnSet(const std::string& name, GyroscopeTurnSet* turn_set) {
  if (name == "random") {
    *turn_set = GyroscopeTurnSet::kRandom;
  } else if (name == "planar") {
    *turn_set = GyroscopeTurnSet::kPlanar;
  } else {
    return Status::Error("unknown turn set '" + name.substr(0, 40) + "' (known: random, planar)");
  }
  return Status::Ok();
}

const char* GyroscopeTurnSetName(GyroscopeTurnSet turn_set) {
  return turn_set == GyroscopeTurnSet::kRandom ? "random" : "planar";
}

GyroscopeParameters XsensLikeGyroscope() {
  GyroscopeParameters truth = GyroscopeParametersWithGain(1.0 / 4778.0, 1.0 / 4764.0, 1.0 / 4774.0);
  // imu_tk's printed matrix on the Xsens log: T(0,1) = -yz, T(0,2) = zy, T(1,2) = -zx,
  // T(1,0) = xz, T(2,0) = -xy, T(2,1) = yx.
  truth[kGyroscopeMisalignmentYz] = -0.00593634;
  truth[kGyroscopeMisalignmentZy] = 0.00111101;
  truth[kGyroscopeMisalignmentZx] = 0.0535569;
  truth[kGyroscopeMisalignmentXz] = 0.00808812;
  truth[kGyroscopeMisalignmentXy] = -0.0253067;
  truth[kGyroscopeMisalignmentYx] = -0.0025513;
  return truth;
}

GyroscopeOffset XsensLikeGyroscopeOffset() { return {32777.1, 32459.8, 32511.8}; }

std::vector<TriadHold> GyroscopeDesignHolds(const GyroscopeSessionDesign& design, uint64_t seed) {
  RandomSource random(seed, 0x67797265);  // its own stream: the noise uses (seed, trial)
  std::vector<TriadHold> holds;
  if (design.turn_set == GyroscopeTurnSet::kPlanar) {
    for (int p = 0; p < design.poses; ++p) {
      const double angle = 2.0 * M_PI * (0.37 * p + 0.05 * random.Uniform());
      holds.push_back({{0.0, std::cos(angle), std::sin(angle)}, design.hold_s});
    }
    return holds;
  }
  holds = RandomSeparatedHolds(design.poses, design.hold_s, 40.0, &random);
  for (TriadHold& hold : holds) hold.turn_yaw_deg = 90.0 * (2.0 * random.Uniform() - 1.0);
  return holds;
}

TriadLogSimulationOptions GyroscopeDesignSimulation(const GyroscopeSessionDesign& design) {
  TriadLogSimulationOptions simulation;
  simulation.truth = design.accelerometer_truth;
  simulation.gravity_mps2 = design.gravity_mps2;
  simulation.rate_hz = design.rate_hz;
  simulation.turn_s = design.turn_s;
  simulation.turn_abruptness = design.turn_abruptness;
  simulation.noise_stddev = design.accelerometer_noise;
  simulation.gyroscope.enabled = true;
  simulation.gyroscope.truth = design.truth;
  simulation.gyroscope.offset = design.offset;
  simulation.gyroscope.effects = design.effects;
  simulation.gyroscope.noise_stddev = design.gyroscope_noise;
  simulation.gyroscope.round_to_counts = design.gyroscope_in_counts;
  simulation.gyroscope.earth_rate = design.earth_rate;
  simulation.gyroscope.latitude_deg = design.latitude_deg;
  return simulation;
}

Status SimulateAndCalibrateGyroscope(const GyroscopeSessionDesign& design,
                                     const std::vector<TriadHold>& holds, uint64_t noise_seed,
                                     const std::vector<int>& estimated, GyroscopeSessionFit* fit) {
  const TriadLogSimulationOptions simulation = GyroscopeDesignSimulation(design);
  RandomSource random(noise_seed, 1);
  fit->session = SimulateTriadSession(simulation, holds, &random);
  fit->intervals.clear();
  for (const TriadHoldSamples& hold : fit->session.holds) {
    StaticInterval interval;
    interval.start = hold.start;
    interval.end = hold.end;
    DescribeInterval(fit->session.log, &interval);
    fit->intervals.push_back(interval);
  }
  fit->accelerometer_options = TriadMlOptions();
  fit->accelerometer_options.gravity_mps2 = design.gravity_mps2;
  fit->accelerometer_options.initial = TriadStudyInitialGuess(simulation.truth);
  fit->accelerometer_options.suggest_poses = false;
  ACCELCAL_RETURN_IF_ERROR(
      CalibrateTriadMl(PoseMeansOfIntervals(fit->session.log, fit->intervals, 0),
                       fit->accelerometer_options, &fit->accelerometer)
          .WithContext("the accelerometer"));
  GyroscopeMlOptions options;
  options.gravity_mps2 = design.gravity_mps2;
  double gain = 0.0;
  for (int k = 0; k < 3; ++k) gain += design.truth[kGyroscopeGainX + k] / 3.0;
  options.initial = GyroscopeParametersWithGain(gain, gain, gain);
  options.quantisation_step = design.gyroscope_in_counts ? 1.0 : 0.0;
  if (!design.gyroscope_in_counts) options.unit = GyroscopeOutputUnit::kRadPerS;
  options.earth_rate_as_noise = design.earth_rate_allowance || design.earth_rate;
  options.latitude_given = design.latitude_known;
  options.latitude_rad = design.latitude_deg * M_PI / 180.0;
  options.turn_sampling_alpha = design.turn_sampling_alpha;
  options.effects = estimated;
  fit->gyroscope_options = options;
  return CalibrateGyroscopeMl(fit->session.log, fit->intervals, fit->accelerometer_options,
                              fit->accelerometer, options, &fit->gyroscope);
}

Status RunGyroscopeMonteCarlo(const GyroscopeMonteCarloOptions& options,
                              GyroscopeMonteCarloResult* result) {
  *result = GyroscopeMonteCarloResult();
  if (options.trials < 1) return Status::Error("the study needs at least one trial");
  const auto start = std::chrono::steady_clock::now();
  const std::vector<TriadHold> holds = GyroscopeDesignHolds(options.design, options.seed);
  std::vector<Trial> trials(options.trials);
  std::vector<std::string> names, units;
  auto run_trial = [&](int index) {
    GyroscopeSessionFit fit;
    const Status status = SimulateAndCalibrateGyroscope(
        options.design, holds, options.seed * 1000003ULL + index, options.estimated, &fit);
    Trial& trial = trials[index];
    if (!status.ok()) {
      trial.failure = status.message();
      if (index == 0) {
        result->undetermined = fit.gyroscope.undetermined;
        result->turn_axes_to_add = fit.gyroscope.turn_axes_to_add;
      }
      return;
    }
    trial.ok = true;
    if (options.discovery_alpha > 0.0) {
      GyroscopeDiscoveryOptions discovery;
      discovery.alpha = options.discovery_alpha;
      discovery.fit = fit.gyroscope_options;
      discovery.fit.effects.clear();
      GyroscopeDiscoveryResult result;
      if (DiscoverGyroscope(fit.session.log, fit.intervals, fit.accelerometer_options,
                            fit.accelerometer, discovery, &result)
              .ok()) {
        trial.verdict = static_cast<int>(result.verdict_code);
        for (const GyroscopeFoundEffect& effect : result.effects) {
          for (int e = 0; e < kGyroscopeEffectCount; ++e)
            if (effect.effect == GyroscopeEffectInfos()[e].name) trial.found[e] = true;
        }
        for (const ResidualCheck& check : result.checks)
          if (check.flagged) trial.checks_flagged.push_back(check.name);
      }
    }
    const GyroscopeMlResult& g = fit.gyroscope;
    trial.clipped_turns = static_cast<int>(g.clipped_turns.size());
    trial.estimate.assign(g.parameters.begin(), g.parameters.end());
    trial.estimate.insert(trial.estimate.end(), g.offset.begin(), g.offset.end());
    for (int c : g.effects_estimated) trial.estimate.push_back(g.effects[c]);
    trial.stddev.assign(g.stddev.data(), g.stddev.data() + g.stddev.size());
    trial.chi2_per_dof = g.chi2_gyroscope / g.gyroscope_degrees_of_freedom;
    trial.p_value = g.gyroscope_p_value;
    if (index == 0) {
      names = g.names;
      units = g.units;
    }
  };
  ProgressCounter progress(options.progress, options.trials);
  run_trial(0);
  progress.Advance();
  result->trials = options.trials;
  if (!trials[0].ok) {
    result->refused = true;
    result->refusal = trials[0].failure;
    return Status::Ok();
  }
  MonteCarloOptions monte_carlo;
  monte_carlo.trials = options.trials - 1;
  monte_carlo.threads = options.threads;
  monte_carlo.progress = &progress;
  RunTrials(monte_carlo, [&](int index) { run_trial(index + 1); });
  result->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::vector<const Trial*> good;
  for (const Trial& trial : trials) {
    if (trial.ok) {
      good.push_back(&trial);
    } else if (result->first_failure.empty()) {
      result->first_failure = trial.failure;
    }
  }
  result->succeeded = static_cast<int>(good.size());
  for (const Trial* trial : good) result->clipped_turns += trial->clipped_turns;
  const double n = good.size();
  std::vector<int> estimated = options.estimated;
  std::sort(estimated.begin(), estimated.end());
  estimated.erase(std::unique(estimated.begin(), estimated.end()), estimated.end());
  const std::vector<double> truth = Truths(options.design, estimated);
  for (size_t u = 0; u < truth.size(); ++u) {
    GyroscopeUnknownStudy row;
    row.name = names[u];
    row.unit = units[u];
    row.truth = truth[u];
    static_cast<SigmaCheck&>(row) = CheckSigma(
        static_cast<int>(good.size()), row.truth, [&](int i) { return good[i]->estimate[u]; },
        [&](int i) { return good[i]->stddev[u]; });
    const double ratio_band = std::max(kRatioBand, kBandSd * row.ratio_stderr);
    row.ratio_ok = std::abs(row.ratio - 1.0) <= ratio_band;
    row.coverage_ok = true;
    for (int level = 0; level < 3; ++level) {
      row.coverage_ok =
          row.coverage_ok && WithinBinomialBand(row.coverage[level],
                                                GyroscopeMonteCarloResult::kExpectedCoverage[level],
                                                result->succeeded);
    }
    if (!row.ratio_ok) {
      result->failures.push_back(
          StringPrintf("%s: reported sigma / spread = %.3f", row.name.c_str(), row.ratio));
    }
    if (!row.coverage_ok) {
      result->failures.push_back(StringPrintf(
          "%s: truth within 1, 2, 3 sigma in %.1f, %.1f, %.1f%% of trials", row.name.c_str(),
          100.0 * row.coverage[0], 100.0 * row.coverage[1], 100.0 * row.coverage[2]));
    }
    result->unknowns.push_back(row);
  }
  for (const Trial* trial : good) {
    result->mean_chi2_per_dof += trial->chi2_per_dof / n;
    result->p_below_001 += (trial->p_value < 0.01) / n;
  }
  result->p_ok = WithinBinomialBand(result->p_below_001, 0.01, result->succeeded);
  if (options.discovery_alpha > 0.0) {
    for (const Trial* trial : good) {
      if (trial->verdict < 0) {
        ++result->discovery_failures;
        continue;
      }
      ++result->verdicts[trial->verdict];
      for (int e = 0; e < kGyroscopeEffectCount; ++e) result->found[e] += trial->found[e];
      for (const std::string& check : trial->checks_flagged) ++result->checks_flagged[check];
    }
    const bool null = options.design.effects == GyroscopeEffectCoefficients{};
    if (null) {
      const double alpha = options.discovery_alpha;
      const double rate = 1.0 - static_cast<double>(result->verdicts[0]) / n;
      result->null_rate_ok = rate <= alpha + 2.0 * std::sqrt(alpha * (1.0 - alpha) / n);
      if (!result->null_rate_ok) {
        result->failures.push_back(StringPrintf(
            "discovery: %.1f%% of sessions with nothing hidden got a verdict but explained, "
            "above alpha = %g + 2 sd",
            100.0 * rate, alpha));
      }
    }
    if (result->discovery_failures > 0) {
      result->failures.push_back(
          StringPrintf("discovery failed on %d sessions", result->discovery_failures));
    }
  }
  if (!result->p_ok) {
    result->failures.push_back(
        StringPrintf("fit statistic: p < 0.01 in %.1f%% of trials", 100.0 * result->p_below_001));
  }
  if (result->succeeded < result->trials) {
    result->failures.push_back(StringPrintf("%d of %d trials failed (first: %s)",
                                            result->trials - result->succeeded, result->trials,
                                            result->first_failure.c_str()));
  }
  result->passed = result->failures.empty();
  result->claim_possible = result->succeeded >= kClaimTrials;
  return Status::Ok();
}

}  // namespace accelcal
