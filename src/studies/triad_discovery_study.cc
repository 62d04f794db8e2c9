#include "studies/triad_discovery_study.h"

#include <chrono>
#include <cmath>

#include "common/format.h"
#include "estimation/triad/triad_session_calibration.h"
#include "simulation/monte_carlo.h"
#include "simulation/noise_process.h"
#include "simulation/random.h"
#include "simulation/triad_log_simulator.h"
#include "studies/triad_monte_carlo.h"

namespace accelcal {
namespace {

constexpr double kFlickerFloor = 0.441;  // Allan variance of flicker noise over B^2 (2 ln 2 / pi)
constexpr double kBankSpacing = 4.0;
constexpr double kMinTurnDeg = 30.0;

NoiseProcessParameters FlickerBank(double b, const TriadDiscoveryStudyOptions& options) {
  NoiseProcessParameters bank;
  bank.sample_period_s = 1.0 / options.rate_hz;
  const double q =
      FlickerBankStddev(b, options.flicker_min_s, options.flicker_max_s, bank.sample_period_s);
  for (double t = options.flicker_min_s; t <= options.flicker_max_s * 1.0001; t *= kBankSpacing)
    bank.markov.push_back({q, t});
  return bank;
}

Status CheckOptions(const TriadDiscoveryStudyOptions& options) {
  if (options.sessions < 1) return Status::Error("the study needs at least 1 session");
  if (options.poses < 10) return Status::Error("a session needs at least 10 poses");
  if (!(options.rate_hz > 0.0) || !(options.hold_s * options.rate_hz >= 2.0))
    return Status::Error("every hold needs at least 2 samples (--hold_s times --rate_hz)");
  if (!(options.turn_s > 0.0)) return Status::Error("the turns need a positive duration");
  if (!(options.alpha > 0.0 && options.alpha < 0.5))
    return Status::Error("alpha must be in (0, 0.5)");
  for (int k = 0; k < 3; ++k) {
    if (!(options.noise_stddev[k] > 0.0)) return Status::Error("the white noise must be positive");
    if (!(options.flicker_b[k] >= 0.0)) return Status::Error("the flicker B must be >= 0");
  }
  if (!(options.flicker_min_s > 0.0 && options.flicker_max_s >= options.flicker_min_s))
    return Status::Error("the flicker band needs 0 < min <= max (s)");
  return Status::Ok();
}

struct Session {
  bool ok = false;
  std::string failure;
  Verdict verdict = Verdict::kExplained;
  bool coloured = false;
  bool effect = false;
  bool remaining = false;
  std::array<bool, 3> drift{};
  double chi2_per_dof = 0.0;
  std::array<double, 3> n{};
  std::array<double, 3> b{};
  std::array<double, 3> k{};
};

}  // namespace

double FlickerBankStddev(double b, double min_s, double max_s, double sample_period_s) {
  if (!(b > 0.0)) return 0.0;
  NoiseProcessParameters unit;
  unit.sample_period_s = sample_period_s;
  for (double t = min_s; t <= max_s * 1.0001; t *= kBankSpacing) unit.markov.push_back({1.0, t});
  const long long m = std::max(1LL, std::llround(std::sqrt(min_s * max_s) / sample_period_s));
  return b * std::sqrt(kFlickerFloor / NoiseProcessAllanVariance(unit, m));
}

Status RunTriadDiscoveryStudy(const TriadDiscoveryStudyOptions& options,
                              TriadDiscoveryStudyResult* result) {
  *result = TriadDiscoveryStudyResult();
  ACCELCAL_RETURN_IF_ERROR(CheckOptions(options));
  const auto start = std::chrono::steady_clock::now();
  TriadParameters truth = options.truth;
  if (truth == TriadParameters{}) truth = XsensLikeTriad();
  std::array<NoiseProcessParameters, 3> banks;
  for (int k = 0; k < 3; ++k) banks[k] = FlickerBank(options.flicker_b[k], options);

  std::vector<Session> sessions(options.sessions);
  auto run = [&](int index) {
    RandomSource random(options.seed, static_cast<uint64_t>(index));
    TriadLogSimulationOptions simulation;
    simulation.truth = truth;
    simulation.gravity_mps2 = options.gravity_mps2;
    simulation.rate_hz = options.rate_hz;
    simulation.turn_s = options.turn_s;
    simulation.noise_stddev = options.noise_stddev;
    simulation.round_to_counts = false;  // after the flicker and drift are added
    const std::vector<TriadHold> holds =
        RandomSeparatedHolds(options.poses, options.hold_s, kMinTurnDeg, &random);
    TriadSession simulated = SimulateTriadSession(simulation, holds, &random);
    TriadLog& log = simulated.log;
    const double middle_s = 0.5 * (log.timestamp_s.front() + log.timestamp_s.back());
    for (int k = 0; k < 3; ++k) {
      std::vector<double> flicker;
      if (options.flicker_b[k] > 0.0)
        flicker = SimulateNoiseProcess(banks[k], static_cast<long long>(log.size()), &random);
      for (size_t i = 0; i < log.size(); ++i) {
        double& u = log.output[i][k];
        if (!flicker.empty()) u += flicker[i];
        u += options.offset_drift[k] * (log.timestamp_s[i] - middle_s);
        u = std::round(u);
      }
    }
    std::vector<StaticInterval> intervals;
    for (const TriadHoldSamples& hold : simulated.holds) {
      StaticInterval interval;
      interval.start = hold.start;
      interval.end = hold.end;
      interval.start_s = log.timestamp_s[hold.start];
      interval.end_s = log.timestamp_s[hold.end];
      interval.duration_s = interval.end_s - interval.start_s;
      intervals.push_back(interval);
    }
    TriadSessionOptions calibration_options;
    calibration_options.gravity_mps2 = options.gravity_mps2;
    calibration_options.alpha = options.alpha;
    TriadSessionCalibration calibration;
    Session& session = sessions[index];
    const Status status =
        CalibrateTriadSessionOnIntervals(log, intervals, calibration_options, &calibration);
    if (!status.ok()) {
      session.failure = status.message();
      return;
    }
    const TriadDiscoveryResult& discovery = calibration.discovery;
    session.ok = true;
    session.verdict = discovery.verdict_code;
    session.coloured = discovery.coloured_noise;
    session.effect = !discovery.effects.empty();
    session.remaining = !discovery.remaining.empty();
    for (const TriadFoundEffect& effect : discovery.effects)
      for (int k = 0; k < 3; ++k)
        if (effect.name == std::string("offset_drift_") + "xyz"[k]) session.drift[k] = true;
    session.chi2_per_dof = discovery.final_fit.chi2_per_dof;
    for (int k = 0; k < 3; ++k) {
      session.n[k] = calibration.pose_noise.terms[k].white_density;
      session.b[k] = calibration.pose_noise.terms[k].bias_instability;
      session.k[k] = calibration.pose_noise.terms[k].random_walk;
    }
  };
  ProgressCounter progress(options.progress, options.sessions);
  MonteCarloOptions monte_carlo;
  monte_carlo.trials = options.sessions;
  monte_carlo.threads = options.threads;
  monte_carlo.progress = &progress;
  const MonteCarloTiming timing = RunTrials(monte_carlo, run);
  result->threads = timing.threads;

  for (int i = 0; i < options.sessions; ++i) {
    const Session& session = sessions[i];
    if (!session.ok) {
      if (result->sessions_failed++ == 0)
        result->first_failure = StringPrintf("session %d: ", i) + session.failure;
      continue;
    }
    ++result->sessions_ok;
    ++result->verdicts[static_cast<int>(session.verdict)];
    result->coloured_noise += session.coloured;
    result->effect_named += session.effect;
    result->unexplained += session.remaining;
    result->beyond_noise += session.effect || session.remaining ||
                            session.verdict == Verdict::kCannotTellApart ||
                            session.verdict == Verdict::kUnexplained;
    for (int k = 0; k < 3; ++k) result->drift_found[k] += session.drift[k];
    result->mean_chi2_per_dof += session.chi2_per_dof;
    for (int k = 0; k < 3; ++k) {
      result->mean_fitted_n[k] += session.n[k];
      result->mean_fitted_b[k] += session.b[k];
      result->mean_fitted_k[k] += session.k[k];
    }
  }
  if (result->sessions_ok > 0) {
    const double n = result->sessions_ok;
    result->mean_chi2_per_dof /= n;
    for (int k = 0; k < 3; ++k) {
      result->mean_fitted_n[k] /= n;
      result->mean_fitted_b[k] /= n;
      result->mean_fitted_k[k] /= n;
    }
    result->beyond_noise_rate = result->beyond_noise / n;
    result->level_band = options.alpha + 2.0 * std::sqrt(options.alpha * (1.0 - options.alpha) / n);
    result->level_held = result->beyond_noise_rate <= result->level_band;
  }
  result->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return Status::Ok();
}

std::string TriadDiscoveryStudyText(const TriadDiscoveryStudyOptions& options,
                                    const TriadDiscoveryStudyResult& result) {
  std::string text = StringPrintf(
      "Discovery on %d simulated sessions (seed %llu): %d poses of %.3g s, turns of %.3g s, "
      "%.4g Hz, outputs rounded to counts\n"
      "  white noise per sample (%.3g, %.3g, %.3g) counts\n",
      options.sessions, static_cast<unsigned long long>(options.seed), options.poses,
      options.hold_s, options.turn_s, options.rate_hz, options.noise_stddev[0],
      options.noise_stddev[1], options.noise_stddev[2]);
  if (options.flicker_b != std::array<double, 3>{}) {
    text += StringPrintf(
        "  flicker noise B = (%.3g, %.3g, %.3g) counts (Allan deviation floor 0.664 B), a bank "
        "of Gauss-Markov processes at correlation times %.3g to %.3g s\n",
        options.flicker_b[0], options.flicker_b[1], options.flicker_b[2], options.flicker_min_s,
        options.flicker_max_s);
  } else {
    text += "  no flicker noise\n";
  }
  if (options.offset_drift != std::array<double, 3>{}) {
    text += StringPrintf("  offset drift (%.3g, %.3g, %.3g) counts/s (hidden)\n",
                         options.offset_drift[0], options.offset_drift[1], options.offset_drift[2]);
  }
  text += StringPrintf("  alpha %.3g\n\n", options.alpha);
  text += StringPrintf(
      "sessions calibrated: %d (failed %d%s%s)\n", result.sessions_ok, result.sessions_failed,
      result.first_failure.empty() ? "" : "; first: ", result.first_failure.c_str());
  text +=
      StringPrintf("verdicts: explained %d, missing %d, unexplained %d, cannot_tell_apart %d\n",
                   result.verdicts[0], result.verdicts[1], result.verdicts[2], result.verdicts[3]);
  text += StringPrintf(
      "coloured noise model chosen: %d; an effect named: %d; something "
      "remained: %d; final chi2/dof mean %.3f\n",
      result.coloured_noise, result.effect_named, result.unexplained, result.mean_chi2_per_dof);
  text += StringPrintf(
      "Allan terms of the poses, mean: N (%.3g, %.3g, %.3g) count/sqrt(Hz), B (%.3g, %.3g, %.3g) "
      "counts, K (%.3g, %.3g, %.3g) count sqrt(Hz)\n",
      result.mean_fitted_n[0], result.mean_fitted_n[1], result.mean_fitted_n[2],
      result.mean_fitted_b[0], result.mean_fitted_b[1], result.mean_fitted_b[2],
      result.mean_fitted_k[0], result.mean_fitted_k[1], result.mean_fitted_k[2]);
  text += StringPrintf("offset_drift found: x %d, y %d, z %d\n", result.drift_found[0],
                       result.drift_found[1], result.drift_found[2]);
  const double n = std::max(result.sessions_ok, 1);
  const bool hidden = options.offset_drift != std::array<double, 3>{};
  text += StringPrintf(
      "beyond the noise (an effect named, unexplained or cannot_tell_apart): %d of %d = %.4f; %s",
      result.beyond_noise, result.sessions_ok, result.beyond_noise / n,
      hidden ? "an effect is hidden, so this is power, not the level\n"
             : StringPrintf("with nothing hidden it should be <= alpha + 2 sd = %.4f: %s\n",
                            result.level_band, result.level_held ? "level held" : "LEVEL NOT HELD")
                   .c_str());
  text += StringPrintf("%.1f s on %d threads\n", result.seconds, result.threads);
  return text;
}

}  // namespace accelcal
