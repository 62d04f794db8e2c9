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

}  // namespace accelcal
