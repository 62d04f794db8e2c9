// imucal's Ferraris calibration reproduced on its own session (example_cal.json), the mapping
// between imucal's and accelcal's conventions, and the least-squares counterpart with sigma:
// what six holds determine, and Monte Carlo agreement of the sigma where the model holds.

#include "estimation/triad/ferraris_calibration.h"

#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "common/ferraris_session.h"
#include "estimation/triad/ferraris_least_squares.h"
#include "io/imucal_session.h"
#include "models/imucal_convention.h"
#include "models/triad.h"
#include "residuals/ferraris_hold_residual.h"
#include "simulation/random.h"
#include "test_support.h"

namespace accelcal {
namespace {

// imucal's regression test: 204.8 Hz, g = 9.81, turns of -360 degrees (its defaults).
FerrarisOptions ImucalTestOptions() {
  FerrarisOptions options;
  options.sampling_rate_hz = 204.8;
  return options;
}

Eigen::Matrix3d MatrixFromJson(const nlohmann::json& json) {
  Eigen::Matrix3d matrix;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) matrix(i, j) = json.at(i).at(j).get<double>();
  return matrix;
}

Eigen::Vector3d VectorFromJson(const nlohmann::json& json) {
  return Eigen::Vector3d(json.at(0).get<double>(), json.at(1).get<double>(),
                         json.at(2).get<double>());
}

// The largest |actual - expected| / |expected| over the elements; elements imucal writes as
// exact zeros must be exact zeros.
template <typename A, typename B>
double MaxRelativeDifference(const Eigen::MatrixBase<A>& actual,
                             const Eigen::MatrixBase<B>& expected) {
  double largest = 0.0;
  for (int i = 0; i < expected.rows(); ++i) {
    for (int j = 0; j < expected.cols(); ++j) {
      const double e = expected(i, j);
      const double difference = std::abs(actual(i, j) - e);
      largest = std::max(
          largest, e == 0.0 ? (difference == 0.0 ? 0.0 : HUGE_VAL) : difference / std::abs(e));
    }
  }
  return largest;
}

// The session and imucal's snapshot, read once.
class FerrarisImucalExample : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string dir = testing::ImucalDataDir();
    if (dir.empty()) {
      GTEST_SKIP() << "imucal data not found: set ACCELCAL_IMUCAL_DATA or put it in "
                      "../shared/data/imucal-ferraris";
    }
    const Status read = ReadImucalSession(dir + "/annotated_session.csv", &session_);
    ASSERT_TRUE(read.ok()) << read.message();
    snapshot_ = nlohmann::json::parse(testing::ReadText(dir + "/example_cal.json"));
    const Status computed = FerrarisClosedForm(session_, ImucalTestOptions(), &calibration_);
    ASSERT_TRUE(computed.ok()) << computed.message();
  }
  FerrarisSession session_;
  nlohmann::json snapshot_;
  ImucalCalibration calibration_;
};

TEST_F(FerrarisImucalExample, ReproducesTheAccelerometerOfExampleCalJson) {
  const ImucalAccelerometer& acc = calibration_.accelerometer;
  const double k = MaxRelativeDifference(acc.k_a, MatrixFromJson(snapshot_.at("K_a")));
  const double r = MaxRelativeDifference(acc.r_a, MatrixFromJson(snapshot_.at("R_a")));
  const double b = MaxRelativeDifference(acc.b_a, VectorFromJson(snapshot_.at("b_a")));
  std::printf("max relative difference from example_cal.json: K_a %.1e, R_a %.1e, b_a %.1e\n", k, r,
              b);
  EXPECT_LT(k, 1e-12);
  EXPECT_LT(r, 1e-12);
  EXPECT_LT(b, 1e-12);
}

TEST_F(FerrarisImucalExample, ReproducesTheGyroscopeOfExampleCalJson) {
  ASSERT_TRUE(calibration_.has_gyroscope);
  const ImucalGyroscope& gyr = calibration_.gyroscope;
  const double k = MaxRelativeDifference(gyr.k_g, MatrixFromJson(snapshot_.at("K_g")));
  const double r = MaxRelativeDifference(gyr.r_g, MatrixFromJson(snapshot_.at("R_g")));
  const double ka = MaxRelativeDifference(gyr.k_ga, MatrixFromJson(snapshot_.at("K_ga")));
  const double b = MaxRelativeDifference(gyr.b_g, VectorFromJson(snapshot_.at("b_g")));
  std::printf(
      "max relative difference from example_cal.json: K_g %.1e, R_g %.1e, K_ga %.1e, b_g %.1e\n", k,
      r, ka, b);
  EXPECT_LT(k, 1e-12);
  EXPECT_LT(r, 1e-12);
  EXPECT_LT(ka, 1e-12);
  EXPECT_LT(b, 1e-12);
}

TEST_F(FerrarisImucalExample, InAccelcalsNamesPredictsWhatImucalDoes) {
  TriadParameters triad{};
  Eigen::Matrix3d rotation;
  ASSERT_TRUE(ImucalToTriad(calibration_.accelerometer, &triad, &rotation).ok());
  // The hold means map to the same specific force through both, up to the rotation Q.
  for (int s = 0; s < kFerrarisSectionCount; ++s) {
    const std::array<double, 3>& raw = session_.sections[s].accelerometer.mean;
    Eigen::Vector3d accelcal;
    TriadSpecificForce(triad.data(), raw.data(), accelcal.data());
    const Eigen::Vector3d imucal =
        ImucalSpecificForce(calibration_.accelerometer, Eigen::Vector3d(raw[0], raw[1], raw[2]));
    EXPECT_EIGEN_NEAR(rotation * accelcal, imucal, 1e-12);
  }
  // Angles of a hand-held session: a few hundredths of a radian at most; gains near the
  // inverse of K_a (the angles are small).
  for (int i = kTriadMisalignmentYz; i <= kTriadMisalignmentZx; ++i)
    EXPECT_LT(std::abs(triad[i]), 0.05);
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(triad[kTriadGainX + k] * calibration_.accelerometer.k_a(k, k), 1.0, 1e-3);
  EXPECT_NEAR(rotation.determinant(), 1.0, 1e-12);
}

// Holds made from a known imucal calibration, exactly +-g along the axes: the closed form
// gives it back.
FerrarisSession SessionFromCalibration(const ImucalAccelerometer& truth, double gravity_mps2) {
  FerrarisSession session;
  const Eigen::Matrix3d to_raw = truth.k_a * truth.r_a;
  for (int p = 0; p < kFerrarisSectionCount; ++p) {
    const int axis = p < kFerrarisHoldCount ? p / 2 : p - kFerrarisHoldCount;
    const double sign = p < kFerrarisHoldCount && p % 2 == 1 ? -1.0 : 1.0;
    const Eigen::Vector3d raw =
        truth.b_a + to_raw * (sign * gravity_mps2 * Eigen::Vector3d::Unit(axis));
    FerrarisSectionData& section = session.sections[p];
    section.accelerometer.sample_count = section.gyroscope.sample_count = 100;
    for (int k = 0; k < 3; ++k) {
      section.accelerometer.mean[k] = raw[k];
      section.accelerometer.variance[k] = 4.0;
      section.gyroscope.variance[k] = 1.0;
    }
  }
  return session;
}

ImucalAccelerometer ExampleTruth() {
  TriadParameters triad{};
  triad[kTriadMisalignmentYz] = 0.004;
  triad[kTriadMisalignmentZy] = -0.011;
  triad[kTriadMisalignmentZx] = 0.017;
  triad[kTriadGainX] = 1.0 / 208.0;
  triad[kTriadGainY] = 1.0 / 211.0;
  triad[kTriadGainZ] = 1.0 / 205.0;
  triad[kTriadOffsetX] = -12.0;
  triad[kTriadOffsetY] = 40.0;
  triad[kTriadOffsetZ] = 25.0;
  Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(0.02, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  return TriadToImucal(triad, rotation);
}

TEST(Ferraris, RecoversTheCalibrationOfExactHolds) {
  const ImucalAccelerometer truth = ExampleTruth();
  ImucalCalibration calibration;
  ASSERT_TRUE(
      FerrarisClosedForm(SessionFromCalibration(truth, 9.81), FerrarisOptions(), &calibration)
          .ok());
  EXPECT_FALSE(calibration.has_gyroscope);
  EXPECT_EIGEN_NEAR(calibration.accelerometer.k_a, truth.k_a, 1e-10);
  EXPECT_EIGEN_NEAR(calibration.accelerometer.r_a, truth.r_a, 1e-13);
  EXPECT_EIGEN_NEAR(calibration.accelerometer.b_a, truth.b_a, 1e-10);
}

TEST(Ferraris, RefusesHoldsThatDoNotSpanThreeAxes) {
  FerrarisSession session = SessionFromCalibration(ExampleTruth(), 9.81);
  // z held like x: the pairs' directions are not independent.
  session.sections[kZp] = session.sections[kXp];
  session.sections[kZa] = session.sections[kXa];
  ImucalCalibration calibration;
  EXPECT_ERROR_CONTAINS(FerrarisClosedForm(session, FerrarisOptions(), &calibration),
                        "two holds point the same way");
}

TEST(Ferraris, RefusesHoldsWithSwappedLabels) {
  FerrarisSession session = SessionFromCalibration(ExampleTruth(), 9.81);
  std::swap(session.sections[kYp], session.sections[kZp]);
  std::swap(session.sections[kYa], session.sections[kZa]);
  ImucalCalibration calibration;
  EXPECT_ERROR_CONTAINS(FerrarisClosedForm(session, FerrarisOptions(), &calibration),
                        "left-handed set; are two sections' labels swapped?");
}

TEST(Ferraris, RefusesTheGyroscopeWithoutASamplingRate) {
  FerrarisOptions options;
  options.sampling_rate_hz = -1.0;
  ImucalCalibration calibration;
  EXPECT_ERROR_CONTAINS(
      FerrarisClosedForm(SessionFromCalibration(ExampleTruth(), 9.81), options, &calibration),
      "sampling rate -1 Hz");
}

// ---- The conventions.

TriadParameters RandomTriad(RandomSource* random) {
  TriadParameters triad{};
  for (int i = kTriadMisalignmentYz; i <= kTriadMisalignmentZx; ++i)
    triad[i] = 0.05 * random->StandardNormal();
  for (int k = 0; k < 3; ++k) {
    triad[kTriadGainX + k] = 0.004 * (1.0 + 0.2 * random->Uniform());
    triad[kTriadOffsetX + k] = 100.0 * random->StandardNormal();
  }
  return triad;
}

Eigen::Matrix3d RandomRotation(RandomSource* random) {
  Eigen::Vector3d axis(random->StandardNormal(), random->StandardNormal(),
                       random->StandardNormal());
  return Eigen::AngleAxisd(3.0 * random->Uniform(), axis.normalized()).toRotationMatrix();
}

TEST(ImucalConvention, AccelcalToImucalAndBackIsTheIdentity) {
  RandomSource random(20);
  for (int trial = 0; trial < 100; ++trial) {
    const TriadParameters triad = RandomTriad(&random);
    const Eigen::Matrix3d rotation = RandomRotation(&random);
    const ImucalAccelerometer imucal = TriadToImucal(triad, rotation);
    EXPECT_EIGEN_NEAR(imucal.r_a.rowwise().norm(), Eigen::Vector3d::Ones(), 1e-14);
    TriadParameters back{};
    Eigen::Matrix3d rotation_back;
    ASSERT_TRUE(ImucalToTriad(imucal, &back, &rotation_back).ok());
    for (int i = 0; i < kTriadParameterCount; ++i)
      EXPECT_NEAR(back[i], triad[i], 1e-12 * std::max(1.0, std::abs(triad[i])))
          << TriadParameterInfos()[i].name;
    EXPECT_EIGEN_NEAR(rotation_back, rotation, 1e-12);
  }
}

TEST(ImucalConvention, ImucalToAccelcalAndBackIsTheIdentity) {
  const ImucalAccelerometer imucal = ExampleTruth();
  TriadParameters triad{};
  Eigen::Matrix3d rotation;
  ASSERT_TRUE(ImucalToTriad(imucal, &triad, &rotation).ok());
  const ImucalAccelerometer back = TriadToImucal(triad, rotation);
  EXPECT_EIGEN_NEAR(back.k_a, imucal.k_a, 1e-10);
  EXPECT_EIGEN_NEAR(back.r_a, imucal.r_a, 1e-14);
  EXPECT_EIGEN_NEAR(back.b_a, imucal.b_a, 0.0);
}

TEST(ImucalConvention, BothPredictTheSameMagnitudeForAnyOutput) {
  RandomSource random(7);
  for (int trial = 0; trial < 20; ++trial) {
    const TriadParameters triad = RandomTriad(&random);
    const ImucalAccelerometer imucal = TriadToImucal(triad, RandomRotation(&random));
    for (int sample = 0; sample < 20; ++sample) {
      const double raw[3] = {5000.0 * random.StandardNormal(), 5000.0 * random.StandardNormal(),
                             5000.0 * random.StandardNormal()};
      double accelcal[3];
      TriadSpecificForce(triad.data(), raw, accelcal);
      const double magnitude = Eigen::Vector3d(accelcal[0], accelcal[1], accelcal[2]).norm();
      EXPECT_NEAR(ImucalSpecificForce(imucal, Eigen::Vector3d(raw[0], raw[1], raw[2])).norm(),
                  magnitude, 1e-12 * magnitude);
    }
  }
}

TEST(ImucalConvention, GainsAreTheCholeskyFactorOfImucalsMatrix) {
  // An independent route: M^T M = (T K)^T (T K), so T K is the upper Cholesky factor of M^T M.
  const ImucalAccelerometer imucal = ExampleTruth();
  const Eigen::Matrix3d m = imucal.r_a.inverse() * imucal.k_a.inverse();
  const Eigen::Matrix3d upper = (m.transpose() * m).llt().matrixU();
  TriadParameters triad{};
  Eigen::Matrix3d rotation;
  ASSERT_TRUE(ImucalToTriad(imucal, &triad, &rotation).ok());
  EXPECT_EIGEN_NEAR(TriadMatrix(triad), upper, 1e-15);
}

TEST(ImucalConvention, RefusesAFrameThatIsMirrored) {
  ImucalAccelerometer imucal = ExampleTruth();
  imucal.r_a.row(2) *= -1.0;
  TriadParameters triad{};
  Eigen::Matrix3d rotation;
  EXPECT_ERROR_CONTAINS(ImucalToTriad(imucal, &triad, &rotation), "it mirrors the frame");
  imucal = ExampleTruth();
  imucal.k_a(0, 1) = 0.5;
  EXPECT_ERROR_CONTAINS(ImucalToTriad(imucal, &triad, &rotation), "K_a[0][1] = 0.5");
}

// ---- Least squares.

TEST_F(FerrarisImucalExample, SixHoldsLeaveTheThreeAnglesUndetermined) {
  FerrarisAnalysis analysis;
  const Status status =
      AnalyzeFerraris(session_, ImucalTestOptions(), FerrarisLeastSquaresOptions(), &analysis);
  ASSERT_TRUE(status.ok()) << status.message();
  const FerrarisIdentifiability& id = analysis.least_squares.identifiability;
  EXPECT_EQ(id.observations, 18);
  EXPECT_EQ(id.unknowns, 21);
  EXPECT_EQ(id.rank, 18);
  // The three null directions are the angles (with the directions turning along): each
  // angle's weight ~0.7, the gains' and offsets' a few hundredths at most.
  for (int i = 0; i < kTriadParameterCount; ++i) {
    if (i <= kTriadMisalignmentZx) {
      EXPECT_GT(id.null_space_weight[i], 0.5) << TriadParameterInfos()[i].name;
    } else {
      EXPECT_LT(id.null_space_weight[i], 0.05) << TriadParameterInfos()[i].name;
    }
  }
  // The 18 non-zero singular values of the normalised Jacobian are all well above zero
  // (the smallest ~0.39 of the largest ~1.43): the rest is exactly determined.
  EXPECT_GT(id.singular_values[17], 0.1 * id.singular_values[0]);
  EXPECT_EQ(id.not_identifiable,
            (std::vector<std::string>{"misalignment_yz", "misalignment_zy", "misalignment_zx"}));
}

TEST_F(FerrarisImucalExample, LeastSquaresBesideTheClosedForm) {
  FerrarisAnalysis analysis;
  ASSERT_TRUE(
      AnalyzeFerraris(session_, ImucalTestOptions(), FerrarisLeastSquaresOptions(), &analysis)
          .ok());
  const FerrarisLeastSquaresResult& ls = analysis.least_squares;
  // (b) with the closed form's angles: an exact fit, offsets and gains within 1 sigma of the
  // closed form's (they use the same six means, without Ferraris's per-axis shortcut).
  EXPECT_LT(ls.unknown_directions.chi2, 1e-12);
  for (int i = kTriadGainX; i <= kTriadOffsetZ; ++i) {
    EXPECT_GT(ls.unknown_directions.stddev[i], 0.0);
    EXPECT_LT(std::abs(ls.unknown_directions.parameters[i] - analysis.closed_form_triad[i]),
              1.0 * ls.unknown_directions.stddev[i])
        << TriadParameterInfos()[i].name;
  }
  for (int i = kTriadMisalignmentYz; i <= kTriadMisalignmentZx; ++i)
    EXPECT_EQ(ls.unknown_directions.stddev[i], 0.0);
  // (a): opposite holds of this hand-held session are not antiparallel: chi2 in the tens of
  // thousands on 6 degrees of freedom.
  EXPECT_EQ(ls.known_directions.degrees_of_freedom, 6);
  EXPECT_GT(ls.known_directions.chi2, 1e4);
  EXPECT_LT(ls.known_directions.p_value, 1e-100);
  std::printf("known directions: chi2 %.1f on %d dof\n", ls.known_directions.chi2,
              ls.known_directions.degrees_of_freedom);
}

// The hold residual: zero where the hold's mean is what the triad outputs under +-g along the
// frame's axis, and its autodiff Jacobian agrees with finite differences. On a triad whose
// output is already near m/s^2 (gains ~1): at gains of 1/208, GradientChecker's finite
// differences disagree with autodiff on d r / d gain, for triad_pose_residual.h too, while a
// central difference by hand (steps 1e-9 to 1e-11) gives autodiff's 2.1221e+06 exactly.
TEST(FerrarisHoldResidual, IsZeroAtTheTruthAndAgreesWithFiniteDifferences) {
  TriadParameters truth{};
  truth[kTriadMisalignmentYz] = 0.004;
  truth[kTriadMisalignmentZy] = -0.011;
  truth[kTriadMisalignmentZx] = 0.017;
  truth[kTriadGainX] = 1.01;
  truth[kTriadGainY] = 0.98;
  truth[kTriadGainZ] = 1.03;
  truth[kTriadOffsetX] = 0.1;
  truth[kTriadOffsetY] = -0.2;
  truth[kTriadOffsetZ] = 0.05;
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, -1).normalized()).toRotationMatrix();
  const std::array<double, 3> correction = {0.001, -0.002, 0.0015};
  double correction_matrix[9];
  ceres::AngleAxisToRotationMatrix(correction.data(),
                                   ceres::ColumnMajorAdapter3x3(correction_matrix));
  const Eigen::Matrix3d q = rotation * Eigen::Map<const Eigen::Matrix3d>(correction_matrix);
  for (int p = 0; p < kFerrarisHoldCount; ++p) {
    const Eigen::Vector3d axis = (p % 2 == 0 ? 1.0 : -1.0) * Eigen::Vector3d::Unit(p / 2);
    const Eigen::Vector3d force = q.transpose() * (9.81 * axis);
    std::array<double, 3> mean;
    TriadRawOutput(truth.data(), force.data(), mean.data());
    const Eigen::Vector3d reference = rotation.transpose() * axis;
    const std::unique_ptr<ceres::CostFunction> cost(FerrarisHoldResidual::Create(
        mean, {0.02, 0.03, 0.025}, {reference[0], reference[1], reference[2]}, 9.81));
    const double* blocks[] = {truth.data(), correction.data()};
    double residual[3];
    ASSERT_TRUE(cost->Evaluate(blocks, residual, nullptr));
    for (double r : residual) EXPECT_NEAR(r, 0.0, 1e-9);
    const std::vector<const ceres::Manifold*>* no_manifolds = nullptr;
    ceres::GradientChecker checker(cost.get(), no_manifolds, ceres::NumericDiffOptions());
    ceres::GradientChecker::ProbeResults results;
    EXPECT_TRUE(checker.Probe(blocks, 1e-7, &results)) << results.error_log;
  }
}

// Simulated Ferraris sessions whose holds are exactly +-g along the axes of a frame, with
// white noise of known sigma on the means: the known-directions fit recovers the truth, its
// chi2 has the chi-square's mean 6, and its sigma are the spread of the estimates.
TEST(FerrarisLeastSquares, SigmaMatchesTheMonteCarloSpreadWhereFerrarisAssumptionHolds) {
  const ImucalAccelerometer truth_imucal = ExampleTruth();
  TriadParameters truth{};
  Eigen::Matrix3d rotation;
  ASSERT_TRUE(ImucalToTriad(truth_imucal, &truth, &rotation).ok());
  const FerrarisSession exact = SessionFromCalibration(truth_imucal, 9.81);
  const std::array<double, 3> noise_stddev = {6.0, 7.0, 8.0};  // counts per sample
  const int samples = 400;
  const int trials = 400;
  RandomSource random(2020);
  std::array<double, kTriadParameterCount> sum{}, sum_squares{}, reported{};
  double chi2_sum = 0.0;
  for (int trial = 0; trial < trials; ++trial) {
    FerrarisSession session = exact;
    for (int p = 0; p < kFerrarisHoldCount; ++p) {
      TriadPoseMean& hold = session.sections[p].accelerometer;
      hold.sample_count = samples;
      for (int k = 0; k < 3; ++k) {
        hold.mean[k] += noise_stddev[k] / std::sqrt(samples) * random.StandardNormal();
        hold.variance[k] = noise_stddev[k] * noise_stddev[k];
      }
    }
    FerrarisAnalysis analysis;
    const Status status =
        AnalyzeFerraris(session, FerrarisOptions(), FerrarisLeastSquaresOptions(), &analysis);
    ASSERT_TRUE(status.ok()) << status.message();
    const FerrarisKnownDirectionsFit& fit = analysis.least_squares.known_directions;
    chi2_sum += fit.chi2;
    for (int i = 0; i < kTriadParameterCount; ++i) {
      const double error = fit.parameters[i] - truth[i];
      sum[i] += error;
      sum_squares[i] += error * error;
      reported[i] += fit.stddev[i] / trials;
    }
  }
  // chi2 mean 6 with standard error sqrt(12 / 400) = 0.17.
  EXPECT_NEAR(chi2_sum / trials, 6.0, 0.7);
  for (int i = 0; i < kTriadParameterCount; ++i) {
    const double mean = sum[i] / trials;
    const double spread = std::sqrt(sum_squares[i] / trials - mean * mean);
    // The spread of 400 estimates is known to 1/sqrt(2 * 400) = 3.5 %: 12 % is 3.4 of those.
    EXPECT_NEAR(reported[i] / spread, 1.0, 0.12) << TriadParameterInfos()[i].name;
    EXPECT_LT(std::abs(mean), 3.0 * spread / std::sqrt(trials)) << TriadParameterInfos()[i].name;
  }
}

TEST(FerrarisLeastSquares, RefusesAHoldWithoutNoise) {
  FerrarisSession session = SessionFromCalibration(ExampleTruth(), 9.81);
  for (int p = 0; p < kFerrarisHoldCount; ++p) session.sections[p].accelerometer.variance[1] = 0.0;
  FerrarisAnalysis analysis;
  EXPECT_ERROR_CONTAINS(
      AnalyzeFerraris(session, FerrarisOptions(), FerrarisLeastSquaresOptions(), &analysis),
      "the accelerometer's y output does not vary within any hold");
}

}  // namespace
}  // namespace accelcal
