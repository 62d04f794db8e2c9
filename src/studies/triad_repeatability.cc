#include "studies/triad_repeatability.h"

#include <cmath>
#include <string>

#include "estimation/triad/triad_initial_guess.h"
#include "simulation/monte_carlo.h"
#include "simulation/random.h"
#include "simulation/triad_simulator.h"

namespace accelcal {

const char* SessionSchemeName(SessionScheme scheme) {
  switch (scheme) {
    case SessionScheme::kDevice:
      return "device";
    case SessionScheme::kPooled:
      return "pooled";
    case SessionScheme::kArray:
      return "array";
  }
  return "?";
}

const char* TriadParameterKindName(TriadParameterKind kind) {
  switch (kind) {
    case TriadParameterKind::kMisalignment:
      return "misalignment";
    case TriadParameterKind::kGain:
      return "gain";
    case TriadParameterKind::kOffset:
      return "offset";
  }
  return "?";
}

TriadParameterKind TriadParameterKindOf(int index) {
  if (index < kTriadGainX) return TriadParameterKind::kMisalignment;
  return index < kTriadOffsetX ? TriadParameterKind::kGain : TriadParameterKind::kOffset;
}

TriadParameterKind GyroscopeParameterKindOf(int index) {
  if (index < kGyroscopeGainX) return TriadParameterKind::kMisalignment;
  return index < kGyroscopeCalibrationOffsetX ? TriadParameterKind::kGain
                                              : TriadParameterKind::kOffset;
}

std::vector<TriadParameterKind> TriadParameterKinds() {
  std::vector<TriadParameterKind> kinds;
  for (int p = 0; p < kTriadParameterCount; ++p) kinds.push_back(TriadParameterKindOf(p));
  return kinds;
}

std::vector<TriadParameterKind> GyroscopeParameterKinds() {
  std::vector<TriadParameterKind> kinds;
  for (int i = 0; i < kGyroscopeCalibrationParameterCount; ++i)
    kinds.push_back(GyroscopeParameterKindOf(i));
  return kinds;
}

ArraySessionEstimates TriadArrayEstimates(const std::vector<std::vector<TriadMlResult>>& sessions) {
  ArraySessionEstimates estimates(kTriadParameterCount);
  for (int p = 0; p < kTriadParameterCount; ++p) {
    for (const std::vector<TriadMlResult>& device : sessions)
      estimates[p].push_back(SessionEstimatesOf(device, p));
  }
  return estimates;
}

namespace {

constexpr double kConfidence = 0.95;

Status CheckArrayShape(const ArraySessionEstimates& estimates, size_t minimum) {
  if (estimates.empty()) return Status::Error("a session study needs parameters");
  for (const std::vector<std::vector<SessionEstimate>>& devices : estimates) {
    if (devices.size() < 2 || devices.size() != estimates[0].size())
      return Status::Error("a session study needs at least 2 devices of the array");
    for (const std::vector<SessionEstimate>& device : devices) {
      if (device.size() != estimates[0][0].size() || device.size() < minimum) {
        return Status::Error("every device needs the same sessions, at least " +
                             std::to_string(minimum));
      }
    }
  }
  return Status::Ok();
}

void Count(const SessionPrediction& prediction, CoverageTable* table) {
  CoverageCount& count =
      (*table)[static_cast<int>(prediction.scheme)][static_cast<int>(prediction.kind)];
  ++count.total;
  count.covered += prediction.covered;
}

}  // namespace

Status PredictSessionEstimates(const ArraySessionEstimates& training,
                               const std::vector<std::vector<double>>& held_out, int held_out_index,
                               const std::vector<TriadParameterKind>& kinds,
                               std::vector<SessionPrediction>* predictions) {
  ACCELCAL_RETURN_IF_ERROR(CheckArrayShape(training, 2));
  if (held_out.size() != training.size() || kinds.size() != training.size())
    return Status::Error("the held-out session needs one estimate per parameter, and a kind");
  const double session_count = training[0][0].size();
  for (size_t p = 0; p < training.size(); ++p) {
    const std::vector<std::vector<SessionEstimate>>& groups = training[p];
    if (held_out[p].size() != groups.size())
      return Status::Error("the held-out session needs one estimate per device");
    BetweenSessionVariance pooled;
    ACCELCAL_RETURN_IF_ERROR(EstimateBetweenSessionVariance(groups, kConfidence, &pooled));
    ArraySessionVariance array;
    ACCELCAL_RETURN_IF_ERROR(EstimateArraySessionVariance(groups, &array));
    const double array_multiplier =
        StudentTQuantile(0.5 * (1.0 + kConfidence), array.degrees_of_freedom);
    const double array_stddev = std::sqrt(array.total_variance * (1.0 + 1.0 / session_count));
    for (size_t d = 0; d < groups.size(); ++d) {
      SessionPrediction prediction;
      prediction.device = static_cast<int>(d);
      prediction.held_out = held_out_index;
      prediction.parameter = static_cast<int>(p);
      prediction.kind = kinds[p];
      prediction.value = held_out[p][d];
      for (int scheme = 0; scheme < kSessionSchemeCount; ++scheme) {
        prediction.scheme = static_cast<SessionScheme>(scheme);
        if (prediction.scheme == SessionScheme::kArray) {
          double mean = 0.0;
          for (const SessionEstimate& s : groups[d]) mean += s.value / session_count;
          prediction.centre = mean;
          prediction.new_session_stddev = array_stddev;
          prediction.multiplier = array_multiplier;
        } else {
          RandomEffectsEstimate estimate;
          if (prediction.scheme == SessionScheme::kDevice) {
            ACCELCAL_RETURN_IF_ERROR(EstimateRandomEffects(groups[d], kConfidence, &estimate));
          } else {
            estimate = CombineSessions(groups[d], pooled);
          }
          prediction.centre = estimate.common;
          prediction.new_session_stddev = estimate.new_session_stddev;
          prediction.multiplier = estimate.interval_multiplier;
        }
        prediction.covered = std::fabs(prediction.value - prediction.centre) <=
                             prediction.multiplier * prediction.new_session_stddev;
        predictions->push_back(prediction);
      }
    }
  }
  return Status::Ok();
}

Status PredictSessions(const std::vector<std::vector<TriadMlResult>>& training,
                       const std::vector<TriadMlResult>& held_out, int held_out_index,
                       std::vector<SessionPrediction>* predictions) {
  if (held_out.size() != training.size())
    return Status::Error("the held-out session needs one estimate per device");
  std::vector<std::vector<double>> held_out_values(kTriadParameterCount);
  for (int p = 0; p < kTriadParameterCount; ++p) {
    for (const TriadMlResult& ml : held_out) held_out_values[p].push_back(ml.parameters[p]);
  }
  return PredictSessionEstimates(TriadArrayEstimates(training), held_out_values, held_out_index,
                                 TriadParameterKinds(), predictions);
}

Status LeaveOneSessionOutOf(const ArraySessionEstimates& sessions,
                            const std::vector<TriadParameterKind>& kinds, LosoResult* result) {
  ACCELCAL_RETURN_IF_ERROR(CheckArrayShape(sessions, 3));
  *result = LosoResult();
  const int session_count = static_cast<int>(sessions[0][0].size());
  for (int scheme = 0; scheme < kSessionSchemeCount; ++scheme)
    result->coverage_by_session[scheme].assign(session_count, CoverageCount());
  for (int out = 0; out < session_count; ++out) {
    ArraySessionEstimates training(sessions.size());
    std::vector<std::vector<double>> held_out(sessions.size());
    for (size_t p = 0; p < sessions.size(); ++p) {
      for (const std::vector<SessionEstimate>& device : sessions[p]) {
        training[p].emplace_back();
        for (int s = 0; s < session_count; ++s) {
          if (s != out) training[p].back().push_back(device[s]);
        }
        held_out[p].push_back(device[out].value);
      }
    }
    ACCELCAL_RETURN_IF_ERROR(
        PredictSessionEstimates(training, held_out, out, kinds, &result->predictions));
  }
  for (const SessionPrediction& prediction : result->predictions) {
    Count(prediction, &result->coverage);
    CoverageCount& by_session =
        result->coverage_by_session[static_cast<int>(prediction.scheme)][prediction.held_out];
    ++by_session.total;
    by_session.covered += prediction.covered;
  }
  return Status::Ok();
}

Status LeaveOneSessionOut(const std::vector<std::vector<TriadMlResult>>& sessions,
                          LosoResult* result) {
  return LeaveOneSessionOutOf(TriadArrayEstimates(sessions), TriadParameterKinds(), result);
}

Status ArrayVariances(const std::vector<std::vector<TriadMlResult>>& sessions,
                      std::array<ArraySessionVariance, kTriadParameterCount>* variances) {
  const ArraySessionEstimates estimates = TriadArrayEstimates(sessions);
  ACCELCAL_RETURN_IF_ERROR(CheckArrayShape(estimates, 2));
  for (int p = 0; p < kTriadParameterCount; ++p)
    ACCELCAL_RETURN_IF_ERROR(EstimateArraySessionVariance(estimates[p], &(*variances)[p]));
  return Status::Ok();
}

TriadParameters Mimu4444LikeTriad() {
  TriadParameters truth = TriadParametersWithOffset(-55.0, -20.0, -90.0);
  const double angles_rad[3] = {-2e-4, 1e-3, 2e-3};  // yz, zy, zx
  for (int k = 0; k < 3; ++k) {
    truth[kTriadMisalignmentYz + k] = angles_rad[k];
    truth[kTriadGainX + k] = 9.80665 / 2048.0;
  }
  return truth;
}

RepeatabilityMonteCarloOptions Mimu4444LikeMonteCarlo() {
  RepeatabilityMonteCarloOptions options;
  for (int p = 0; p < kTriadParameterCount; ++p) {
    switch (TriadParameterKindOf(p)) {
      case TriadParameterKind::kMisalignment:
        options.between_stddev[p] = 2e-4;
        options.common_share[p] = 0.35;
        break;
      case TriadParameterKind::kGain:
        options.between_stddev[p] = 8e-7;
        options.common_share[p] = 0.35;
        break;
      case TriadParameterKind::kOffset:
        options.common_share[p] = 0.9;
        break;
    }
  }
  options.between_stddev[kTriadOffsetX] = 1.2;
  options.between_stddev[kTriadOffsetY] = 0.5;
  options.between_stddev[kTriadOffsetZ] = 3.0;
  return options;
}

namespace {

struct MonteCarloTrial {
  bool failed = false;
  std::vector<SessionPrediction> predictions;
  // Device scheme on the training sessions: per device and parameter.
  std::vector<std::array<BetweenSessionVariance, kTriadParameterCount>> between;
};

Status CheckMonteCarloOptions(const RepeatabilityMonteCarloOptions& options) {
  if (options.trials < 1 || options.poses < 10 || options.samples_per_pose < 2)
    return Status::Error("the study needs trials >= 1, poses >= 10, samples_per_pose >= 2");
  if (options.devices < 2 || options.training_sessions < 2)
    return Status::Error("the study needs at least 2 devices and 2 training sessions");
  for (int p = 0; p < kTriadParameterCount; ++p) {
    if (!(options.between_stddev[p] >= 0.0) ||
        !(options.common_share[p] >= 0.0 && options.common_share[p] <= 1.0)) {
      return Status::Error(std::string("between-session sigma of ") +
                           TriadParameterInfos()[p].name +
                           " must be >= 0 and its common share in [0, 1]");
    }
  }
  for (double noise : options.noise_stddev) {
    if (!(noise > 0.0)) return Status::Error("the noise sigma must be positive");
  }
  return Status::Ok();
}

void RunMonteCarloTrial(const RepeatabilityMonteCarloOptions& options, int trial_index,
                        MonteCarloTrial* trial) {
  RandomSource random(options.seed, static_cast<uint64_t>(trial_index));
  const int sessions = options.training_sessions + 1;
  const TriadParameters base = Mimu4444LikeTriad();
  // Every session's common shift, then each device's own.
  std::vector<TriadParameters> common(sessions);
  for (TriadParameters& shift : common) {
    for (int p = 0; p < kTriadParameterCount; ++p)
      shift[p] =
          options.between_stddev[p] * std::sqrt(options.common_share[p]) * random.StandardNormal();
  }
  std::vector<std::vector<TriadMlResult>> training(options.devices);
  std::vector<TriadMlResult> held_out(options.devices);
  TriadSimulationOptions simulation;
  simulation.gravity_mps2 = options.gravity_mps2;
  simulation.samples_per_pose = options.samples_per_pose;
  simulation.noise_stddev = options.noise_stddev;
  for (int d = 0; d < options.devices; ++d) {
    TriadParameters device = base;  // devices differ by far more than a session moves them
    for (int p = 0; p < kTriadParameterCount; ++p)
      device[p] += 10.0 * options.between_stddev[p] * random.StandardNormal();
    for (int s = 0; s < sessions; ++s) {
      simulation.truth = device;
      for (int p = 0; p < kTriadParameterCount; ++p) {
        simulation.truth[p] += common[s][p] + options.between_stddev[p] *
                                                  std::sqrt(1.0 - options.common_share[p]) *
                                                  random.StandardNormal();
      }
      const std::vector<TriadPoseMean> poses =
          SimulateTriadPoses(simulation, RandomPoseDirections(options.poses, &random), &random);
      TriadMlOptions ml;
      ml.gravity_mps2 = options.gravity_mps2;
      ml.initial = TriadStartFromPoses(poses, options.gravity_mps2);
      TriadMlResult result;
      if (!CalibrateTriadMl(poses, ml, &result).ok()) {
        trial->failed = true;
        return;
      }
      if (s < options.training_sessions) {
        training[d].push_back(result);
      } else {
        held_out[d] = result;
      }
    }
  }
  if (!PredictSessions(training, held_out, options.training_sessions, &trial->predictions).ok()) {
    trial->failed = true;
    return;
  }
  trial->between.resize(options.devices);
  for (int d = 0; d < options.devices; ++d) {
    for (int p = 0; p < kTriadParameterCount; ++p) {
      if (!EstimateBetweenSessionVariance({SessionEstimatesOf(training[d], p)}, kConfidence,
                                          &trial->between[d][p])
               .ok()) {
        trial->failed = true;
      }
    }
  }
}

}  // namespace

Status RunRepeatabilityMonteCarlo(const RepeatabilityMonteCarloOptions& options,
                                  RepeatabilityMonteCarloResult* result) {
  ACCELCAL_RETURN_IF_ERROR(CheckMonteCarloOptions(options));
  std::vector<MonteCarloTrial> trials(options.trials);
  MonteCarloOptions monte_carlo;
  monte_carlo.trials = options.trials;
  monte_carlo.threads = 1;  // the trials are cheap; results do not depend on it anyway
  RunTrials(monte_carlo, [&](int i) { RunMonteCarloTrial(options, i, &trials[i]); });

  *result = RepeatabilityMonteCarloResult();
  result->options = options;
  std::array<double, kTriadParameterKindCount> ratio_sum{};
  std::array<int, kTriadParameterKindCount> ratio_count{};
  for (const MonteCarloTrial& trial : trials) {
    if (trial.failed) {
      ++result->failed_trials;
      continue;
    }
    for (const SessionPrediction& prediction : trial.predictions)
      Count(prediction, &result->coverage);
    for (const auto& device : trial.between) {
      for (int p = 0; p < kTriadParameterCount; ++p) {
        const double truth = options.between_stddev[p];
        const int kind = static_cast<int>(TriadParameterKindOf(p));
        CoverageCount& count = result->tau_interval_coverage[kind];
        ++count.total;
        count.covered += device[p].stddev_low <= truth && truth <= device[p].stddev_high;
        if (truth > 0.0) {
          ratio_sum[kind] += device[p].variance / (truth * truth);
          ++ratio_count[kind];
        }
      }
    }
  }
  for (int kind = 0; kind < kTriadParameterKindCount; ++kind)
    result->tau2_ratio[kind] = ratio_count[kind] > 0 ? ratio_sum[kind] / ratio_count[kind] : 0.0;
  const int good = options.trials - result->failed_trials;
  result->coverage_standard_error =
      good > 0 ? std::sqrt(kConfidence * (1.0 - kConfidence) / good) : 0.0;
  return Status::Ok();
}

}  // namespace accelcal
