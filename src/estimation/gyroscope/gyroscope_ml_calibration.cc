#include "estimation/gyroscope/gyroscope_ml_calibration.h"

#include <ceres/ceres.h>
#include <ceres/covariance.h>
#include <ceres/manifold.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <set>

#include "common/format.h"
#include "common/vector3.h"
#include "estimation/statistics/chi_square.h"
#include "models/gyroscope_units.h"
#include "models/triad.h"
#include "residuals/gyroscope_residuals.h"
#include "residuals/scalar_prior_residual.h"
#include "residuals/triad_pose_residual.h"

namespace accelcal {
namespace {

// Two orthonormal vectors normal to the unit `n`.
std::array<Vector3, 2> NormalBasis(const Vector3& n) {
  const Vector3 seed = std::abs(n[0]) < 0.6 ? Vector3{1.0, 0.0, 0.0} : Vector3{0.0, 1.0, 0.0};
  Vector3 e1 = Cross(n, seed);
  const double norm = std::sqrt(Dot(e1, e1));
  for (double& v : e1) v /= norm;
  return {e1, Cross(n, e1)};
}

double Median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// The turns' sampling error for kappa^2 = 1 (rad^2, 3 x 3, in the body frame at the turn's
// end): each step's change of the rate times its step, carried to the end's body frame along the
// turn's attitude, outer products summed, less what the white noise puts there (the change of
// two independent samples). The attitude and rates from the start's gains without misalignment:
// a noise model's weights, not an estimate, so they stay fixed while the fit moves.
Eigen::Matrix3d TurnSamplingMatrix(const TriadLog& log, int first, int last,
                                   const std::vector<double>& step_s, const double* gain,
                                   const GyroscopeOffset& offset,
                                   const std::array<double, 3>& white) {
  const int count = last - first + 1;
  auto rate = [&](int j) {
    Eigen::Vector3d w;
    for (int k = 0; k < 3; ++k) w[k] = gain[k] * (log.gyroscope[first + j][k] - offset[k]);
    return w;
  };
  auto rate_at = [&](int j, double* out) {
    const Eigen::Vector3d w = rate(j);
    for (int k = 0; k < 3; ++k) out[k] = w[k];
  };
  std::vector<std::array<double, 4>> path;
  double end[9];
  IntegrateAngularRateHermite(count, rate_at, step_s, end, &path);
  const Eigen::Matrix3d end_rotation =
      Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(end);
  Eigen::Matrix3d sampling = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d noise = Eigen::Matrix3d::Zero();
  Eigen::Vector3d noise_per_step;
  for (int k = 0; k < 3; ++k) noise_per_step[k] = 2.0 * gain[k] * gain[k] * white[k];
  for (int j = 0; j + 1 < count; ++j) {
    double at[9];
    QuaternionToRotationMatrix(path[j + 1].data(), at);
    const Eigen::Matrix3d to_end =
        end_rotation.transpose() * Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(at);
    const double dt = step_s[j];
    const Eigen::Vector3d change = to_end * (rate(j + 1) - rate(j)) * dt;
    sampling += change * change.transpose();
    noise += dt * dt * to_end * noise_per_step.asDiagonal() * to_end.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(sampling - noise);
  return eigen.eigenvectors() * eigen.eigenvalues().cwiseMax(0.0).asDiagonal() *
         eigen.eigenvectors().transpose();
}

std::vector<std::string> UnknownNames(const std::vector<int>& effects) {
  std::vector<std::string> names;
  for (int i = 0; i < kGyroscopeCalibrationParameterCount; ++i)
    names.push_back(GyroscopeCalibrationParameterName(i));
  for (int c : effects) names.push_back(GyroscopeEffectCoefficientName(c));
  return names;
}

// The joint solve's unknowns, to start it again from where it started.
struct JointBlocks {
  GyroscopeParameters parameters{};
  GyroscopeOffset offset{};
  GyroscopeEffectCoefficients effects{};
  std::vector<std::array<double, 3>> directions;
  TriadParameters accelerometer{};
};

JointBlocks SnapshotBlocks(const GyroscopeMlResult* result, const TriadParameters& accelerometer) {
  return {result->parameters, result->offset, result->effects, result->directions, accelerometer};
}

void RestoreBlocks(const JointBlocks& blocks, GyroscopeMlResult* result,
                   TriadParameters* accelerometer) {
  // In place: the problem holds pointers into these arrays.
  result->parameters = blocks.parameters;
  result->offset = blocks.offset;
  result->effects = blocks.effects;
  for (size_t p = 0; p < blocks.directions.size(); ++p)
    result->directions[p] = blocks.directions[p];
  *accelerometer = blocks.accelerometer;
}

// The vertical Earth rate's place in the effect block.
constexpr int kEarth = GyroscopeEffectFirstOf<GyroscopeEarthRateEffect>();

// A gain that ended kGainCollapse times smaller or larger than it started.
constexpr double kGainCollapse = 10.0;
bool GainsCollapsed(const JointBlocks& started, const GyroscopeMlResult& result) {
  for (int k = 0; k < 3; ++k) {
    const double ratio =
        result.parameters[kGyroscopeGainX + k] / started.parameters[kGyroscopeGainX + k];
    if (!(ratio > 1.0 / kGainCollapse && ratio < kGainCollapse)) return true;
  }
  return false;
}

}  // namespace

const char* GyroscopeTurnAxisOf(int unknown, const std::vector<int>& effects_estimated) {
  // Column j of T K multiplies the reading of axis j: turns about j determine it.
  static const char* const kColumn[kGyroscopeParameterCount] = {"y", "z", "z", "x", "x",
                                                                "y", "x", "y", "z"};
  if (unknown < kGyroscopeParameterCount) return kColumn[unknown];
  if (unknown < kGyroscopeCalibrationCount) return "";
  const int e = unknown - kGyroscopeCalibrationCount;
  if (e >= static_cast<int>(effects_estimated.size())) return "";
  const int c = effects_estimated[e];
  static const char* const kAxis[3] = {"x", "y", "z"};
  const int place = GyroscopeEffectPlaceOf(c);
  if (GyroscopeEffectInfos()[GyroscopeEffectOf(c)].per_axis && place < 3) return kAxis[place];
  return "";
}

Status CalibrateGyroscopeMl(const TriadLog& log, const std::vector<StaticInterval>& intervals,
                            const TriadMlOptions& accelerometer_options,
                            const TriadMlResult& accelerometer, const GyroscopeMlOptions& options,
                            GyroscopeMlResult* result) {
  *result = GyroscopeMlResult();
  const int pose_count = static_cast<int>(intervals.size());
  if (!log.has_gyroscope() || log.gyroscope.size() != log.size()) {
    return Status::Error(
        "the log has no gyroscope samples beside the accelerometer's (one per time stamp); give "
        "a log with gyroscope columns, or imu_tk's gyroscope file with --gyro_log");
  }
  if (pose_count < 2 || static_cast<int>(accelerometer.directions.size()) != pose_count ||
      static_cast<int>(accelerometer.mean_stddev.size()) != pose_count) {
    return Status::Error(StringPrintf(
        "the gyroscope's calibration needs the accelerometer's fit of the same poses (%d "
        "intervals, %d fitted directions)",
        pose_count, static_cast<int>(accelerometer.directions.size())));
  }
  // A channel that never changes reads nothing: dead, disconnected, stuck, or another column.
  for (int k = 0; k < 3; ++k) {
    const double first = log.gyroscope[0][k];
    if (std::all_of(log.gyroscope.begin(), log.gyroscope.end(),
                    [&](const std::array<double, 3>& u) { return u[k] == first; })) {
      return Status::Error(StringPrintf(
          "the gyroscope's %c output is %.6g in every one of the log's %zu samples, through every "
          "turn: a dead, disconnected or stuck channel, or the wrong column (--columns)",
          "xyz"[k], first, log.size()));
    }
  }
  result->effects_estimated = options.effects;
  std::sort(result->effects_estimated.begin(), result->effects_estimated.end());
  result->effects_estimated.erase(
      std::unique(result->effects_estimated.begin(), result->effects_estimated.end()),
      result->effects_estimated.end());
  const std::vector<int>& estimated = result->effects_estimated;
  for (int c : estimated) {
    if (c < 0 || c >= kGyroscopeEffectCoefficientCount ||
        GyroscopeEffectInfos()[GyroscopeEffectOf(c)].not_a_candidate != nullptr) {
      return Status::Error(
          "the gyroscope's effects to estimate must be the sensor's registered coefficients (the "
          "Earth's rate is held by the fit itself: give the latitude or let its prior bound it)");
    }
  }
  const int unknown_count = kGyroscopeCalibrationCount + static_cast<int>(estimated.size());
  result->names = UnknownNames(estimated);
  for (int i = 0; i < kGyroscopeCalibrationParameterCount; ++i)
    result->units.push_back(GyroscopeParameterUnit(i, options.unit));
  for (int c : estimated) result->units.push_back(GyroscopeEffectCoefficientUnit(c));

  // The gyroscope's pose means and pooled white noise.
  std::vector<TriadPoseMean> rest(pose_count);
  // The mean over each pose of the output's rate of change (central differences, one-sided at the
  // log's ends), the context of the effects of the output's change (models/gyroscope_effect.h): 0
  // inside a still pose, not where its ends touch a turn.
  std::vector<std::array<double, 3>> rest_output_rate(pose_count, {0.0, 0.0, 0.0});
  for (int p = 0; p < pose_count; ++p) {
    const StaticInterval& interval = intervals[p];
    if (interval.start < 0 || interval.end >= static_cast<int>(log.size()) ||
        interval.end <= interval.start || (p > 0 && interval.start <= intervals[p - 1].end)) {
      return Status::Error(
          StringPrintf("pose %d: samples %d to %d are not a static interval after the one before",
                       p + 1, interval.start, interval.end));
    }
    TriadPoseMean& pose = rest[p];
    pose.sample_count = interval.sample_count();
    for (int k = 0; k < 3; ++k) {
      double sum = 0.0;
      for (int i = interval.start; i <= interval.end; ++i) sum += log.gyroscope[i][k];
      pose.mean[k] = sum / pose.sample_count;
      double squares = 0.0;
      for (int i = interval.start; i <= interval.end; ++i) {
        const double d = log.gyroscope[i][k] - pose.mean[k];
        squares += d * d;
      }
      pose.variance[k] = squares / (pose.sample_count - 1);
    }
    for (int i = interval.start; i <= interval.end; ++i) {
      const std::array<double, 3> rate = GyroscopeOutputRate(log.timestamp_s, log.gyroscope, i);
      for (int k = 0; k < 3; ++k) rest_output_rate[p][k] += rate[k] / pose.sample_count;
    }
  }
  std::array<double, 3> white = PooledWithinPoseVariance(rest);
  for (int k = 0; k < 3; ++k) {
    white[k] += options.quantisation_step * options.quantisation_step / 12.0;
    if (!(white[k] > 0.0) || !std::isfinite(white[k])) {
      return Status::Error(StringPrintf(
          "the gyroscope's axis %c does not vary within any pose (pooled variance %g): its noise "
          "cannot be estimated; if its output is quantised, say so (counts are)",
          "xyz"[k], white[k]));
    }
  }
  result->noise_variance = white;

  // The unknowns' start.
  result->parameters = options.initial;
  result->effects = options.initial_effects;
  for (int k = 0; k < 3; ++k) {
    if (options.offset_given) {
      result->offset[k] = options.initial_offset[k];
    } else {
      double sum = 0.0;
      for (const TriadPoseMean& pose : rest) sum += pose.mean[k];
      result->offset[k] = sum / pose_count;
    }
  }
  TriadParameters accelerometer_parameters = accelerometer.parameters;
  TriadEffectCoefficients accelerometer_effects = accelerometer.effects;
  result->directions = accelerometer.directions;
  const std::vector<TriadPoseMean> poses = PoseMeansOfIntervals(log, intervals, 0);
  if (static_cast<int>(poses.size()) != pose_count)
    return Status::Error("the accelerometer's pose means do not match its intervals");

  const double gain_rad_s[3] = {std::abs(options.initial[kGyroscopeGainX]),
                                std::abs(options.initial[kGyroscopeGainY]),
                                std::abs(options.initial[kGyroscopeGainZ])};
  // The Earth's rate: its vertical part in the model (given, or an unknown with a prior), the
  // rest as noise per axis: of the pose means (horizontal part) and over a turn (all of it).
  const double omega2 = kEarthRateRadPerS * kEarthRateRadPerS;
  const double earth_axis_variance = options.earth_rate_as_noise ? omega2 / 3.0 : 0.0;
  // The horizontal part's squared size h^2 ((rad/s)^2): in pose p it lies in the plane normal to
  // up, at an azimuth not known, so its covariance there is h^2 / 2 (I - n_p n_p^T).
  double earth_horizontal2 = 0.0;
  double vertical_prior_stddev = 0.0;
  double vertical_start = 0.0;
  if (options.earth_rate_as_noise && options.latitude_given) {
    const double horizontal = kEarthRateRadPerS * std::cos(options.latitude_rad);
    earth_horizontal2 = horizontal * horizontal;
    vertical_start = kEarthRateRadPerS * std::sin(options.latitude_rad);
  } else if (options.earth_rate_as_noise) {
    earth_horizontal2 = options.earth_horizontal_fixed
                            ? 3.0 * options.earth_horizontal_axis_variance
                            : 2.0 * omega2 / 3.0;  // until a first fit says more
    vertical_prior_stddev = kEarthRateRadPerS;
  }
  result->earth_vertical_prior_stddev = vertical_prior_stddev;

  // The samples at a rail: each axis's largest or smallest output when it is held for kRailRun
  // samples or more in a row, or reached in kRailVisits separate runs (a smooth turn's peak,
  // rounded, repeats its largest value a few times in one place; a saturating output returns to
  // its rail at every swing beyond the range, for a few samples each time). Then every sample at
  // it is at the rail.
  constexpr size_t kRailRun = 5;
  constexpr int kRailVisits = 5;
  constexpr double kRailNoiseSigmas = 50.0;
  std::array<std::vector<bool>, 3> at_rail;
  std::array<std::array<double, 2>, 3> rails{};
  for (int k = 0; k < 3; ++k) {
    double low = log.gyroscope[0][k], high = low;
    for (const std::array<double, 3>& u : log.gyroscope) {
      low = std::min(low, u[k]);
      high = std::max(high, u[k]);
    }
    rails[k] = {low, high};
    at_rail[k].assign(log.size(), false);
    for (double rail : {low, high}) {
      size_t run = 0;
      int visits = 0;
      bool held = false;
      for (size_t i = 0; i <= log.size(); ++i) {
        if (i < log.size() && log.gyroscope[i][k] == rail) {
          ++run;
          continue;
        }
        if (run > 0) ++visits;
        if (run >= kRailRun) held = true;
        run = 0;
      }
      // Visits count only far beyond the noise (a dead or stuck channel returns to its
      // extremes at every other sample).
      const bool far = std::abs(rail - result->offset[k]) > kRailNoiseSigmas * std::sqrt(white[k]);
      if (!held && !(visits >= kRailVisits && far)) continue;
      for (size_t i = 0; i < log.size(); ++i)
        if (log.gyroscope[i][k] == rail) at_rail[k][i] = true;
    }
  }

  // Per fitted turn, its residual's 2 x 2 covariance without the sampling term and the sampling
  // term's for kappa^2 = 1, and its residual (unwhitened) at the last fit: the sampling term's
  // method of moments.
  struct TurnNoise {
    Eigen::Matrix2d without_sampling;
    Eigen::Matrix2d sampling;
    Eigen::Vector2d residual = Eigen::Vector2d::Zero();
  };
  std::vector<TurnNoise> turn_noise;
  // Per pose, the Cholesky factor of its mean's covariance at the last fit.
  std::vector<Eigen::Matrix3d> rest_factors;

  // One fit with a bias wander of variance wander[k] (the output's unit squared) between poses
  // and the turns' sampling error of variance kappa2 (dimensionless).
  auto fit = [&](const std::array<double, 3>& wander, double kappa2) -> Status {
    turn_noise.clear();
    rest_factors.clear();
    result->rest_means.clear();
    result->rest_stddev.clear();
    result->rest_whitened.clear();
    result->turns.clear();
    result->turned_about_rad = {};
    result->clipped_turns.clear();
    result->undetermined.clear();
    result->turn_axes_to_add.clear();
    result->chi2_rest = result->chi2_turns = 0.0;
    result->accelerometer_shift_sigma = result->offset_sigma_rad_s = 0.0;
    ceres::Problem problem;
    double* gyroscope = result->parameters.data();
    double* offset = result->offset.data();
    double* effects = result->effects.data();
    effects[kEarth] = vertical_start;
    std::vector<ceres::ResidualBlockId> accelerometer_blocks, rest_blocks, turn_blocks;
    std::vector<double> pose_sigmas;
    for (int p = 0; p < pose_count; ++p) {
      double* direction = result->directions[p].data();
      if (accelerometer.effects_estimated.empty()) {
        accelerometer_blocks.push_back(problem.AddResidualBlock(
            TriadPoseResidual::Create(poses[p].mean, accelerometer.mean_stddev[p],
                                      accelerometer_options.gravity_mps2),
            nullptr, accelerometer_parameters.data(), direction));
      } else {
        TriadPoseContext context;
        context.time_s = poses[p].time_s - accelerometer.time_origin_s;
        accelerometer_blocks.push_back(problem.AddResidualBlock(
            TriadPoseResidual::CreateWithEffects(poses[p].mean, accelerometer.mean_stddev[p],
                                                 accelerometer_options.gravity_mps2, context),
            nullptr, accelerometer_parameters.data(), accelerometer_effects.data(), direction));
      }
      problem.SetManifold(direction, new ceres::SphereManifold<3>());
      // The mean's covariance (the output's unit squared): white noise and wander per axis, the
      // Earth's horizontal part in the plane normal to the pose's up direction (the
      // accelerometer's), through the gains.
      const Vector3& up = accelerometer.directions[p];
      Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
      for (int i = 0; i < 3; ++i) {
        covariance(i, i) = white[i] / rest[p].sample_count + wander[i];
        for (int j = 0; j < 3; ++j) {
          covariance(i, j) += 0.5 * earth_horizontal2 * ((i == j ? 1.0 : 0.0) - up[i] * up[j]) /
                              (gain_rad_s[i] * gain_rad_s[j]);
        }
      }
      std::array<double, 3> stddev;
      for (int k = 0; k < 3; ++k) {
        stddev[k] = std::sqrt(covariance(k, k));
        pose_sigmas.push_back(std::sqrt(white[k] / rest[p].sample_count) * gain_rad_s[k]);
      }
      const Eigen::Matrix3d factor = covariance.llt().matrixL();
      rest_factors.push_back(factor);
      const Eigen::Matrix3d inverse = factor.inverse();
      std::array<double, 9> whitening;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) whitening[3 * i + j] = inverse(i, j);
      result->rest_means.push_back(rest[p].mean);
      result->rest_stddev.push_back(stddev);
      rest_blocks.push_back(problem.AddResidualBlock(
          GyroscopeRestResidual::Create(rest[p].mean, whitening, options.gravity_mps2,
                                        rest_output_rate[p]),
          nullptr, gyroscope, offset, effects, direction));
    }
    // The vertical Earth rate (the effect block's earth_rate): held where given or not counted,
    // else its prior.
    ceres::ResidualBlockId vertical_prior = nullptr;
    if (vertical_prior_stddev > 0.0) {
      vertical_prior = problem.AddResidualBlock(
          new ScalarPrior(kGyroscopeEffectCoefficientCount, kEarth, 0.0, vertical_prior_stddev),
          nullptr, effects);
    }
    // The effect coefficients the solve moves: those estimated, and the vertical Earth rate
    // under its prior (not one of the reported unknowns: its prior's one residual counts against
    // it). The turns differentiate them all.
    std::vector<int> moving = estimated;
    if (vertical_prior != nullptr) {
      moving.push_back(kEarth);
      std::sort(moving.begin(), moving.end());
    }
    if (!accelerometer.effects_estimated.empty())
      problem.SetParameterBlockConstant(accelerometer_effects.data());

    // The turns.
    std::vector<double> turn_sigmas, turn_earth;
    for (int p = 0; p + 1 < pose_count; ++p) {
      GyroscopeMlTurn turn;
      turn.pose_before = p;
      turn.first_sample = intervals[p].end;
      turn.last_sample = intervals[p + 1].start;
      const int count = turn.last_sample - turn.first_sample + 1;
      bool clipped = false;
      for (int k = 0; k < 3 && !clipped; ++k) {
        int samples = 0;
        double rail = 0.0;
        for (int i = turn.first_sample; i <= turn.last_sample; ++i) {
          if (!at_rail[k][i]) continue;
          ++samples;
          rail = log.gyroscope[i][k];
        }
        if (samples > 0) {
          result->clipped_turns.push_back({p, k, rail, samples});
          clipped = true;
        }
      }
      if (clipped) continue;
      if (count < 2) {
        return Status::Error(
            StringPrintf("the turn from pose %d to pose %d has %d samples; a turn needs at least 2",
                         p + 1, p + 2, count));
      }
      GyroscopeTurnSamples samples;
      double weights_squared = 0.0;
      for (int i = turn.first_sample; i <= turn.last_sample; ++i) {
        samples.raw.push_back(log.gyroscope[i]);
        double force[3];
        TriadSpecificForce(accelerometer.parameters.data(), log.output[i].data(), force);
        samples.specific_force.push_back({force[0], force[1], force[2]});
        samples.output_rate.push_back(GyroscopeOutputRate(log.timestamp_s, log.gyroscope, i));
        const double before =
            i > turn.first_sample ? log.timestamp_s[i] - log.timestamp_s[i - 1] : 0.0;
        const double after =
            i < turn.last_sample ? log.timestamp_s[i + 1] - log.timestamp_s[i] : 0.0;
        if (i < turn.last_sample) {
          if (!(after > 0.0)) {
            return Status::Error(
                StringPrintf("samples %d and %d: time does not increase (%.17g then %.17g s)",
                             i + 1, i + 2, log.timestamp_s[i], log.timestamp_s[i + 1]));
          }
          samples.step_s.push_back(after);
        }
        const double weight = 0.5 * (before + after);
        weights_squared += weight * weight;
      }
      turn.duration_s = log.timestamp_s[turn.last_sample] - log.timestamp_s[turn.first_sample];
      turn.time_s = log.timestamp_s[turn.first_sample] - log.timestamp_s.front();
      // The angle's covariance (rad^2) in the body frame at the turn's end: diagonal but for the
      // sampling part, whose matrix for kappa^2 = 1 is kept apart.
      double angle_variance[3];
      for (int k = 0; k < 3; ++k) {
        angle_variance[k] =
            gain_rad_s[k] * gain_rad_s[k] *
                (white[k] * weights_squared + wander[k] * turn.duration_s * turn.duration_s) +
            earth_axis_variance * turn.duration_s * turn.duration_s;
      }
      const Eigen::Matrix3d sampling =
          TurnSamplingMatrix(log, turn.first_sample, turn.last_sample, samples.step_s, gain_rad_s,
                             result->offset, white);
      turn.sampling_measure_rad = std::sqrt(sampling.trace() / 3.0);
      for (int i = turn.first_sample; i <= turn.last_sample; ++i) {
        const double before =
            i > turn.first_sample ? log.timestamp_s[i] - log.timestamp_s[i - 1] : 0.0;
        const double after =
            i < turn.last_sample ? log.timestamp_s[i + 1] - log.timestamp_s[i] : 0.0;
        double squares = 0.0;
        for (int k = 0; k < 3; ++k) {
          const double rate = gain_rad_s[k] * (log.gyroscope[i][k] - result->offset[k]);
          squares += rate * rate;
          result->turned_about_rad[k] += 0.5 * (before + after) * std::abs(rate);
        }
        turn.peak_rate_rad_s = std::max(turn.peak_rate_rad_s, std::sqrt(squares));
      }
      turn_sigmas.push_back(std::sqrt(
          (angle_variance[0] + angle_variance[1] + angle_variance[2] + kappa2 * sampling.trace()) /
          3.0));
      turn_earth.push_back(kEarthRateRadPerS * turn.duration_s);
      turn.angle_stddev_rad = turn_sigmas.back();
      const Vector3& after = accelerometer.directions[p + 1];
      const std::array<Vector3, 2> basis = NormalBasis(after);
      // C = E^T [n]x S [n]x^T E; [n]x^T e = e x n.
      auto seen_at_after = [&](const Eigen::Matrix3d& variance) {
        Eigen::Matrix<double, 3, 2> u;
        for (int a = 0; a < 2; ++a) {
          const Vector3 ua = Cross(basis[a], after);
          u.col(a) = Eigen::Vector3d(ua[0], ua[1], ua[2]);
        }
        return Eigen::Matrix2d(u.transpose() * variance * u);
      };
      TurnNoise noise;
      noise.without_sampling = seen_at_after(
          Eigen::Vector3d(angle_variance[0], angle_variance[1], angle_variance[2]).asDiagonal());
      noise.sampling = seen_at_after(sampling);
      const Eigen::Matrix2d c = noise.without_sampling + kappa2 * noise.sampling;
      turn_noise.push_back(noise);
      const Eigen::Matrix2d w = Eigen::Matrix2d(c.llt().matrixL()).inverse();
      const std::array<double, 4> whitening = {w(0, 0), w(0, 1), w(1, 0), w(1, 1)};
      turn.angle_rad = AngleBetween(accelerometer.directions[p], after);
      result->turns.push_back(turn);
      turn_blocks.push_back(problem.AddResidualBlock(
          new GyroscopeTurnResidual(std::move(samples), basis, whitening, moving), nullptr,
          gyroscope, offset, effects, result->directions[p].data(),
          result->directions[p + 1].data()));
    }
    // The effect block: only the coefficients that move (with or without the Earth's).
    bool earth_moves = false;
    auto move_effects = [&](bool earth) {
      earth_moves = earth && vertical_prior != nullptr;
      std::vector<int> held;
      for (int c = 0; c < kGyroscopeEffectCoefficientCount; ++c) {
        if (!std::binary_search(moving.begin(), moving.end(), c) || (!earth && c == kEarth))
          held.push_back(c);
      }
      if (static_cast<int>(held.size()) == kGyroscopeEffectCoefficientCount) {
        problem.SetParameterBlockConstant(effects);
        return;
      }
      problem.SetParameterBlockVariable(effects);
      problem.SetManifold(effects, held.empty() ? nullptr
                                                : new ceres::SubsetManifold(
                                                      kGyroscopeEffectCoefficientCount, held));
    };
    move_effects(true);

    // How much the turns go about each body axis (rad, from the accelerometer's directions), and
    // how far each gyroscope output strays from its offset in them (in its noise's sigmas).
    std::array<double, 3> turned_about{}, channel_peak_sigmas{};
    for (const GyroscopeMlTurn& turn : result->turns) {
      Vector3 axis = Cross(accelerometer.directions[turn.pose_before],
                           accelerometer.directions[turn.pose_before + 1]);
      const double norm = std::sqrt(Dot(axis, axis));
      for (int k = 0; k < 3; ++k) {
        if (norm > 0.0) turned_about[k] += turn.angle_rad * std::abs(axis[k]) / norm;
        for (int i = turn.first_sample; i <= turn.last_sample; ++i) {
          channel_peak_sigmas[k] =
              std::max(channel_peak_sigmas[k],
                       std::abs(log.gyroscope[i][k] - result->offset[k]) / std::sqrt(white[k]));
        }
      }
    }

    // The gyroscope's information with everything else marginalised; its near-null directions.
    auto check_rank = [&]() -> Status {
      // The blocks that move; the vertical Earth rate's column (in the effect block's tangent
      // space, after the estimated coefficients below it) is left out: its prior bounds it.
      std::vector<double*> order = {gyroscope, offset};
      int earth_column = -1;
      if (!estimated.empty() || earth_moves) order.push_back(effects);
      if (earth_moves) {
        earth_column =
            kGyroscopeCalibrationCount +
            static_cast<int>(std::lower_bound(estimated.begin(), estimated.end(), kEarth) -
                             estimated.begin());
      }
      order.push_back(accelerometer_parameters.data());
      for (Vector3& direction : result->directions) order.push_back(direction.data());
      ceres::Problem::EvaluateOptions evaluate;
      evaluate.parameter_blocks = order;
      evaluate.num_threads = 1;
      ceres::CRSMatrix crs;
      if (!problem.Evaluate(evaluate, nullptr, nullptr, nullptr, &crs))
        return Status::Error("the gyroscope's residuals could not be evaluated");
      // Sparse: the directions couple only through consecutive turns, so the rest's
      // information is banded and its factorisation linear in the poses.
      std::vector<Eigen::Triplet<double>> entries;
      entries.reserve(crs.values.size());
      for (int row = 0; row < crs.num_rows; ++row) {
        for (int i = crs.rows[row]; i < crs.rows[row + 1]; ++i) {
          const int column = crs.cols[i];
          if (column == earth_column) continue;
          entries.emplace_back(
              row, earth_column >= 0 && column > earth_column ? column - 1 : column, crs.values[i]);
        }
      }
      const int columns = crs.num_cols - (earth_column >= 0 ? 1 : 0);
      Eigen::SparseMatrix<double> jacobian(crs.num_rows, columns);
      jacobian.setFromTriplets(entries.begin(), entries.end());
      const Eigen::SparseMatrix<double> information =
          Eigen::SparseMatrix<double>(jacobian.transpose()) * jacobian;
      const int m = unknown_count;
      const int r = static_cast<int>(information.rows()) - m;
      const Eigen::SparseMatrix<double> rest_information = information.bottomRightCorner(r, r);
      const Eigen::MatrixXd cross = Eigen::MatrixXd(information.bottomLeftCorner(r, m));
      const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> rest_solve(rest_information);
      const Eigen::MatrixXd marginal = Eigen::MatrixXd(information.topLeftCorner(m, m)) -
                                       cross.transpose() * rest_solve.solve(cross);
      std::vector<std::string> unconstrained;
      for (int i = 0; i < m; ++i)
        if (!(marginal(i, i) > 0.0)) unconstrained.push_back(result->names[i]);
      std::vector<int> weak;
      if (unconstrained.empty()) {
        const Eigen::VectorXd scale = marginal.diagonal().cwiseSqrt().cwiseInverse();
        const Eigen::MatrixXd normalised = scale.asDiagonal() * marginal * scale.asDiagonal();
        const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(normalised);
        const double largest = eigen.eigenvalues().maxCoeff();
        std::set<int> named;
        for (int k = 0; k < m; ++k) {
          if (eigen.eigenvalues()[k] > options.rank_tolerance * largest) continue;
          for (int i = 0; i < m; ++i)
            if (std::abs(eigen.eigenvectors()(i, k)) > 0.1) named.insert(i);
        }
        weak.assign(named.begin(), named.end());
      } else {
        for (int i = 0; i < m; ++i)
          if (!(marginal(i, i) > 0.0)) weak.push_back(i);
      }
      if (weak.empty()) return Status::Ok();
      std::set<std::string> axes;
      std::string names;
      for (int i : weak) {
        result->undetermined.push_back(result->names[i]);
        names += (names.empty() ? "" : ", ") + result->names[i];
        const std::string axis = GyroscopeTurnAxisOf(i, estimated);
        if (!axis.empty()) axes.insert(axis);
      }
      // An axis whose output stays at its offset through every turn, though the turns (as the
      // accelerometer sees them) go about it, is a dead channel, not a missing turn.
      std::string dead, missing;
      for (const std::string& axis : axes) {
        const int k = axis[0] - 'x';
        if (channel_peak_sigmas[k] < 10.0 && turned_about[k] > 0.5) {
          dead += (dead.empty() ? "" : " and ") + axis;
        } else {
          result->turn_axes_to_add.push_back(axis);
          missing += (missing.empty() ? "" : " and ") + axis;
        }
      }
      std::string advice;
      if (!dead.empty()) {
        advice += "; the gyroscope's " + dead +
                  " output stays within the noise of its offset through every turn, though the "
                  "turns go about that axis (the accelerometer's poses say so): a dead, "
                  "disconnected or stuck channel, or the wrong column (--columns)";
      }
      if (!missing.empty()) {
        advice += "; add turns about the sensor's " + missing +
                  " axis (tilt it so that the axis is level and turn it about that axis by 90 "
                  "degrees or more, several times, both ways)";
      }
      if (axes.empty()) advice = "; hold the sensor still in more orientations";
      return Status::Error(StringPrintf("the %d turns between the %d poses do not determine %s",
                                        static_cast<int>(result->turns.size()), pose_count,
                                        names.c_str()) +
                           advice);
    };
    ACCELCAL_RETURN_IF_ERROR(check_rank());
    // The vertical Earth rate reaches the rest poses' outputs as K^-1 T^-1 (w_v n_p), which its
    // prior (in rad/s) does not bound as the gains shrink: with an unmodelled g-sensitivity of
    // 2e-4 (rad/s)/(m/s^2) (0.1 deg/s per g, a common MEMS figure), a pose-dependent offset that
    // the noise model's turns then weigh lightly, the joint solve went to gains of 3e-12 and
    // angles of 0.3 rad, a lower cost than the sane solution, and the session was refused ("could
    // not invert"). When the gains end a factor kGainCollapse or more from where the solve
    // started (or it fails), it is done again from there with the vertical rate held at its
    // start (0, its prior's mean), then released from that solution; if the gains collapse
    // again, the held solution stands and the result says so (earth_vertical_held).
    const JointBlocks started = SnapshotBlocks(result, accelerometer_parameters);
    Status solved = SolveQuietlySparse(options.solve, &problem, &result->solver);
    result->earth_vertical_held = false;
    if (vertical_prior != nullptr && (!solved.ok() || GainsCollapsed(started, *result))) {
      RestoreBlocks(started, result, &accelerometer_parameters);
      move_effects(false);
      solved = SolveQuietlySparse(options.solve, &problem, &result->solver);
      if (solved.ok()) {
        const JointBlocks held = SnapshotBlocks(result, accelerometer_parameters);
        const SolverReport held_report = result->solver;
        move_effects(true);
        const Status released = SolveQuietlySparse(options.solve, &problem, &result->solver);
        if (!released.ok() || GainsCollapsed(started, *result)) {
          RestoreBlocks(held, result, &accelerometer_parameters);
          result->solver = held_report;
          move_effects(false);
          result->earth_vertical_held = true;
        }
      }
    }
    ACCELCAL_RETURN_IF_ERROR(check_rank());
    ACCELCAL_RETURN_IF_ERROR(solved.WithContext("the gyroscope's maximum-likelihood solve"));

    // Residuals and statistics.
    auto evaluate_blocks = [&](const std::vector<ceres::ResidualBlockId>& blocks,
                               std::vector<double>* values) {
      ceres::Problem::EvaluateOptions evaluate;
      evaluate.residual_blocks = blocks;
      evaluate.num_threads = 1;
      problem.Evaluate(evaluate, nullptr, values, nullptr, nullptr);
    };
    std::vector<double> accelerometer_residuals, rest_residuals, turn_residuals;
    evaluate_blocks(accelerometer_blocks, &accelerometer_residuals);
    evaluate_blocks(rest_blocks, &rest_residuals);
    evaluate_blocks(turn_blocks, &turn_residuals);
    double chi2_accelerometer = 0.0;
    for (double r : accelerometer_residuals) chi2_accelerometer += r * r;
    for (int p = 0; p < pose_count; ++p) {
      std::array<double, 3> whitened;
      for (int k = 0; k < 3; ++k) {
        whitened[k] = rest_residuals[3 * p + k];
        result->chi2_rest += whitened[k] * whitened[k];
      }
      result->rest_whitened.push_back(whitened);
    }
    for (size_t t = 0; t < result->turns.size(); ++t) {
      GyroscopeMlTurn& turn = result->turns[t];
      turn.whitened = {turn_residuals[2 * t], turn_residuals[2 * t + 1]};
      {
        const Eigen::Matrix2d covariance =
            turn_noise[t].without_sampling + kappa2 * turn_noise[t].sampling;
        turn_noise[t].residual = Eigen::Matrix2d(covariance.llt().matrixL()) *
                                 Eigen::Vector2d(turn.whitened[0], turn.whitened[1]);
      }
      result->chi2_turns +=
          turn.whitened[0] * turn.whitened[0] + turn.whitened[1] * turn.whitened[1];
      const auto* residual = static_cast<const GyroscopeTurnResidual*>(
          problem.GetCostFunctionForResidualBlock(turn_blocks[t]));
      double rotation[9];
      const double* at[3] = {gyroscope, offset, effects};
      residual->RotationAt(at, rotation);
      const Vector3& before = result->directions[turn.pose_before];
      const Vector3 rotated = {
          rotation[0] * before[0] + rotation[3] * before[1] + rotation[6] * before[2],
          rotation[1] * before[0] + rotation[4] * before[1] + rotation[7] * before[2],
          rotation[2] * before[0] + rotation[5] * before[1] + rotation[8] * before[2]};
      turn.residual_angle_rad = AngleBetween(rotated, result->directions[turn.pose_before + 1]);
      const double trace = rotation[0] + rotation[4] + rotation[8];
      turn.rotation_angle_rad = std::acos(std::clamp(0.5 * (trace - 1.0), -1.0, 1.0));
      const Vector3 axis = {rotation[7] - rotation[5], rotation[2] - rotation[6],
                            rotation[3] - rotation[1]};
      const double axis_norm = std::sqrt(Dot(axis, axis));
      if (axis_norm > 0.0)
        for (int k = 0; k < 3; ++k) turn.rotation_axis[k] = axis[k] / axis_norm;
    }
    const int turn_count = static_cast<int>(result->turns.size());
    result->gyroscope_degrees_of_freedom = 3 * pose_count + 2 * turn_count - unknown_count;
    // The vertical Earth rate's prior: one residual for its one unknown.
    double chi2_prior = 0.0;
    if (vertical_prior != nullptr) {
      std::vector<double> prior_residual;
      evaluate_blocks({vertical_prior}, &prior_residual);
      chi2_prior = prior_residual[0] * prior_residual[0];
    }
    result->chi2 = chi2_accelerometer + result->chi2_rest + result->chi2_turns + chi2_prior;
    // What the gyroscope adds to the accelerometer's fit alone: the joint fit nests it, so the
    // increase is chi-square on the gyroscope's residuals minus its unknowns.
    result->chi2_gyroscope = std::max(0.0, result->chi2 - accelerometer.chi2);
    result->degrees_of_freedom =
        6 * pose_count + 2 * turn_count - (kTriadParameterCount + 2 * pose_count + unknown_count);
    if (result->gyroscope_degrees_of_freedom < 1 || result->degrees_of_freedom < 1) {
      return Status::Error(StringPrintf(
          "%d poses and %d turns leave %d degrees of freedom for the gyroscope's %d unknowns; "
          "hold the sensor in more poses",
          pose_count, turn_count, result->gyroscope_degrees_of_freedom, unknown_count));
    }
    result->p_value = ChiSquareSurvival(result->chi2, result->degrees_of_freedom);
    result->gyroscope_p_value =
        ChiSquareSurvival(result->chi2_gyroscope, result->gyroscope_degrees_of_freedom);

    // The covariance, by ceres::Covariance of the whitened problem.
    ceres::Covariance::Options covariance_options;
    covariance_options.algorithm_type = ceres::SPARSE_QR;  // see triad_ml_calibration.cc
    covariance_options.num_threads = 1;
    ceres::Covariance covariance(covariance_options);
    std::vector<std::pair<const double*, const double*>> pairs = {
        {gyroscope, gyroscope},
        {gyroscope, offset},
        {offset, offset},
        {accelerometer_parameters.data(), accelerometer_parameters.data()}};
    if (!estimated.empty()) {
      pairs.push_back({gyroscope, effects});
      pairs.push_back({offset, effects});
    }
    if (!estimated.empty() || earth_moves) pairs.push_back({effects, effects});
    if (!covariance.Compute(pairs, &problem)) {
      return Status::Error(StringPrintf(
          "ceres::Covariance could not invert the information of the gyroscope's %d unknowns",
          unknown_count));
    }
    constexpr int kP = kGyroscopeParameterCount;
    constexpr int kE = kGyroscopeEffectCoefficientCount;
    Eigen::MatrixXd full = Eigen::MatrixXd::Zero(kP + 3 + kE, kP + 3 + kE);
    auto take = [&](const double* a, const double* b, int row, int col, int rows, int cols) {
      std::vector<double> block(rows * cols);
      covariance.GetCovarianceBlock(a, b, block.data());
      for (int i = 0; i < rows; ++i) {
        for (int j = 0; j < cols; ++j) {
          full(row + i, col + j) = block[i * cols + j];
          full(col + j, row + i) = block[i * cols + j];
        }
      }
    };
    take(gyroscope, gyroscope, 0, 0, kP, kP);
    take(gyroscope, offset, 0, kP, kP, 3);
    take(offset, offset, kP, kP, 3, 3);
    if (!estimated.empty()) {
      take(gyroscope, effects, 0, kP + 3, kP, kE);
      take(offset, effects, kP, kP + 3, 3, kE);
    }
    if (!estimated.empty() || earth_moves) take(effects, effects, kP + 3, kP + 3, kE, kE);
    std::vector<int> rows;
    for (int i = 0; i < kP + 3; ++i) rows.push_back(i);
    for (int c : estimated) rows.push_back(kP + 3 + c);
    result->covariance.resize(unknown_count, unknown_count);
    result->stddev.resize(unknown_count);
    for (int i = 0; i < unknown_count; ++i) {
      for (int j = 0; j < unknown_count; ++j) result->covariance(i, j) = full(rows[i], rows[j]);
      result->stddev[i] = std::sqrt(std::max(result->covariance(i, i), 0.0));
    }
    double accelerometer_block[kTriadParameterCount * kTriadParameterCount];
    covariance.GetCovarianceBlock(accelerometer_parameters.data(), accelerometer_parameters.data(),
                                  accelerometer_block);
    result->accelerometer_joint = accelerometer_parameters;
    for (int i = 0; i < kTriadParameterCount; ++i) {
      const double sigma = accelerometer.stddev[i];
      if (sigma > 0.0) {
        result->accelerometer_shift_sigma =
            std::max(result->accelerometer_shift_sigma,
                     std::abs(accelerometer_parameters[i] - accelerometer.parameters[i]) / sigma);
      }
    }

    // The Earth's rate against the noise, and its vertical part.
    result->earth_vertical_rate_rad_s = effects[kEarth];
    result->earth_vertical_rate_stddev =
        earth_moves ? std::sqrt(std::max(full(kP + 3 + kEarth, kP + 3 + kEarth), 0.0)) : 0.0;
    // The sensor's effects only, from here on: the Earth's rate is the session's world, not a
    // term of the calibration (models/gyroscope_effects/earth_rate.h).
    effects[kEarth] = 0.0;
    result->pose_mean_sigma_rad_s = Median(pose_sigmas);
    for (int k = 0; k < 3; ++k) {
      result->offset_sigma_rad_s = std::max(result->offset_sigma_rad_s,
                                            result->stddev[kGyroscopeOffsetX + k] * gain_rad_s[k]);
    }
    result->turn_angle_sigma_rad = Median(turn_sigmas);
    result->turn_earth_angle_rad = Median(turn_earth);
    return Status::Ok();
  };
  // The turns' sampling error, by the method of moments: the kappa^2 >= 0 that makes
  // sum_t e_t' (C_t + kappa^2 S_t)^-1 e_t equal its expectation, the turns' components less the
  // unknowns they determine (the 9 parameters and the effects' scale terms), at the residuals e_t
  // of the last fit; 0 when they already fit without it.
  int turn_determined = kGyroscopeParameterCount;
  for (int c : estimated)
    if (!GyroscopeEffectInfos()[GyroscopeEffectOf(c)].seen_at_rest) ++turn_determined;
  auto turn_dof = [&]() {
    return std::max(1, 2 * static_cast<int>(turn_noise.size()) - turn_determined);
  };
  auto estimate_sampling = [&]() {
    const double target = turn_dof();
    auto statistic = [&](double kappa2) {
      double sum = 0.0;
      for (const TurnNoise& noise : turn_noise) {
        const Eigen::Matrix2d covariance = noise.without_sampling + kappa2 * noise.sampling;
        sum += noise.residual.dot(covariance.ldlt().solve(noise.residual));
      }
      return sum;
    };
    if (turn_noise.empty() || statistic(0.0) <= target) return 0.0;
    // The statistic falls with kappa^2; bracket, then bisect on the log scale.
    double low = 0.0, high = 1e-6;
    while (statistic(high) > target && high < 1e12) high *= 10.0;
    for (int iteration = 0; iteration < 200; ++iteration) {
      const double middle = low > 0.0 ? std::sqrt(low * high) : 0.5 * high;
      (statistic(middle) > target ? low : high) = middle;
    }
    return 0.5 * (low + high);
  };
  // The turns' chi-square without the sampling term, and whether it rejects the noise model.
  auto turns_reject = [&]() {
    result->turns_without_sampling_p_value = ChiSquareSurvival(result->chi2_turns, turn_dof());
    return options.turn_sampling_alpha > 0.0 &&
           result->turns_without_sampling_p_value < options.turn_sampling_alpha;
  };
  // Fits with the sampling term: estimated from the residuals of the fit without it, then once
  // more from the fit with it (the residuals move little: the term reweights the turns).
  auto fit_with_sampling = [&](const std::array<double, 3>& wander) -> Status {
    if (options.turn_sampling_fixed) {
      result->turn_sampling_variance = options.turn_sampling_variance;
      return fit(wander, result->turn_sampling_variance);
    }
    result->turn_sampling_variance = 0.0;
    ACCELCAL_RETURN_IF_ERROR(fit(wander, 0.0));
    if (!turns_reject()) return Status::Ok();
    const double without_p = result->turns_without_sampling_p_value;
    // A fixed point: kappa^2 from the residuals of the fit it weights (the fit without it
    // leaves its largest residuals where the term is largest, so one step from there overshoots).
    double kappa2 = estimate_sampling();
    if (!(kappa2 > 0.0)) return Status::Ok();
    for (int iteration = 0; iteration < 8; ++iteration) {
      ACCELCAL_RETURN_IF_ERROR(fit(wander, kappa2));
      const double next = estimate_sampling();
      const bool settled = std::abs(next - kappa2) <= 0.02 * kappa2;
      kappa2 = next;
      if (settled || !(kappa2 > 0.0)) break;
    }
    ACCELCAL_RETURN_IF_ERROR(fit(wander, kappa2));
    result->turn_sampling_variance = kappa2;
    result->turns_without_sampling_p_value = without_p;
    return Status::Ok();
  };
  // Without the latitude, the horizontal part of the Earth's rate has the size the vertical part
  // leaves, Omega^2 - e^2, e from a first fit: taken at the smallest |e| within one sigma (a
  // vertical part one sigma too large would leave the poses no horizontal allowance at all, and
  // their offsets would seem to wander: 6 of 200 quiet sessions at alpha/4 measured).
  if (vertical_prior_stddev > 0.0 && !options.earth_horizontal_fixed) {
    ACCELCAL_RETURN_IF_ERROR(fit({0.0, 0.0, 0.0}, 0.0));
    const double smallest = std::max(
        0.0, std::abs(result->earth_vertical_rate_rad_s) - result->earth_vertical_rate_stddev);
    earth_horizontal2 = std::max(0.0, omega2 - smallest * smallest);
  }
  result->earth_horizontal_axis_variance = earth_horizontal2 / 3.0;
  if (options.bias_wander_fixed) {
    result->bias_wander_variance = options.bias_wander_variance;
    return fit_with_sampling(result->bias_wander_variance);
  }
  // The turns' sampling error first: turns the noise model cannot fit pull the offsets, and
  // the poses' offsets would then seem to wander.
  result->bias_wander_variance = {0.0, 0.0, 0.0};
  ACCELCAL_RETURN_IF_ERROR(fit_with_sampling(result->bias_wander_variance));
  // The rest residuals under white noise: 3 per pose, less the 3 offsets (and the g-sensitivity's
  // coefficients, which they determine too).
  int rest_unknowns = 3;
  for (int c : estimated)
    if (GyroscopeEffectInfos()[GyroscopeEffectOf(c)].seen_at_rest) ++rest_unknowns;
  const int rest_dof = std::max(1, 3 * pose_count - rest_unknowns);
  result->white_rest_p_value = ChiSquareSurvival(result->chi2_rest, rest_dof);
  const double white_rest_p_value = result->white_rest_p_value;
  bool wanders = false;
  if (result->white_rest_p_value < options.bias_wander_alpha) {
    // The poses' offsets scatter more than their white noise allows: the offset wanders (bias
    // instability, temperature). Its variance between poses by the method of moments per axis:
    // the tau^2 >= 0 that makes sum_p e_p^2 / (sigma_p^2 + tau^2) = P - 1, e_p the pose's
    // residual.
    for (int k = 0; k < 3; ++k) {
      std::vector<double> e2, s2;
      for (int p = 0; p < pose_count; ++p) {
        const double sigma = result->rest_stddev[p][k];
        const Eigen::Vector3d whitened(result->rest_whitened[p][0], result->rest_whitened[p][1],
                                       result->rest_whitened[p][2]);
        const double e = (rest_factors[p] * whitened)[k];
        e2.push_back(e * e);
        s2.push_back(sigma * sigma);
      }
      auto statistic = [&](double tau2) {
        double sum = 0.0;
        for (int p = 0; p < pose_count; ++p) sum += e2[p] / (s2[p] + tau2);
        return sum;
      };
      const double target = pose_count - 1;
      if (statistic(0.0) <= target) continue;
      double low = 0.0, high = *std::max_element(e2.begin(), e2.end()) + 1.0;
      for (int iteration = 0; iteration < 200; ++iteration) {
        const double middle = 0.5 * (low + high);
        (statistic(middle) > target ? low : high) = middle;
      }
      result->bias_wander_variance[k] = 0.5 * (low + high);
      wanders = true;
    }
  }
  if (!wanders) return Status::Ok();
  const std::array<double, 3> wander = result->bias_wander_variance;
  ACCELCAL_RETURN_IF_ERROR(fit_with_sampling(wander));
  result->white_rest_p_value = white_rest_p_value;
  return Status::Ok();
}

}  // namespace accelcal
