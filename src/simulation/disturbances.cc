#include "simulation/disturbances.h"

#include <cmath>

#include "common/format.h"

namespace accelcal {
namespace {

using nlohmann::json;

// The disturber's own random streams: the simulator's seed mixed with a constant per
// purpose (the purpose's name in ASCII, as the scenario's decoys do), so that they never
// share a draw with the simulator's noise stream or with each other.
constexpr uint64_t kStudentTSeedMix = 0x73747564656E7474ull;  // "studentt"
constexpr uint64_t kOutlierSeedMix = 0x6F75746C69657273ull;   // "outliers"

constexpr int kMaxHarmonicOrder = 20;

// One --set name with its range, written as the range reads: '(' or ')' open, '[' or ']'
// closed.
struct Setting {
  const char* name;
  double Disturbances::*member;  // nullptr: theta_harmonic_order, an int
  char low_bracket;
  double low;
  double high;
  char high_bracket;
  const char* unit;  // "" when dimensionless
  const char* meaning;
  const char* zero_means = nullptr;  // what 0, outside the range, stands for, if allowed
};

// In the order of the struct. The amplitudes' and steps' bound is the bias's
// (models/effects/bias.h); the cubic's gives c g^3 about 10 m/s^2 in the tilt test.
const Setting kSettings[] = {
    {"noise_ar1_x", &Disturbances::noise_ar1_x, '(', -0.99, 0.99, ')', "",
     "the lag-1 correlation of the x noise"},
    {"noise_ar1_y", &Disturbances::noise_ar1_y, '(', -0.99, 0.99, ')', "",
     "the lag-1 correlation of the y noise"},
    {"noise_student_t_dof", &Disturbances::noise_student_t_dof, '(', 2.0, 1000.0, ']', "",
     "the degrees of freedom of Student-t noise", "Gaussian noise"},
    {"outlier_fraction", &Disturbances::outlier_fraction, '[', 0.0, 0.2, ']', "",
     "the fraction of tilt-test samples that are outliers"},
    {"outlier_sigma", &Disturbances::outlier_sigma, '[', 0.0, 1000.0, ']', "noise sigmas",
     "an outlier's size"},
    {"theta_harmonic_order", nullptr, '[', 1.0, kMaxHarmonicOrder, ']', "",
     "the harmonic's order in the table angle"},
    {"theta_harmonic_x", &Disturbances::theta_harmonic_x, '[', -100.0, 100.0, ']', "m/s^2",
     "the x amplitude of the harmonic in the table angle"},
    {"theta_harmonic_y", &Disturbances::theta_harmonic_y, '[', -100.0, 100.0, ']', "m/s^2",
     "the y amplitude of the harmonic in the table angle"},
    {"theta_harmonic_phase", &Disturbances::theta_harmonic_phase_rad, '[', -1e3, 1e3, ']', "rad",
     "the harmonic's phase"},
    {"bias_step_at", &Disturbances::bias_step_at, '(', 0.0, 1.0, ')', "",
     "where the bias step starts, as a fraction of the test's samples"},
    {"bias_step_x", &Disturbances::bias_step_x, '[', -100.0, 100.0, ']', "m/s^2",
     "the x bias step"},
    {"bias_step_y", &Disturbances::bias_step_y, '[', -100.0, 100.0, ']', "m/s^2",
     "the y bias step"},
    {"scale_cubic_x", &Disturbances::scale_cubic_x, '[', -1e-2, 1e-2, ']', "1/(m/s^2)^2",
     "the x cubic scale term"},
    {"scale_cubic_y", &Disturbances::scale_cubic_y, '[', -1e-2, 1e-2, ']', "1/(m/s^2)^2",
     "the y cubic scale term"},
    {"bias_warmup_x", &Disturbances::bias_warmup_x, '[', -100.0, 100.0, ']', "m/s^2",
     "the x warm-up and cool-down's height"},
    {"bias_warmup_y", &Disturbances::bias_warmup_y, '[', -100.0, 100.0, ']', "m/s^2",
     "the y warm-up and cool-down's height"},
    {"bias_hysteresis_x", &Disturbances::bias_hysteresis_x, '[', -100.0, 100.0, ']', "m/s^2",
     "the x bias turning up minus turning down"},
    {"bias_hysteresis_y", &Disturbances::bias_hysteresis_y, '[', -100.0, 100.0, ']', "m/s^2",
     "the y bias turning up minus turning down"},
    {"position_offset_at", &Disturbances::position_offset_at, '(', 0.0, 1.0, ')', "",
     "the sample in the held position that is offset, as a fraction of the test's samples"},
    {"position_offset_x", &Disturbances::position_offset_x, '[', -100.0, 100.0, ']', "m/s^2",
     "the x offset of one held position"},
    {"position_offset_y", &Disturbances::position_offset_y, '[', -100.0, 100.0, ']', "m/s^2",
     "the y offset of one held position"},
    {"full_scale_x", &Disturbances::full_scale_x, '(', 0.0, 1000.0, ']', "m/s^2",
     "the force along x beyond which x clips", "no clipping"},
    {"full_scale_y", &Disturbances::full_scale_y, '(', 0.0, 1000.0, ']', "m/s^2",
     "the force along y beyond which y clips", "no clipping"},
};

const Setting* FindSetting(const std::string& name) {
  for (const Setting& setting : kSettings) {
    if (name == setting.name) return &setting;
  }
  return nullptr;
}

double Value(const Setting& setting, const Disturbances& disturbances) {
  return setting.member != nullptr ? disturbances.*setting.member
                                   : disturbances.theta_harmonic_order;
}

// Gamma(shape, 1) for shape >= 1 (Marsaglia and Tsang, ACM TOMS 26(3), 2000): exact, and
// built on RandomSource's normals and uniforms, so the same on any machine.
double StandardGamma(double shape, RandomSource* random) {
  const double d = shape - 1.0 / 3.0;
  const double c = 1.0 / std::sqrt(9.0 * d);
  for (;;) {
    double x;
    double v;
    do {
      x = random->StandardNormal();
      v = 1.0 + c * x;
    } while (v <= 0.0);
    v = v * v * v;
    const double u = random->Uniform();
    if (u < 1.0 - 0.0331 * x * x * x * x) return d * v;
    if (std::log(u) < 0.5 * x * x + d * (1.0 - v + std::log(v))) return d * v;
  }
}

}  // namespace

bool Disturbances::any() const {
  return noise_ar1_x != 0.0 || noise_ar1_y != 0.0 || noise_student_t_dof != 0.0 ||
         outlier_fraction != 0.0 || theta_harmonic_x != 0.0 || theta_harmonic_y != 0.0 ||
         bias_step_x != 0.0 || bias_step_y != 0.0 || scale_cubic_x != 0.0 || scale_cubic_y != 0.0 ||
         bias_warmup_x != 0.0 || bias_warmup_y != 0.0 || bias_hysteresis_x != 0.0 ||
         bias_hysteresis_y != 0.0 || position_offset_x != 0.0 || position_offset_y != 0.0 ||
         full_scale_x != 0.0 || full_scale_y != 0.0;
}

const std::vector<std::string>& DisturbanceNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> list;
    for (const Setting& setting : kSettings) list.push_back(setting.name);
    return list;
  }();
  return names;
}

bool IsDisturbanceName(const std::string& name) { return FindSetting(name) != nullptr; }

Status SetDisturbance(const std::string& name, double value, Disturbances* disturbances) {
  const Setting* setting = FindSetting(name);
  if (setting == nullptr) return Status::Error("'" + name + "' is not a disturbance");
  if (setting->member != nullptr) {
    disturbances->*setting->member = value;
    return Status::Ok();
  }
  // Checked before the conversion: a double outside int's range does not convert.
  if (!(value >= 1.0 && value <= kMaxHarmonicOrder && value == std::floor(value))) {
    return Status::Error(StringPrintf("%s = %.6g must be a whole number from 1 to %d", name.c_str(),
                                      value, kMaxHarmonicOrder));
  }
  disturbances->theta_harmonic_order = static_cast<int>(value);
  return Status::Ok();
}

Status ValidateDisturbances(const Disturbances& disturbances) {
  for (const Setting& setting : kSettings) {
    const double value = Value(setting, disturbances);
    if (setting.zero_means != nullptr && value == 0.0) continue;
    const bool above_low = setting.low_bracket == '(' ? value > setting.low : value >= setting.low;
    const bool below_high =
        setting.high_bracket == ')' ? value < setting.high : value <= setting.high;
    if (std::isfinite(value) && above_low && below_high) continue;
    const std::string zero =
        setting.zero_means != nullptr ? std::string(", or 0 for ") + setting.zero_means : "";
    return Status::Error(StringPrintf("%s = %.6g is outside %c%.6g, %.6g%c%s%s%s: %s", setting.name,
                                      value, setting.low_bracket, setting.low, setting.high,
                                      setting.high_bracket, *setting.unit != '\0' ? " " : "",
                                      setting.unit, zero.c_str(), setting.meaning));
  }
  return Status::Ok();
}

json DisturbancesJson(const Disturbances& disturbances) {
  json values = json::object();
  for (const Setting& setting : kSettings) {
    if (setting.member != nullptr) {
      values[setting.name] = disturbances.*setting.member;
    } else {
      values[setting.name] = disturbances.theta_harmonic_order;
    }
  }
  return values;
}

SampleDisturber::SampleDisturber(const Disturbances& disturbances, Phase phase, int sample_count,
                                 double sigma_x, double sigma_y, uint64_t seed, uint64_t stream,
                                 const std::vector<double>& theta_rad)
    : in_tilt_test_(phase == Phase::kCalibrationTest),
      student_t_dof_(disturbances.noise_student_t_dof),
      outlier_fraction_(in_tilt_test_ ? disturbances.outlier_fraction : 0.0),
      outlier_sigma_(disturbances.outlier_sigma),
      harmonic_order_(disturbances.theta_harmonic_order),
      harmonic_phase_rad_(disturbances.theta_harmonic_phase_rad),
      step_sample_(static_cast<int>(std::floor(disturbances.bias_step_at * sample_count))),
      needs_forces_(disturbances.scale_cubic_x != 0.0 || disturbances.scale_cubic_y != 0.0 ||
                    disturbances.full_scale_x != 0.0 || disturbances.full_scale_y != 0.0),
      sample_count_(sample_count),
      student_t_random_(seed ^ kStudentTSeedMix, stream),
      outlier_random_(seed ^ kOutlierSeedMix, stream) {
  const auto make_axis = [&](double sigma, double rho, double harmonic, double step, double cubic,
                             double warmup, double hysteresis, double offset, double full_scale) {
    Axis axis;
    axis.sigma = sigma;
    axis.rho = rho;
    axis.innovation_sigma = std::sqrt(1.0 - rho * rho) * sigma;
    // The harmonic, the step, the warm-up, the hysteresis and the position's offset belong to
    // the table's test, not to the run.
    axis.harmonic_amplitude = in_tilt_test_ ? harmonic : 0.0;
    axis.step_size = in_tilt_test_ ? step : 0.0;
    axis.scale_cubic = cubic;
    axis.warmup = in_tilt_test_ ? warmup : 0.0;
    axis.hysteresis = in_tilt_test_ ? hysteresis : 0.0;
    axis.position_offset = in_tilt_test_ ? offset : 0.0;
    axis.full_scale = full_scale;
    return axis;
  };
  const Disturbances& d = disturbances;
  x_ = make_axis(sigma_x, d.noise_ar1_x, d.theta_harmonic_x, d.bias_step_x, d.scale_cubic_x,
                 d.bias_warmup_x, d.bias_hysteresis_x, d.position_offset_x, d.full_scale_x);
  y_ = make_axis(sigma_y, d.noise_ar1_y, d.theta_harmonic_y, d.bias_step_y, d.scale_cubic_y,
                 d.bias_warmup_y, d.bias_hysteresis_y, d.position_offset_y, d.full_scale_y);
  if (x_.warmup != 0.0 || y_.warmup != 0.0) {
    for (int i = 0; i < sample_count; ++i) warmup_mean_ += WarmUp(i) / sample_count;
  }
  if (x_.hysteresis != 0.0 || y_.hysteresis != 0.0) turn_direction_ = TurnDirection(theta_rad);
  if (x_.position_offset != 0.0 || y_.position_offset != 0.0) {
    const int sample = static_cast<int>(std::floor(d.position_offset_at * sample_count));
    for (const StaticPosition& held : StaticPositions(theta_rad)) {
      if (sample >= held.begin && sample < held.end) offset_position_ = held;
    }
  }
}

double SampleDisturber::WarmUp(int sample_index) const {
  return sample_count_ > 1 ? std::sin(M_PI * sample_index / (sample_count_ - 1)) : 0.0;
}

double SampleDisturber::UnitInnovation(double normal) {
  if (student_t_dof_ == 0.0) return normal;
  // A Student-t is z / sqrt(V / nu) with V a chi-square of nu degrees of freedom, i.e.
  // 2 Gamma(nu / 2); its variance nu / (nu - 2) is brought to one. The numerator is the
  // simulator's own draw, so a t-distributed sample keeps the sign of its Gaussian one.
  const double chi_square = 2.0 * StandardGamma(0.5 * student_t_dof_, &student_t_random_);
  return normal * std::sqrt((student_t_dof_ - 2.0) / chi_square);
}

void SampleDisturber::ApplyToAxis(int sample_index, double theta_reported_rad,
                                  double force_along_axis, double normal, Axis* axis,
                                  double* output) {
  const double innovation = UnitInnovation(normal);
  // Without a correlation the noise is sigma w exactly, as the simulator's own sigma z: the
  // recursion is skipped rather than trusted to reproduce it to the bit.
  const double noise = axis->rho != 0.0 && axis->started
                           ? axis->rho * axis->previous_noise + axis->innovation_sigma * innovation
                           : axis->sigma * innovation;
  axis->started = true;
  axis->previous_noise = noise;
  *output += noise;
  if (outlier_fraction_ > 0.0) {
    // Two draws per sample whether it is hit or not: which samples are hit then does not
    // depend on the outliers' signs, and a larger fraction hits a superset of samples.
    const bool hit = outlier_random_.Uniform() < outlier_fraction_;
    const double sign = outlier_random_.Uniform() < 0.5 ? -1.0 : 1.0;
    if (hit) {
      *output += sign * outlier_sigma_ * axis->sigma;
      axis->outlier_indices.push_back(sample_index);
    }
  }
  if (axis->harmonic_amplitude != 0.0) {
    *output += axis->harmonic_amplitude *
               std::sin(harmonic_order_ * theta_reported_rad + harmonic_phase_rad_);
  }
  if (axis->step_size != 0.0 && sample_index >= step_sample_) *output += axis->step_size;
  if (axis->scale_cubic != 0.0) {
    *output += axis->scale_cubic * force_along_axis * force_along_axis * force_along_axis;
  }
  if (axis->warmup != 0.0) *output += axis->warmup * (WarmUp(sample_index) - warmup_mean_);
  if (axis->hysteresis != 0.0) *output += 0.5 * axis->hysteresis * turn_direction_[sample_index];
  if (axis->position_offset != 0.0 && sample_index >= offset_position_.begin &&
      sample_index < offset_position_.end) {
    *output += axis->position_offset;
  }
  if (axis->full_scale != 0.0 && std::abs(force_along_axis) > axis->full_scale) {
    *output -= std::copysign(std::abs(force_along_axis) - axis->full_scale, force_along_axis);
  }
}

void SampleDisturber::Apply(int sample_index, double theta_reported_rad, double force_along_x,
                            double force_along_y, double normal_x, double normal_y,
                            double* output_x, double* output_y) {
  // x before y: the order in which the Student-t and outlier streams are drawn.
  ApplyToAxis(sample_index, theta_reported_rad, force_along_x, normal_x, &x_, output_x);
  ApplyToAxis(sample_index, theta_reported_rad, force_along_y, normal_y, &y_, output_y);
}

}  // namespace accelcal
