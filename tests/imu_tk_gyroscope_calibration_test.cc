// imu_tk's gyroscope calibration (estimation/gyroscope/imu_tk_gyroscope_calibration.h) against what
// imu_tk printed on its own Xsens pair of logs (issue 32), and on simulated sessions whose
// gyroscope errors are known; the model and imu_tk's integration (models/gyroscope.h) and the
// residual (residuals/imu_tk_gyroscope_residual.h) on their own.

#include "estimation/gyroscope/imu_tk_gyroscope_calibration.h"

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "common/format.h"
#include "estimation/triad/imu_tk_calibration.h"
#include "io/imu_log.h"
#include "models/gyroscope.h"
#include "models/triad.h"
#include "residuals/imu_tk_gyroscope_residual.h"
#include "simulation/random.h"
#include "simulation/triad_simulator.h"
#include "test_support.h"

namespace accelcal {
namespace {

// ---------------------------------------------------------------------------------------------
// imu_tk's Xsens example (apps/test_imu_calib.cpp): g = 9.81744, a rest of 50 s, accelerometer
// offsets from 32768, gyroscope gains from 1/6258 (rad/s)/count, the gyroscope's offset from the
// rest and not estimated, the step from the time stamps.

class ImuTkGyroscopeXsens : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const std::string dir = testing::ImuTkDataDir();
    if (dir.empty()) return;
    log_ = new TriadLog;
    accelerometer_ = new ImuTkResult;
    result_ = new ImuTkGyroscopeResult;
    ImuLogReadOptions read_options;
    read_options.gyroscope_path = dir + "/xsens_gyro.mat";
    status_ = ReadImuLog(dir + "/xsens_acc.mat", read_options, log_);
    if (!status_.ok()) return;
    ImuTkOptions options;
    options.gravity_mps2 = 9.81744;
    options.init_rest_s = 50.0;
    options.initial = TriadParametersWithOffset(32768.0, 32768.0, 32768.0);
    status_ = CalibrateImuTk(*log_, options, accelerometer_);
    if (!status_.ok()) return;
    ImuTkGyroscopeOptions gyroscope_options;
    gyroscope_options.initial =
        GyroscopeParametersWithGain(1.0 / 6258.0, 1.0 / 6258.0, 1.0 / 6258.0);
    status_ = CalibrateImuTkGyroscope(*log_, *accelerometer_, gyroscope_options, result_);
  }
  static void TearDownTestSuite() {
    delete log_;
    delete accelerometer_;
    delete result_;
  }
  void SetUp() override {
    if (log_ == nullptr) {
      GTEST_SKIP() << "imu_tk data not found: set ACCELCAL_IMU_TK_DATA or put it in "
                      "../shared/data/imu_tk-xsens";
    }
    ASSERT_TRUE(status_.ok()) << status_.message();
  }
  static TriadLog* log_;
  static ImuTkResult* accelerometer_;
  static ImuTkGyroscopeResult* result_;
  static Status status_;
};
TriadLog* ImuTkGyroscopeXsens::log_ = nullptr;
ImuTkResult* ImuTkGyroscopeXsens::accelerometer_ = nullptr;
ImuTkGyroscopeResult* ImuTkGyroscopeXsens::result_ = nullptr;
Status ImuTkGyroscopeXsens::status_;

// imu_tk's stream prints 6 significant digits: "%g".
std::string Printed(double value) { return StringPrintf("%g", value); }

TEST_F(ImuTkGyroscopeXsens, ReadsTheGyroscopeBesideTheAccelerometer) {
  ASSERT_EQ(log_->gyroscope.size(), 51175u);
  ASSERT_EQ(log_->output.size(), 51175u);
}

TEST_F(ImuTkGyroscopeXsens, ReproducesImuTksPrintedResidual) {
  EXPECT_EQ(Printed(result_->cost), "0.00150696");
  EXPECT_LT(result_->cost, result_->initial_cost);
}

TEST_F(ImuTkGyroscopeXsens, ReproducesImuTksPrintedMisalignmentMatrix) {
  const char* printed[9] = {"1",          "0.00593634", "0.00111101", "0.00808812", "1",
                            "-0.0535569", "0.0253067",  "-0.0025513", "1"};
  const std::array<double, 9> matrix = result_->misalignment_matrix();
  for (int i = 0; i < 9; ++i) EXPECT_EQ(Printed(matrix[i]), printed[i]) << "element " << i;
  // The six angles with imu_tk's signs (its misYZ() ... misYX() return them).
  const GyroscopeParameters& p = result_->parameters;
  EXPECT_EQ(Printed(p[kGyroscopeMisalignmentYz]), "-0.00593634");
  EXPECT_EQ(Printed(p[kGyroscopeMisalignmentZy]), "0.00111101");
  EXPECT_EQ(Printed(p[kGyroscopeMisalignmentZx]), "0.0535569");
  EXPECT_EQ(Printed(p[kGyroscopeMisalignmentXz]), "0.00808812");
  EXPECT_EQ(Printed(p[kGyroscopeMisalignmentXy]), "-0.0253067");
  EXPECT_EQ(Printed(p[kGyroscopeMisalignmentYx]), "-0.0025513");
}

TEST_F(ImuTkGyroscopeXsens, ReproducesImuTksPrintedScaleMatrixAndInverseScaleFactors) {
  EXPECT_EQ(Printed(result_->parameters[kGyroscopeGainX]), "0.000209295");
  EXPECT_EQ(Printed(result_->parameters[kGyroscopeGainY]), "0.000209899");
  EXPECT_EQ(Printed(result_->parameters[kGyroscopeGainZ]), "0.000209483");
  const std::array<double, 3> inverse = result_->inverse_gains();
  EXPECT_EQ(Printed(inverse[0]), "4777.96");
  EXPECT_EQ(Printed(inverse[1]), "4764.21");
  EXPECT_EQ(Printed(inverse[2]), "4773.66");
}

TEST_F(ImuTkGyroscopeXsens, ReproducesImuTksPrintedBiasVector) {
  EXPECT_EQ(Printed(result_->offset[0]), "32777.1");
  EXPECT_EQ(Printed(result_->offset[1]), "32459.8");
  EXPECT_EQ(Printed(result_->offset[2]), "32511.8");
}

TEST_F(ImuTkGyroscopeXsens, AgreesWithTheDatasheetToWithinItsTolerance) {
  // Xsens: 4778, 4758, 4766 counts per rad/s; imu_tk's are within 0.2% of them.
  const double datasheet[3] = {4778.0, 4758.0, 4766.0};
  const std::array<double, 3> inverse = result_->inverse_gains();
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(inverse[k] / datasheet[k], 1.0, 2e-3) << "axis " << k;
}

TEST_F(ImuTkGyroscopeXsens, IntegratesEveryTurnBetweenTheAccelerometersIntervals) {
  // k = 6: 38 intervals, all of at least 100 samples, so 37 turns.
  EXPECT_EQ(accelerometer_->best().multiplier, 6);
  ASSERT_EQ(accelerometer_->intervals.size(), 38u);
  ASSERT_EQ(result_->turns.size(), 37u);
  EXPECT_EQ(result_->rest_end, accelerometer_->rest_end);
  for (size_t p = 0; p < result_->turns.size(); ++p) {
    const ImuTkGyroscopeTurn& turn = result_->turns[p];
    EXPECT_EQ(turn.first_sample, accelerometer_->intervals[p].end);
    EXPECT_EQ(turn.last_sample, accelerometer_->intervals[p + 1].start - 1);
    // A hand's turn: tens of degrees; the calibrated gyroscope misses it by a fraction of one.
    EXPECT_GT(turn.turn_angle_rad, 0.1) << "turn " << p;
    EXPECT_LT(turn.residual_angle_rad, 0.02) << "turn " << p;
  }
}

// ---------------------------------------------------------------------------------------------
// The model and imu_tk's integration.

GyroscopeParameters GyroscopeTruth() {
  GyroscopeParameters truth = GyroscopeParametersWithGain(1.0 / 4778.0, 1.0 / 4758.0, 1.0 / 4766.0);
  truth[kGyroscopeMisalignmentYz] = -0.006;
  truth[kGyroscopeMisalignmentZy] = 0.0011;
  truth[kGyroscopeMisalignmentZx] = 0.05;
  truth[kGyroscopeMisalignmentXz] = 0.008;
  truth[kGyroscopeMisalignmentXy] = -0.025;
  truth[kGyroscopeMisalignmentYx] = -0.0026;
  return truth;
}
const GyroscopeOffset kGyroscopeOffset = {32768.0, 32466.0, 32485.0};

TEST(GyroscopeModel, RawOutputInvertsTheAngularRate) {
  const GyroscopeParameters truth = GyroscopeTruth();
  const double rate[3] = {0.3, -1.2, 2.5};
  double raw[3];
  GyroscopeRawOutput(truth.data(), kGyroscopeOffset.data(), rate, raw);
  double back[3];
  GyroscopeAngularRate(truth.data(), kGyroscopeOffset.data(), raw, back);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(back[k], rate[k], 1e-13);
}

TEST(GyroscopeModel, HasImuTksMatrixLayoutAndSigns) {
  // One count above the offset on y alone: w = T K e_y = gain_y (column 1 of T).
  const GyroscopeParameters truth = GyroscopeTruth();
  const double raw[3] = {kGyroscopeOffset[0], kGyroscopeOffset[1] + 1.0, kGyroscopeOffset[2]};
  double rate[3];
  GyroscopeAngularRate(truth.data(), kGyroscopeOffset.data(), raw, rate);
  const double gain_y = truth[kGyroscopeGainY];
  EXPECT_DOUBLE_EQ(rate[0], -truth[kGyroscopeMisalignmentYz] * gain_y);
  EXPECT_DOUBLE_EQ(rate[1], gain_y);
  EXPECT_DOUBLE_EQ(rate[2], truth[kGyroscopeMisalignmentYx] * gain_y);
}

TEST(GyroscopeModel, CompilesForCeresJets) {
  using Jet = ceres::Jet<double, kGyroscopeParameterCount>;
  const GyroscopeParameters truth = GyroscopeTruth();
  Jet parameters[kGyroscopeParameterCount];
  for (int p = 0; p < kGyroscopeParameterCount; ++p) parameters[p] = Jet(truth[p], p);
  const Jet offset[3] = {Jet(kGyroscopeOffset[0]), Jet(kGyroscopeOffset[1]),
                         Jet(kGyroscopeOffset[2])};
  const double raw[3] = {33000.0, 32000.0, 34000.0};
  Jet rate[3];
  GyroscopeAngularRate(parameters, offset, raw, rate);
  // d w_z / d xy = -gain_x (u_x - b_x); d w_x / d gain_x = u_x - b_x.
  EXPECT_DOUBLE_EQ(rate[2].v[kGyroscopeMisalignmentXy],
                   -truth[kGyroscopeGainX] * (raw[0] - kGyroscopeOffset[0]));
  EXPECT_DOUBLE_EQ(rate[0].v[kGyroscopeGainX], raw[0] - kGyroscopeOffset[0]);
}

// R for a rotation by `angle` about the unit `axis` (Rodrigues), row-major.
std::array<double, 9> AxisAngle(const std::array<double, 3>& axis, double angle) {
  const double c = std::cos(angle), s = std::sin(angle), v = 1.0 - c;
  const double x = axis[0], y = axis[1], z = axis[2];
  return {c + x * x * v,     x * y * v - z * s, x * z * v + y * s, y * x * v + z * s, c + y * y * v,
          y * z * v - x * s, z * x * v - y * s, z * y * v + x * s, c + z * z * v};
}

// The angle of the rotation between two rotation matrices (row-major): |vee(A^T B)| = sin(angle).
double AngleBetweenRotations(const double* a, const double* b) {
  double m[9];
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      m[3 * i + j] = a[i] * b[j] + a[3 + i] * b[3 + j] + a[6 + i] * b[6 + j];
    }
  }
  const double v[3] = {m[7] - m[5], m[2] - m[6], m[3] - m[1]};
  return std::asin(0.5 * std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
}

TEST(GyroscopeIntegration, AConstantRateGivesTheExactRotation) {
  // Body rate w about a fixed axis for 2 s in 200 steps: R = exp([w] t), the body's attitude in
  // its first frame (its x axis, R e_x, turns towards +y for a rate about +z). RK4 is exact for a
  // constant rate up to (|w| dt)^5 / 5! per step: 200 steps of 0.009 rad leave about 1e-11.
  const std::array<double, 3> axis = {2.0 / 7.0, -3.0 / 7.0, 6.0 / 7.0};
  const double speed = 0.9;  // rad/s
  const std::vector<double> steps(200, 0.01);
  double rotation[9];
  IntegrateAngularRate(
      201,
      [&](int, double* rate) {
        for (int k = 0; k < 3; ++k) rate[k] = speed * axis[k];
      },
      steps, rotation);
  const std::array<double, 9> expected = AxisAngle(axis, speed * 2.0);
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(rotation[i], expected[i], 1e-10) << i;
}

TEST(GyroscopeIntegration, IsExactForARateRisingLinearlyAboutOneAxis) {
  // w(t) = 0.4 t rad/s^2 about a fixed axis for 3 s: the rotation is by 0.2 t^2 = 1.8 rad. About
  // a fixed axis imu_tk's step adds dt (w0 + w1) / 2, exact for a linear rate (the middle rate
  // taken as the later one's, say, would add dt (w0 + 5 w1) / 6 and turn 0.02 rad too far).
  const std::array<double, 3> axis = {-0.48, 0.6, 0.64};
  const double dt = 0.01;
  double rotation[9];
  IntegrateAngularRate(
      301,
      [&](int j, double* rate) {
        for (int k = 0; k < 3; ++k) rate[k] = 0.4 * j * dt * axis[k];
      },
      std::vector<double>(300, dt), rotation);
  const std::array<double, 9> expected = AxisAngle(axis, 1.8);
  EXPECT_LT(AngleBetweenRotations(rotation, expected.data()), 1e-10);
}

TEST(GyroscopeIntegration, IsTheTrapezoidRuleForAVaryingRate) {
  // A turn by `total` about a fixed axis in `duration`, with the rate of a hand,
  // w(t) = total pi / (2 duration) sin(pi t / duration), 0 at both ends. imu_tk's step takes the
  // middle rate as the mean of the ends, so about a fixed axis it adds dt (w0 + w1) / 2: the
  // trapezoid rule, whose error here is dt^2 (w'(0) - w'(T)) / 12 = dt^2 total pi^2 /
  // (12 duration^2) (the turn comes out that much short), second-order in the step.
  const std::array<double, 3> axis = {0.0, 0.6, 0.8};
  const double total = 1.3, duration = 2.0;  // rad, s
  auto error_with = [&](int steps_count) {
    const double dt = duration / steps_count;
    double rotation[9];
    IntegrateAngularRate(
        steps_count + 1,
        [&](int j, double* rate) {
          const double speed = total * M_PI / (2.0 * duration) * std::sin(M_PI * j * dt / duration);
          for (int k = 0; k < 3; ++k) rate[k] = speed * axis[k];
        },
        std::vector<double>(steps_count, dt), rotation);
    const std::array<double, 9> expected = AxisAngle(axis, total);
    return AngleBetweenRotations(rotation, expected.data());
  };
  for (const int steps_count : {100, 200, 400}) {
    const double dt = duration / steps_count;
    const double trapezoid = dt * dt * total * M_PI * M_PI / (12.0 * duration * duration);
    EXPECT_NEAR(error_with(steps_count), trapezoid, 0.01 * trapezoid) << steps_count << " steps";
  }
}

// ---------------------------------------------------------------------------------------------
// Simulated sessions: the sensor held in one pose after another, turned between them about the
// axis perpendicular to both gravity directions, with the rate of a hand (0 at both ends of the
// turn). Body frame: f = R^T g_world turns as df/dt = -w x f, so a turn of f by theta about a
// takes the body rate w = -dtheta/dt a.

// imu_tk's accelerometer fit on its Xsens log (tests/imu_tk_calibration_test.cc).
TriadParameters AccelerometerTruth() {
  TriadParameters truth = TriadParametersWithOffset(33124.2, 33275.2, 32364.4);
  const double angles[3] = {0.0033593, -0.0089064, 0.0213341};
  const double inverse_gains[3] = {414.459, 412.01, 414.649};
  for (int k = 0; k < 3; ++k) {
    truth[kTriadMisalignmentYz + k] = angles[k];
    truth[kTriadGainX + k] = 1.0 / inverse_gains[k];
  }
  return truth;
}

constexpr double kGravity = 9.81744;

// `count` gravity directions drawn on the sphere (a fixed seed: the same poses every run).
std::vector<std::array<double, 3>> PoseDirections(int count) {
  RandomSource random(11);
  return RandomPoseDirections(count, &random);
}

struct GyroscopeSession {
  TriadLog log;
  std::vector<StaticInterval> holds;  // the true holds
};

// 100 Hz; the first hold lasts `rest_s`, the others `hold_s`, turns `turn_s`; white noise of
// `accelerometer_noise` and `gyroscope_noise` counts (none when 0).
GyroscopeSession SimulateGyroscopeSession(const GyroscopeParameters& gyroscope, int poses,
                                          double rest_s, double hold_s, double turn_s,
                                          double accelerometer_noise, double gyroscope_noise,
                                          uint64_t seed) {
  const double dt = 0.01;
  const TriadParameters accelerometer = AccelerometerTruth();
  RandomSource random(seed);
  GyroscopeSession session;
  auto add = [&](const std::array<double, 3>& direction, const std::array<double, 3>& rate) {
    const double force[3] = {kGravity * direction[0], kGravity * direction[1],
                             kGravity * direction[2]};
    double raw[3];
    TriadRawOutput(accelerometer.data(), force, raw);
    double raw_rate[3];
    GyroscopeRawOutput(gyroscope.data(), kGyroscopeOffset.data(), rate.data(), raw_rate);
    const double t = 0.02 + dt * session.log.size();
    session.log.Add(t, raw[0] + accelerometer_noise * random.StandardNormal(),
                    raw[1] + accelerometer_noise * random.StandardNormal(),
                    raw[2] + accelerometer_noise * random.StandardNormal());
    session.log.gyroscope.push_back({raw_rate[0] + gyroscope_noise * random.StandardNormal(),
                                     raw_rate[1] + gyroscope_noise * random.StandardNormal(),
                                     raw_rate[2] + gyroscope_noise * random.StandardNormal()});
  };
  const std::vector<std::array<double, 3>> directions = PoseDirections(poses);
  for (int p = 0; p < poses; ++p) {
    StaticInterval hold;
    hold.start = static_cast<int>(session.log.size());
    const int samples = static_cast<int>(std::lround((p == 0 ? rest_s : hold_s) / dt));
    for (int i = 0; i < samples; ++i) add(directions[p], {0.0, 0.0, 0.0});
    hold.end = static_cast<int>(session.log.size()) - 1;
    session.holds.push_back(hold);
    if (p + 1 == poses) break;
    const std::array<double, 3>& from = directions[p];
    const std::array<double, 3>& to = directions[p + 1];
    std::array<double, 3> axis = {from[1] * to[2] - from[2] * to[1],
                                  from[2] * to[0] - from[0] * to[2],
                                  from[0] * to[1] - from[1] * to[0]};
    const double sine = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    const double angle = std::atan2(sine, from[0] * to[0] + from[1] * to[1] + from[2] * to[2]);
    for (double& a : axis) a /= sine;
    const int turn_samples = static_cast<int>(std::lround(turn_s / dt));
    for (int j = 1; j < turn_samples; ++j) {
      const double phase = M_PI * j / turn_samples;
      const double theta = angle * (1.0 - std::cos(phase)) / 2.0;
      const double theta_rate = angle * M_PI / (2.0 * turn_s) * std::sin(phase);
      // f = from cos(theta) + (axis x from) sin(theta): from is perpendicular to the axis.
      const std::array<double, 3> across = {axis[1] * from[2] - axis[2] * from[1],
                                            axis[2] * from[0] - axis[0] * from[2],
                                            axis[0] * from[1] - axis[1] * from[0]};
      std::array<double, 3> direction;
      for (int k = 0; k < 3; ++k)
        direction[k] = from[k] * std::cos(theta) + across[k] * std::sin(theta);
      add(direction, {-theta_rate * axis[0], -theta_rate * axis[1], -theta_rate * axis[2]});
    }
  }
  return session;
}

// The accelerometer's result as imu_tk's detector and a perfect fit would give it: the true
// parameters, and the true holds less half of imu_tk's window (50 samples) at each end, where
// the detector's windows still see the turn.
ImuTkResult PerfectAccelerometer(const GyroscopeSession& session) {
  ImuTkResult result;
  result.rest_end = session.holds.front().end;
  ImuTkSweepEntry entry;
  entry.multiplier = 2;
  entry.solved = true;
  entry.parameters = AccelerometerTruth();
  result.sweep.push_back(entry);
  result.chosen = 0;
  for (StaticInterval interval : session.holds) {
    interval.start += 50;
    interval.end -= 50;
    result.intervals.push_back(interval);
  }
  result.interval_used.assign(session.holds.size(), true);
  return result;
}

// The fraction of a turn of the simulated shape (2 s, 100 Hz) that imu_tk's rule misses:
// dt^2 pi^2 / (12 T^2) (GyroscopeIntegration.IsTheTrapezoidRuleForAVaryingRate), 2.06e-5.
const double kTrapezoidShortfall = 0.01 * 0.01 * M_PI * M_PI / (12.0 * 2.0 * 2.0);

ImuTkGyroscopeOptions StartFromTheNominalGain() {
  ImuTkGyroscopeOptions options;
  options.initial = GyroscopeParametersWithGain(1.0 / 4770.0, 1.0 / 4770.0, 1.0 / 4770.0);
  return options;
}

TEST(ImuTkGyroscopeResidual, IsZeroAtTheTruthUpToTheIntegrationError) {
  const GyroscopeParameters truth = GyroscopeTruth();
  const GyroscopeSession session = SimulateGyroscopeSession(truth, 8, 5.0, 2.0, 2.0, 0, 0, 1);
  const ImuTkResult accelerometer = PerfectAccelerometer(session);
  ImuTkGyroscopeOptions options = StartFromTheNominalGain();
  options.initial = truth;
  options.max_iterations = 0;
  ImuTkGyroscopeResult result;
  const Status status = CalibrateImuTkGyroscope(session.log, accelerometer, options, &result);
  ASSERT_TRUE(status.ok()) << status.message();
  // Each turn misses by the error of imu_tk's rule alone, the trapezoid rule's on a turn of the
  // simulated shape (GyroscopeIntegration.IsTheTrapezoidRuleForAVaryingRate).
  ASSERT_EQ(result.turns.size(), 7u);
  for (const ImuTkGyroscopeTurn& turn : result.turns) {
    EXPECT_GT(turn.turn_angle_rad, 0.3);
    EXPECT_NEAR(turn.residual_angle_rad, kTrapezoidShortfall * turn.turn_angle_rad,
                0.01 * kTrapezoidShortfall * turn.turn_angle_rad);
  }
  // The offset is the rest's mean: exact without noise.
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(result.offset[k], kGyroscopeOffset[k], 1e-9);
}

// Central differences with a step relative to each parameter's scale (ceres::GradientChecker's
// step has a floor far above the gains, 2e-4 (rad/s)/count, and its differences are then not
// derivatives).
TEST(ImuTkGyroscopeResidual, AutodiffAgreesWithCentralDifferences) {
  const GyroscopeParameters truth = GyroscopeTruth();
  const GyroscopeSession session = SimulateGyroscopeSession(truth, 2, 1.0, 1.0, 2.0, 0, 0, 1);
  const std::vector<std::array<double, 3>> raw(
      session.log.gyroscope.begin() + session.holds[0].end,
      session.log.gyroscope.begin() + session.holds[1].start);
  const std::vector<std::array<double, 3>> directions = PoseDirections(2);
  const ImuTkGyroscopeResidual residual(directions[0], directions[1], raw,
                                        std::vector<double>(raw.size() - 1, 0.01),
                                        kGyroscopeOffset);
  GyroscopeParameters at = GyroscopeParametersWithGain(1.0 / 4700.0, 1.0 / 4800.0, 1.0 / 4750.0);
  for (int p = 0; p < 6; ++p) at[p] = 0.01 * (p + 1) * (p % 2 == 0 ? 1 : -1);
  using Jet = ceres::Jet<double, kGyroscopeParameterCount>;
  Jet jets[kGyroscopeParameterCount];
  for (int p = 0; p < kGyroscopeParameterCount; ++p) jets[p] = Jet(at[p], p);
  Jet with_derivatives[3];
  ASSERT_TRUE(residual(jets, with_derivatives));
  for (int p = 0; p < kGyroscopeParameterCount; ++p) {
    const double step = 1e-6 * (p < kGyroscopeGainX ? 0.01 : at[p]);
    GyroscopeParameters above = at, below = at;
    above[p] += step;
    below[p] -= step;
    double r_above[3], r_below[3];
    ASSERT_TRUE(residual(above.data(), r_above));
    ASSERT_TRUE(residual(below.data(), r_below));
    for (int k = 0; k < 3; ++k) {
      const double numeric = (r_above[k] - r_below[k]) / (2.0 * step);
      const double analytic = with_derivatives[k].v[p];
      EXPECT_NEAR(analytic, numeric, 1e-6 * std::max(1.0, std::abs(numeric)))
          << GyroscopeParameterInfos()[p].name << ", component " << k;
    }
  }
}

TEST(ImuTkGyroscopeCalibration, RecoversNoiseFreeGyroscopeErrors) {
  const GyroscopeParameters truth = GyroscopeTruth();
  const GyroscopeSession session = SimulateGyroscopeSession(truth, 16, 10.0, 2.0, 2.0, 0, 0, 2);
  ImuTkGyroscopeOptions options = StartFromTheNominalGain();
  options.function_tolerance = 1e-14;
  options.parameter_tolerance = 1e-14;
  options.max_iterations = 100;
  ImuTkGyroscopeResult result;
  const Status status =
      CalibrateImuTkGyroscope(session.log, PerfectAccelerometer(session), options, &result);
  ASSERT_TRUE(status.ok()) << status.message();
  ASSERT_EQ(result.turns.size(), 15u);
  // Every turn of the simulation has the same shape, so imu_tk's rule falls short of each by the
  // same fraction, and the fit makes up for it exactly by raising every gain by that fraction;
  // the angles come out true.
  for (int p = 0; p < 6; ++p) {
    EXPECT_NEAR(result.parameters[p], truth[p], 1e-8) << GyroscopeParameterInfos()[p].name;
  }
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(result.parameters[kGyroscopeGainX + k] / truth[kGyroscopeGainX + k],
                1.0 + kTrapezoidShortfall, 1e-8)
        << GyroscopeParameterInfos()[kGyroscopeGainX + k].name;
  }
  EXPECT_LT(result.cost, 1e-12);
}

// The whole chain on a noisy session: imu_tk's accelerometer calibration finds the poses and the
// accelerometer, then the gyroscope's. Noise of 3 counts (accelerometer) and 2 counts (gyroscope,
// 4e-4 rad/s), about the Xsens unit's.
TEST(ImuTkGyroscopeCalibration, RecoversTheGyroscopeAfterImuTksAccelerometerCalibration) {
  const GyroscopeParameters truth = GyroscopeTruth();
  const GyroscopeSession session = SimulateGyroscopeSession(truth, 24, 50.0, 3.0, 2.0, 3.0, 2.0, 3);
  ImuTkOptions accelerometer_options;
  accelerometer_options.gravity_mps2 = kGravity;
  accelerometer_options.init_rest_s = 50.0;
  accelerometer_options.initial = TriadParametersWithOffset(32768.0, 32768.0, 32768.0);
  ImuTkResult accelerometer;
  Status status = CalibrateImuTk(session.log, accelerometer_options, &accelerometer);
  ASSERT_TRUE(status.ok()) << status.message();
  ASSERT_EQ(accelerometer.best().used_intervals, 24);
  ImuTkGyroscopeResult result;
  status = CalibrateImuTkGyroscope(session.log, accelerometer, StartFromTheNominalGain(), &result);
  ASSERT_TRUE(status.ok()) << status.message();
  // The offset: the mean of 5000 samples of 2 counts, sigma 0.03 counts.
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(result.offset[k], kGyroscopeOffset[k], 0.15);
  // Angles and gains: the gravity directions are known to about 1e-4 rad (the accelerometer's
  // fit, and 3 counts of noise over some 200 samples), each turn's rotation to about the
  // gyroscope's noise integrated over it (4e-4 rad/s * sqrt(0.01 s * 3 s) ~ 7e-5 rad), over 23
  // turns of about 0.7 rad: errors of about 1e-4 (rad, relative), 1e-4 seen with this seed.
  for (int p = 0; p < 6; ++p) {
    EXPECT_NEAR(result.parameters[p], truth[p], 5e-4) << GyroscopeParameterInfos()[p].name;
  }
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(result.parameters[kGyroscopeGainX + k] / truth[kGyroscopeGainX + k], 1.0, 5e-4)
        << GyroscopeParameterInfos()[kGyroscopeGainX + k].name;
  }
}

// ---------------------------------------------------------------------------------------------
// Bad input.

TEST(ImuTkGyroscopeCalibration, RefusesALogWithoutGyroscope) {
  const GyroscopeSession session =
      SimulateGyroscopeSession(GyroscopeTruth(), 8, 5.0, 2.0, 2.0, 0, 0, 4);
  TriadLog log = session.log;
  log.gyroscope.clear();
  ImuTkGyroscopeResult result;
  const Status status = CalibrateImuTkGyroscope(log, PerfectAccelerometer(session),
                                                StartFromTheNominalGain(), &result);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("no gyroscope samples"), std::string::npos) << status.message();
}

TEST(ImuTkGyroscopeCalibration, RefusesTooFewIntervals) {
  const GyroscopeSession session =
      SimulateGyroscopeSession(GyroscopeTruth(), 5, 5.0, 2.0, 2.0, 0, 0, 5);
  ImuTkGyroscopeResult result;
  const Status status = CalibrateImuTkGyroscope(session.log, PerfectAccelerometer(session),
                                                StartFromTheNominalGain(), &result);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("used 5 static intervals, fewer than the 6"), std::string::npos)
      << status.message();
}

TEST(ImuTkGyroscopeCalibration, RefusesAFailedAccelerometerCalibration) {
  const GyroscopeSession session =
      SimulateGyroscopeSession(GyroscopeTruth(), 8, 5.0, 2.0, 2.0, 0, 0, 6);
  ImuTkGyroscopeResult result;
  const Status status =
      CalibrateImuTkGyroscope(session.log, ImuTkResult(), StartFromTheNominalGain(), &result);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("did not succeed"), std::string::npos) << status.message();
}

}  // namespace
}  // namespace accelcal
