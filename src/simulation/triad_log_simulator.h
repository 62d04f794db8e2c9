#ifndef ACCELCAL_SIMULATION_TRIAD_LOG_SIMULATOR_H_
#define ACCELCAL_SIMULATION_TRIAD_LOG_SIMULATOR_H_

// A whole multi-position session of a triad (models/triad.h), sample by sample, as a static
// detector sees it: the sensor held still in one orientation after another, turned between
// them, every sample with white Gaussian noise. The holds' true first and last samples come
// back beside the log, so a detector's intervals can be checked against them.
//
// Hold p: specific force g n_p. Turn from n_p to n_p+1 over `turn_s`: the direction rotates
// about n_p x n_p+1 by the angle between them times (1 - cos(pi tau / turn_s)) / 2, tau the time
// into the turn, so it starts and ends at rest, as a hand does, and the first samples of a turn
// differ from the hold by little (the hardest boundaries for a detector). The triad outputs
// u = K^-1 T^-1 a + b (TriadRawOutput), plus noise (scaled per hold, and carried through the
// turn that follows it) and vibration, rounded to whole counts when asked (an ADC; a noise below
// one count then leaves most windows of a hold constant, as on 12-bit consumer sensors).
// The log starts with the first hold: no initial rest unless the caller makes it long.

#include <array>
#include <vector>

#include "common/triad_log.h"
#include "models/gyroscope.h"
#include "models/gyroscope_effect_list.h"
#include "models/triad.h"
#include "simulation/random.h"

namespace accelcal {

struct TriadHold {
  std::array<double, 3> direction{};  // unit vector of the specific force
  double duration_s = 0.0;            // 0: the turn passes through it without stopping
  double noise_scale = 1.0;           // the output noise of this hold is noise_stddev times it
  double turn_yaw_deg = 0.0;  // the turn after it also turns about gravity by this (gyroscope)
};

// The gyroscope beside the triad (models/gyroscope.h, models/gyroscope_effect_list.h), when
// enabled: at rest it reads its offset plus noise (and the effects of the specific force); in a
// turn the body turns about the fixed axis n_p x n_p+1 by the hold-to-hold angle, and at the same
// time about the current gravity direction by the hold's turn_yaw_deg, with the same (1 - cos)
// profile: the rate is w = psi' n(t) - phi' a (rad/s, body frame), which leaves the accelerometer's
// samples exactly as without the gyroscope. The rates are exact at the samples (continuous-time
// turns sampled), the outputs u = GyroscopeRawWithEffects(w, g n) + noise.
struct GyroscopeSimulationOptions {
  bool enabled = false;
  GyroscopeParameters truth = GyroscopeParametersWithGain(2e-4, 2e-4, 2e-4);
  GyroscopeOffset offset{};
  GyroscopeEffectCoefficients effects{};
  std::array<double, 3> noise_stddev{{3.0, 3.0, 3.0}};  // per sample, in the output's unit
  bool round_to_counts = true;
  // The Earth's rate (7.292e-5 rad/s) at this latitude: Omega sin(latitude) about the up
  // direction (the specific force's) and Omega cos(latitude) about a horizontal direction at a
  // random azimuth in each hold (turned with the body through the turn that follows it).
  bool earth_rate = false;
  double latitude_deg = 0.0;
};

struct TriadLogSimulationOptions {
  TriadParameters truth{};
  double gravity_mps2 = 9.81;
  double rate_hz = 100.0;
  double turn_s = 1.5;
  // How abruptly a turn starts and stops (docs/gyroscope.md, "The turns' sampling error"): the
  // rate jumps to this fraction of its peak at the turn's start and from it to 0 at its end, as
  // a hand that sets the sensor down against a table stops it, with the motion starting and
  // ending at uniformly random times within a sample interval (independently), so that the
  // samples do not resolve the jumps (the turn's first two and last two samples at rest, as a
  // static detector leaves them). The profile between is the (1 - cos) one's rate, raised to start
  // and end there: rate ~ e + (1 - e) sin(pi u), u the motion's progress in time. 0: the smooth
  // profile, its motion starting at a sample (the random stream is then not drawn from).
  double turn_abruptness = 0.0;
  std::array<double, 3> noise_stddev{{3.0, 3.0, 3.0}};  // per sample, in counts
  bool round_to_counts = true;
  double start_s = 0.0;  // time stamp of the first sample
  // Narrow-band vibration on every sample (a motor, a fan, a table that rings), in counts per
  // axis: vibration_counts[k] sin(2 pi f t + phase_k), f = vibration_hz, the phases drawn once
  // per log. Quiet windows are then not white: most of their variance sits at one frequency.
  std::array<double, 3> vibration_counts{{0.0, 0.0, 0.0}};
  double vibration_hz = 0.0;
  GyroscopeSimulationOptions gyroscope;  // SimulateTriadSession only
};

// The true samples of a hold, inclusive (end < start for a hold of no samples).
struct TriadHoldSamples {
  int start = 0;
  int end = -1;
};

struct TriadSession {
  TriadLog log;
  std::vector<TriadHoldSamples> holds;  // one per TriadHold, in order
};

TriadSession SimulateTriadSession(const TriadLogSimulationOptions& options,
                                  const std::vector<TriadHold>& holds, RandomSource* random);

// `count` holds of `hold_s` in random directions, each at least `min_turn_deg` from the one
// before (a hand turns the sensor; two nearly equal consecutive poses are one pose).
std::vector<TriadHold> RandomSeparatedHolds(int count, double hold_s, double min_turn_deg,
                                            RandomSource* random);

// A sensor turning the whole time at constant rates, never resting: the specific force points
// along (cos a sin e, sin a sin e, cos e), a = azimuth_rate t, e = elevation_rate t + 0.3 rad,
// with `shake_mps2` of white force noise per axis on top (a hand) and the options' output noise.
// What a static detector must refuse: turned slowly, every window is as quiet as any other.
TriadLog SimulateSteadyTurn(const TriadLogSimulationOptions& options, double duration_s,
                            double azimuth_rate_rad_s, double elevation_rate_rad_s,
                            double shake_mps2, RandomSource* random);

}  // namespace accelcal

#endif  // ACCELCAL_SIMULATION_TRIAD_LOG_SIMULATOR_H_
