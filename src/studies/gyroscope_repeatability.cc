#include "studies/gyroscope_repeatability.h"

#include <cmath>
#include <vector>

#include "estimation/gyroscope/gyroscope_sessions.h"
#include "estimation/triad/triad_session_calibration.h"
#include "simulation/monte_carlo.h"
#include "simulation/random.h"
#include "simulation/triad_log_simulator.h"

namespace accelcal {

ArraySessionEstimates GyroscopeArrayEstimates(
    const std::vector<std::vector<GyroscopeMlResult>>& sessions) {
  ArraySessionEstimates estimates(kGyroscopeCalibrationCount);
  for (const std::vector<GyroscopeMlResult>& device : sessions) {
    const std::vector<std::vector<SessionEstimate>> by_unknown = GyroscopeSessionEstimates(device);
    for (int i = 0; i < kGyroscopeCalibrationCount; ++i) estimates[i].push_back(by_unknown[i]);
  }
  return estimates;
}

GyroscopeSessionDesign Mimu4444LikeGyroscopeDesign() {
  GyroscopeSessionDesign design;
  design.accelerometer_truth = Mimu4444LikeTriad();
  design.poses = 24;
  design.hold_s = 4.0;
  design.rate_hz = 100.0;
  design.turn_s = 1.5;
  design.gravity_mps2 = 9.8187;
  design.accelerometer_noise = {7.5, 6.8, 10.2};
  design.gyroscope_noise = {2.6, 3.0, 1.8};
  design.truth = GyroscopeParametersWithGain(1.0 / 942.3, 1.0 / 946.4, 1.0 / 928.4);
  design.truth[kGyroscopeMisalignmentYz] = -7.2e-4;
  design.truth[kGyroscopeMisalignmentZy] = 8.2e-3;
  design.truth[kGyroscopeMisalignmentZx] = -6.4e-3;
  design.truth[kGyroscopeMisalignmentXz] = -4.9e-3;
  design.truth[kGyroscopeMisalignmentXy] = -6.0e-3;
  design.truth[kGyroscopeMisalignmentYx] = -9.2e-4;
  design.offset = {-23.1, -4.5, -3.3};
  return design;
}

namespace {

constexpr double kConfidence = 0.95;

// One session of the design with the gyroscope's unknowns `truth` (the 12), calibrated as the
// sessions path does.
Status SimulateAndCalibrateSession(const GyroscopeSessionDesign& design,
                                   const std::vector<TriadHold>& holds,
                                   const std::array<double, kGyroscopeCalibrationCount>& truth,
                                   RandomSource* random, GyroscopeMlResult* result) {
  TriadLogSimulationOptions simulation = GyroscopeDesignSimulation(design);
  for (int i = 0; i < kGyroscopeParameterCount; ++i) simulation.gyroscope.truth[i] = truth[i];
  for (int k = 0; k < 3; ++k) simulation.gyroscope.offset[k] = truth[kGyroscopeOffsetX + k];
  const TriadSession session = SimulateTriadSession(simulation, holds, random);
  TriadSessionOptions options;
  options.gravity_mps2 = design.gravity_mps2;
  TriadSessionCalibration accelerometer;
  ACCELCAL_RETURN_IF_ERROR(
      CalibrateTriadSession(session.log, options, &accelerometer).WithContext("the accelerometer"));
  GyroscopeSessionsOptions gyroscope;
  gyroscope.session.gravity_mps2 = design.gravity_mps2;
  gyroscope.initial_gain = truth[kGyroscopeGainX];
  const GyroscopeSessionOutcome outcome =
      CalibrateSessionGyroscope(session.log, accelerometer, gyroscope);
  if (!outcome.calibrated) return Status::Error("the gyroscope: " + outcome.not_calibrated);
  *result = outcome.calibration.ml;
  return Status::Ok();
}

std::array<double, kGyroscopeCalibrationCount> DesignTruth(const GyroscopeSessionDesign& design) {
  std::array<double, kGyroscopeCalibrationCount> truth{};
  for (int i = 0; i < kGyroscopeParameterCount; ++i) truth[i] = design.truth[i];
  for (int k = 0; k < 3; ++k) truth[kGyroscopeOffsetX + k] = design.offset[k];
  return truth;
}

struct DeviceTrial {
  Status status;
  std::array<bool, kGyroscopeCalibrationCount> covered{};
  std::array<bool, kGyroscopeCalibrationCount> tau_covered{};
};

}  // namespace

Status RunGyroscopeRepeatabilityMonteCarlo(const GyroscopeRepeatabilityOptions& options,
                                           GyroscopeRepeatabilityResult* result) {
  if (options.devices < 1 || options.training_sessions < 2 ||
      !(options.between_over_within >= 0.0)) {
    return Status::Error(
        "the study needs devices >= 1, training_sessions >= 2, between_over_within >= 0");
  }
  *result = GyroscopeRepeatabilityResult();
  result->options = options;
  const std::vector<TriadHold> holds = GyroscopeDesignHolds(options.design, options.seed);
  const std::array<double, kGyroscopeCalibrationCount> base = DesignTruth(options.design);
  {
    RandomSource random(options.seed, 0x70696c6f);  // the pilot's own stream
    GyroscopeMlResult pilot;
    ACCELCAL_RETURN_IF_ERROR(
        SimulateAndCalibrateSession(options.design, holds, base, &random, &pilot)
            .WithContext("the pilot session"));
    for (int i = 0; i < kGyroscopeCalibrationCount; ++i) {
      result->within_stddev[i] = pilot.stddev[i];
      result->between_stddev[i] = options.between_over_within * pilot.stddev[i];
    }
  }
  std::vector<DeviceTrial> trials(options.devices);
  MonteCarloOptions monte_carlo;
  monte_carlo.trials = options.devices;
  monte_carlo.threads = options.threads;
  RunTrials(monte_carlo, [&](int d) {
    RandomSource random(options.seed, static_cast<uint64_t>(d) + 1);
    DeviceTrial& trial = trials[d];
    std::vector<GyroscopeMlResult> training;
    GyroscopeMlResult held_out;
    for (int s = 0; s <= options.training_sessions; ++s) {
      std::array<double, kGyroscopeCalibrationCount> truth = base;
      for (int i = 0; i < kGyroscopeCalibrationCount; ++i)
        truth[i] += result->between_stddev[i] * random.StandardNormal();
      GyroscopeMlResult session;
      trial.status =
          SimulateAndCalibrateSession(options.design, holds, truth, &random, &session)
              .WithContext("device " + std::to_string(d) + ", session " + std::to_string(s + 1));
      if (!trial.status.ok()) return;
      if (s < options.training_sessions) {
        training.push_back(session);
      } else {
        held_out = session;
      }
    }
    GyroscopeRandomEffects combined;
    trial.status = CombineGyroscopeSessions(training, kConfidence, &combined);
    if (!trial.status.ok()) return;
    const std::vector<std::vector<SessionEstimate>> new_session =
        GyroscopeSessionEstimates({held_out});
    for (int i = 0; i < kGyroscopeCalibrationCount; ++i) {
      const RandomEffectsEstimate& e = combined[i];
      trial.covered[i] = std::fabs(new_session[i][0].value - e.common) <=
                         e.interval_multiplier * e.new_session_stddev;
      trial.tau_covered[i] = e.between.stddev_low <= result->between_stddev[i] &&
                             result->between_stddev[i] <= e.between.stddev_high;
    }
  });
  for (const DeviceTrial& trial : trials) {
    if (!trial.status.ok()) {
      if (result->failed_devices++ == 0) result->first_failure = trial.status.message();
      continue;
    }
    for (int i = 0; i < kGyroscopeCalibrationCount; ++i) {
      for (CoverageCount* count : {&result->coverage[static_cast<int>(GyroscopeParameterKindOf(i))],
                                   &result->coverage_by_unknown[i], &result->coverage_all}) {
        ++count->total;
        count->covered += trial.covered[i];
      }
      ++result->tau_interval_coverage.total;
      result->tau_interval_coverage.covered += trial.tau_covered[i];
    }
  }
  result->coverage_standard_error =
      result->coverage_all.total > 0
          ? std::sqrt(kConfidence * (1.0 - kConfidence) / result->coverage_all.total)
          : 0.0;
  return Status::Ok();
}

}  // namespace accelcal
