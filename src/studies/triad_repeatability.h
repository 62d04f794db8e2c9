#ifndef ACCELCAL_STUDIES_TRIAD_REPEATABILITY_H_
#define ACCELCAL_STUDIES_TRIAD_REPEATABILITY_H_

// Does the new-session sigma of estimation/triad/triad_sessions.h cover new sessions as claimed
// (issue 21, item 3)? Two checks, the same three schemes in both:
//
//   device  each device's own tau^2 (estimation/triad/triad_sessions.h), t on S - 1 dof: what
//           `calibrate_imu --log=S1,S2,...` reports for one device;
//   pooled  tau^2 shared by the array's devices as if their sessions were independent,
//           t on D (S - 1) dof;
//   array   the two-way model of EstimateArraySessionVariance: a session's common shift of
//           every device plus each device's own, t on Satterthwaite's dof.
//
// Each predicts a held-out session of device d as: centre = the device's estimate from its
// other sessions (the weighted mean for device and pooled, the plain mean for array),
// interval = centre +- multiplier x new-session sigma at 95%; covered when the held-out
// estimate lies inside. Coverage is counted per parameter kind (misalignment, gain, offset).
//
// 1. Leave one session out on measured sessions (`sessions[d][s]`, every device the same
//    S >= 3 sessions): each session held out in turn, predicted from the S - 1 others.
// 2. Monte Carlo: an array of D simulated triads whose parameters move between sessions by
//    known amounts (a common part shared by every device and a device's own part, per
//    parameter), each session simulated as static poses (simulation/triad_simulator.h) and
//    calibrated (estimation/triad/triad_ml_calibration.h); the schemes predict session S + 1 from
//    sessions 1..S. Also whether the device scheme's interval of tau covers the device's true
//    between-session sigma (common and own parts together), and the mean of tau^2 estimated
//    over its truth. Coverage's standard error is given on `trials` independent arrays
//    (conservative: the predictions of one array share its sessions' common shifts).

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "common/status.h"
#include "estimation/triad/triad_ml_calibration.h"
#include "estimation/triad/triad_sessions.h"
#include "models/gyroscope.h"
#include "models/triad.h"

namespace accelcal {

enum class SessionScheme { kDevice, kPooled, kArray };
constexpr int kSessionSchemeCount = 3;
const char* SessionSchemeName(SessionScheme scheme);

enum class TriadParameterKind { kMisalignment, kGain, kOffset };
constexpr int kTriadParameterKindCount = 3;
const char* TriadParameterKindName(TriadParameterKind kind);
TriadParameterKind TriadParameterKindOf(int index);
// The gyroscope's 12 unknowns (kGyroscopeCalibrationCount's order) by the same kinds: its six
// angles, three gains, three offsets.
TriadParameterKind GyroscopeParameterKindOf(int index);

// One held-out estimate and its prediction.
struct SessionPrediction {
  int device = 0;
  int held_out = 0;  // session index
  int parameter = 0;
  TriadParameterKind kind = TriadParameterKind::kMisalignment;
  SessionScheme scheme = SessionScheme::kDevice;
  double value = 0.0;   // the held-out session's estimate
  double centre = 0.0;  // from the other sessions
  double new_session_stddev = 0.0;
  double multiplier = 0.0;
  bool covered = false;
};

struct CoverageCount {
  int covered = 0;
  int total = 0;
  double fraction() const { return total > 0 ? static_cast<double>(covered) / total : 0.0; }
};

// [scheme][kind]
using CoverageTable =
    std::array<std::array<CoverageCount, kTriadParameterKindCount>, kSessionSchemeCount>;

struct LosoResult {
  std::vector<SessionPrediction> predictions;
  CoverageTable coverage{};
  // [scheme][held-out session]: every kind together.
  std::array<std::vector<CoverageCount>, kSessionSchemeCount> coverage_by_session;
};

// Any sensor's parameters: estimates[p][d][s], parameter p of device d in session s (every
// device the same sessions), with kinds[p] its kind.
using ArraySessionEstimates = std::vector<std::vector<std::vector<SessionEstimate>>>;
ArraySessionEstimates TriadArrayEstimates(const std::vector<std::vector<TriadMlResult>>& sessions);
std::vector<TriadParameterKind> TriadParameterKinds();
std::vector<TriadParameterKind> GyroscopeParameterKinds();

// The predictions of the held-out session (held_out[p][d]: its estimate of parameter p on
// device d) from `training` (at least 2 sessions per device; D >= 2), each scheme.
Status PredictSessionEstimates(const ArraySessionEstimates& training,
                               const std::vector<std::vector<double>>& held_out, int held_out_index,
                               const std::vector<TriadParameterKind>& kinds,
                               std::vector<SessionPrediction>* predictions);

// Every session held out in turn (S >= 3, D >= 2).
Status LeaveOneSessionOutOf(const ArraySessionEstimates& sessions,
                            const std::vector<TriadParameterKind>& kinds, LosoResult* result);

// The predictions of `held_out` (its estimates for every device and parameter, each scheme)
// from `training` (sessions[d][s], every device the same sessions, at least 2; D >= 2).
Status PredictSessions(const std::vector<std::vector<TriadMlResult>>& training,
                       const std::vector<TriadMlResult>& held_out, int held_out_index,
                       std::vector<SessionPrediction>* predictions);

// sessions[d][s]: D >= 2 devices, the same S >= 3 sessions each.
Status LeaveOneSessionOut(const std::vector<std::vector<TriadMlResult>>& sessions,
                          LosoResult* result);

// Per parameter over the whole array (all S sessions): the array model's figures.
Status ArrayVariances(const std::vector<std::vector<TriadMlResult>>& sessions,
                      std::array<ArraySessionVariance, kTriadParameterCount>* variances);

struct RepeatabilityMonteCarloOptions {
  int trials = 500;
  int devices = 8;
  int training_sessions = 2;  // S; session S + 1 is predicted
  int poses = 20;
  int samples_per_pose = 1400;                           // ~22 s at 62.5 Hz, as mimu4444's poses
  std::array<double, 3> noise_stddev{{7.5, 6.8, 10.2}};  // counts per sample, as mimu4444
  double gravity_mps2 = 9.8187;
  // Between-session standard deviation per parameter (common and own parts together) and
  // the common part's share of its variance; defaults near what mimu4444's runs 1-3 show.
  TriadParameters between_stddev{};
  TriadParameters common_share{};
  uint64_t seed = 1;
};

// mimu4444-like: angles 1e-4..4e-3 rad, gains ~1/209 (m/s^2)/count, offsets tens of counts;
// between-session sigmas 2e-4 rad, 8e-7 (m/s^2)/count, 1.2 / 0.5 / 3 counts; common shares
// 0.35 (angles, gains) and 0.9 (offsets).
TriadParameters Mimu4444LikeTriad();
RepeatabilityMonteCarloOptions Mimu4444LikeMonteCarlo();

struct RepeatabilityMonteCarloResult {
  RepeatabilityMonteCarloOptions options;
  int failed_trials = 0;  // a session the calibration refused (then the trial is skipped)
  CoverageTable coverage{};
  // Device scheme, per kind: the 95% interval of tau covering the true sigma, and
  // mean(tau_hat^2) / true tau^2.
  std::array<CoverageCount, kTriadParameterKindCount> tau_interval_coverage{};
  std::array<double, kTriadParameterKindCount> tau2_ratio{};
  // The binomial standard error of a 95% coverage on `trials` independent arrays.
  double coverage_standard_error = 0.0;
};

// Fails only on options no study can run (non-positive counts, fewer than 2 devices or
// sessions, a negative sigma, a share outside [0, 1]).
Status RunRepeatabilityMonteCarlo(const RepeatabilityMonteCarloOptions& options,
                                  RepeatabilityMonteCarloResult* result);

}  // namespace accelcal

#endif  // ACCELCAL_STUDIES_TRIAD_REPEATABILITY_H_
