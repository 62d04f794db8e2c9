#include "simulation/triad_log_simulator.h"

#include <algorithm>
#include <cmath>

#include "common/vector3.h"
#include "simulation/triad_simulator.h"

namespace accelcal {
namespace {

// Rodrigues' rotation of `v` about the unit `axis` by `angle_rad`.
Vector3 Rotate(const Vector3& v, const Vector3& axis, double angle_rad) {
  const Vector3 cross = Cross(axis, v);
  const double along = Dot(axis, v) * (1.0 - std::cos(angle_rad));
  const double c = std::cos(angle_rad);
  const double s = std::sin(angle_rad);
  return {v[0] * c + cross[0] * s + axis[0] * along, v[1] * c + cross[1] * s + axis[1] * along,
          v[2] * c + cross[2] * s + axis[2] * along};
}

// The unit axis turning `from` towards `to`; for opposite directions any axis perpendicular to
// `from` does.
Vector3 TurnAxis(const Vector3& from, const Vector3& to) {
  Vector3 axis = Cross(from, to);
  double norm = std::sqrt(Dot(axis, axis));
  if (norm < 1e-9) {
    axis = Cross(from, std::abs(from[0]) < 0.9 ? Vector3{1.0, 0.0, 0.0} : Vector3{0.0, 1.0, 0.0});
    norm = std::sqrt(Dot(axis, axis));
  }
  return {axis[0] / norm, axis[1] / norm, axis[2] / norm};
}

class SampleWriter {
 public:
  SampleWriter(const TriadLogSimulationOptions& options, RandomSource* random, TriadLog* log)
      : options_(options), random_(random), log_(log) {
    if (options_.vibration_hz > 0.0)
      for (double& phase : vibration_phase_) phase = 2.0 * M_PI * random_->Uniform();
  }
  // The factor on the options' noise for the samples that follow.
  void SetNoiseScale(double scale) { noise_scale_ = scale; }

  // `shake_mps2`: white noise of the specific force itself, per axis (a hand's tremor).
  void Add(const Vector3& direction, double shake_mps2 = 0.0) {
    double force[3] = {options_.gravity_mps2 * direction[0], options_.gravity_mps2 * direction[1],
                       options_.gravity_mps2 * direction[2]};
    if (shake_mps2 > 0.0)
      for (double& f : force) f += shake_mps2 * random_->StandardNormal();
    double actual_raw[3];
    TriadRawOutput(options_.truth.data(), force, actual_raw);
    double measured[3];
    const double elapsed_s = static_cast<double>(log_->size()) / options_.rate_hz;
    for (int k = 0; k < 3; ++k) {
      measured[k] =
          actual_raw[k] + noise_scale_ * options_.noise_stddev[k] * random_->StandardNormal();
      if (options_.vibration_hz > 0.0) {
        measured[k] +=
            options_.vibration_counts[k] *
            std::sin(2.0 * M_PI * options_.vibration_hz * elapsed_s + vibration_phase_[k]);
      }
      if (options_.round_to_counts) measured[k] = std::round(measured[k]);
    }
    const double t_s = options_.start_s + elapsed_s;
    log_->Add(t_s, measured[0], measured[1], measured[2]);
    const GyroscopeSimulationOptions& gyroscope = options_.gyroscope;
    if (!gyroscope.enabled) return;
    double raw[3];
    const Vector3 rate = {rate_[0] + earth_[0], rate_[1] + earth_[1], rate_[2] + earth_[2]};
    GyroscopeRawWithEffects(gyroscope.truth.data(), gyroscope.offset.data(),
                            gyroscope.effects.data(), rate.data(), force, raw);
    Vector3 noise;
    for (int k = 0; k < 3; ++k)
      noise[k] = noise_scale_ * gyroscope.noise_stddev[k] * random_->StandardNormal();
    if (delayed_) {
      // The output's own terms (models/gyroscope_effect.h's kOutput stage) need the output's
      // change in time: the samples are finished once the whole log is there (Finish).
      aligned_.push_back({raw[0], raw[1], raw[2]});
      noise_.push_back(noise);
      force_.push_back({force[0], force[1], force[2]});
      log_->gyroscope.push_back({0.0, 0.0, 0.0});
      return;
    }
    for (int k = 0; k < 3; ++k) {
      raw[k] += noise[k];
      if (gyroscope.round_to_counts) raw[k] = std::round(raw[k]);
    }
    log_->gyroscope.push_back({raw[0], raw[1], raw[2]});
  }
  // The gyroscope's samples with the output stage's terms: u = u_aligned - shift, the shift at
  // the aligned output's rate of change (central differences), then the noise.
  void Finish() {
    if (!delayed_) return;
    const int count = static_cast<int>(aligned_.size());
    for (int j = 0; j < count; ++j) {
      const Vector3 output_rate = GyroscopeOutputRate(log_->timestamp_s, aligned_, j);
      GyroscopeSampleContext<double> context;
      context.specific_force = force_[j].data();
      context.output_rate = output_rate.data();
      GyroscopeRateTerms<double> terms;
      terms.output_shift.fill(0.0);
      ApplyGyroscopeEffects<GyroscopeEffectStage::kOutput>(options_.gyroscope.effects.data(),
                                                           context, &terms);
      for (int k = 0; k < 3; ++k) {
        double raw = aligned_[j][k] - terms.output_shift[k] + noise_[j][k];
        if (options_.gyroscope.round_to_counts) raw = std::round(raw);
        log_->gyroscope[j][k] = raw;
      }
    }
  }
  // The body's angular rate (rad/s) for the samples that follow.
  void SetRate(const Vector3& rate) { rate_ = rate; }
  // The Earth's rate in the body (rad/s), added to the body's own for the samples that follow.
  void SetEarth(const Vector3& earth) { earth_ = earth; }
  int size() const { return static_cast<int>(log_->size()); }

 private:
  const TriadLogSimulationOptions& options_;
  RandomSource* random_;
  TriadLog* log_;
  double noise_scale_ = 1.0;
  std::array<double, 3> vibration_phase_{};
  const bool delayed_ =
      options_.gyroscope.enabled &&
      GyroscopeStageActive(options_.gyroscope.effects.data(), GyroscopeEffectStage::kOutput);
  std::vector<Vector3> aligned_, noise_, force_;
  Vector3 rate_{};
  Vector3 earth_{};
};

// The Earth's rate in a body whose up direction is `up` and whose horizontal reference (unit,
// normal to up) is `level`.
Vector3 EarthRateInBody(const GyroscopeSimulationOptions& gyroscope, const Vector3& up,
                        const Vector3& level) {
  constexpr double kEarthRate = 7.2921159e-5;
  const double latitude = gyroscope.latitude_deg * M_PI / 180.0;
  const double vertical = kEarthRate * std::sin(latitude);
  const double horizontal = kEarthRate * std::cos(latitude);
  return {vertical * up[0] + horizontal * level[0], vertical * up[1] + horizontal * level[1],
          vertical * up[2] + horizontal * level[2]};
}

}  // namespace

TriadSession SimulateTriadSession(const TriadLogSimulationOptions& options,
                                  const std::vector<TriadHold>& holds, RandomSource* random) {
  TriadSession session;
  SampleWriter writer(options, random, &session.log);
  const int turn_samples = static_cast<int>(std::lround(options.turn_s * options.rate_hz));
  for (size_t p = 0; p < holds.size(); ++p) {
    const Vector3& direction = holds[p].direction;
    TriadHoldSamples samples;
    samples.start = writer.size();
    const int hold_samples = static_cast<int>(std::lround(holds[p].duration_s * options.rate_hz));
    writer.SetNoiseScale(holds[p].noise_scale);
    // The hold's horizontal reference for the Earth's rate: a random azimuth about up.
    Vector3 level{};
    const bool earth = options.gyroscope.enabled && options.gyroscope.earth_rate;
    if (earth) {
      const Vector3 seed =
          std::abs(direction[0]) < 0.6 ? Vector3{1.0, 0.0, 0.0} : Vector3{0.0, 1.0, 0.0};
      Vector3 east = Cross(direction, seed);
      const double norm = std::sqrt(Dot(east, east));
      for (double& v : east) v /= norm;
      const Vector3 north = Cross(east, direction);
      const double azimuth = 2.0 * M_PI * random->Uniform();
      for (int k = 0; k < 3; ++k)
        level[k] = std::cos(azimuth) * north[k] + std::sin(azimuth) * east[k];
      writer.SetEarth(EarthRateInBody(options.gyroscope, direction, level));
    }
    for (int i = 0; i < hold_samples; ++i) writer.Add(direction);
    samples.end = writer.size() - 1;
    session.holds.push_back(samples);
    if (p + 1 == holds.size()) break;
    const Vector3& next = holds[p + 1].direction;
    const Vector3 axis = TurnAxis(direction, next);
    const double angle_rad = std::atan2(
        std::sqrt(Dot(Cross(direction, next), Cross(direction, next))), Dot(direction, next));
    // The yaw of the turn (the gyroscope's alone: it leaves the gravity direction's path as is).
    const double yaw_rad = holds[p].turn_yaw_deg * M_PI / 180.0;
    // The motion spans [start, start + motion) in samples from the hold's last one; the smooth
    // profile fills the turn; an abrupt one starts within the second sample interval and ends
    // within the last but one, so that, as a static detector leaves them, the turn's first two
    // and last two samples are at rest (turns of at least 4 samples).
    const double abrupt = turn_samples >= 4 ? options.turn_abruptness : 0.0;
    const double start = abrupt > 0.0 ? 1.0 + random->Uniform() : 0.0;
    const double motion =
        abrupt > 0.0 ? turn_samples - 2.0 + random->Uniform() - start : turn_samples;
    const double motion_s = motion / options.rate_hz;
    const double area = abrupt + (1.0 - abrupt) * 2.0 / M_PI;  // of the rate's shape over u
    // Samples strictly inside the turn: its end points are the holds' own samples.
    for (int i = 1; i < turn_samples; ++i) {
      double progress = 0.5 * (1.0 - std::cos(M_PI * i / turn_samples));
      double speed = 0.5 * M_PI / motion_s * std::sin(M_PI * i / turn_samples);
      if (abrupt > 0.0) {
        const double u = std::clamp((i - start) / motion, 0.0, 1.0);
        const bool moving = i - start > 0.0 && i - start < motion;
        progress = (abrupt * u + (1.0 - abrupt) * (1.0 - std::cos(M_PI * u)) / M_PI) / area;
        speed = moving ? (abrupt + (1.0 - abrupt) * std::sin(M_PI * u)) / (area * motion_s) : 0.0;
      }
      const Vector3 now = Rotate(direction, axis, angle_rad * progress);
      if (earth) {
        writer.SetEarth(
            EarthRateInBody(options.gyroscope, now, Rotate(level, axis, angle_rad * progress)));
      }
      writer.SetRate({yaw_rad * speed * now[0] - angle_rad * speed * axis[0],
                      yaw_rad * speed * now[1] - angle_rad * speed * axis[1],
                      yaw_rad * speed * now[2] - angle_rad * speed * axis[2]});
      writer.Add(now);
    }
    writer.SetRate({0.0, 0.0, 0.0});
  }
  writer.Finish();
  return session;
}

TriadLog SimulateSteadyTurn(const TriadLogSimulationOptions& options, double duration_s,
                            double azimuth_rate_rad_s, double elevation_rate_rad_s,
                            double shake_mps2, RandomSource* random) {
  TriadLog log;
  SampleWriter writer(options, random, &log);
  const int samples = static_cast<int>(std::lround(duration_s * options.rate_hz));
  for (int i = 0; i < samples; ++i) {
    const double t_s = i / options.rate_hz;
    const double azimuth = azimuth_rate_rad_s * t_s;
    const double elevation = elevation_rate_rad_s * t_s + 0.3;
    writer.Add({std::cos(azimuth) * std::sin(elevation), std::sin(azimuth) * std::sin(elevation),
                std::cos(elevation)},
               shake_mps2);
  }
  writer.Finish();
  return log;
}

std::vector<TriadHold> RandomSeparatedHolds(int count, double hold_s, double min_turn_deg,
                                            RandomSource* random) {
  const double max_cosine = std::cos(min_turn_deg * M_PI / 180.0);
  std::vector<TriadHold> holds;
  while (static_cast<int>(holds.size()) < count) {
    const std::array<double, 3> d = RandomPoseDirections(1, random).front();
    if (!holds.empty()) {
      const std::array<double, 3>& last = holds.back().direction;
      if (d[0] * last[0] + d[1] * last[1] + d[2] * last[2] > max_cosine) continue;
    }
    holds.push_back({d, hold_s});
  }
  return holds;
}

}  // namespace accelcal
