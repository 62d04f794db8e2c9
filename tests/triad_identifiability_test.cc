// The triad ML problem's directions eliminated (estimation/triad/triad_identifiability.h): the
// reduced information's rank decision names the parameters the whole Jacobian's SVD named, on
// pose sets that cannot determine the triad, and its inverse is ceres::Covariance's marginal
// covariance of the sensor parameters (over every block, the directions included) to 1e-9.

#include "estimation/triad/triad_identifiability.h"

#include <ceres/ceres.h>
#include <ceres/sphere_manifold.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "estimation/triad/triad_ml_calibration.h"
#include "models/triad_effect_list.h"
#include "residuals/triad_pose_residual.h"
#include "simulation/triad_simulator.h"
#include "studies/triad_monte_carlo.h"
#include "triad_test_session.h"

namespace accelcal {
namespace {

constexpr double kGravity = testing::kTriadTestGravity;
using testing::TriadTestMlOptions;
using testing::TriadTestSimulationOptions;

// The ML problem at given parameters and directions, as CalibrateTriadMl builds it: the triad
// block, the effects block when `estimated` is not empty (the others held by a SubsetManifold),
// then one direction per pose on the sphere.
class MlProblem {
 public:
  MlProblem(const std::vector<TriadPoseMean>& poses, const TriadParameters& parameters,
            const TriadEffectCoefficients& effects, const std::vector<int>& estimated,
            const std::vector<std::array<double, 3>>& directions,
            const std::vector<std::array<double, 3>>& mean_stddev, double time_origin_s)
      : parameters_(parameters), effects_(effects), directions_(directions) {
    blocks_.push_back(parameters_.data());
    if (!estimated.empty()) blocks_.push_back(effects_.data());
    for (size_t p = 0; p < poses.size(); ++p) {
      double* direction = directions_[p].data();
      if (estimated.empty()) {
        problem_.AddResidualBlock(
            TriadPoseResidual::Create(poses[p].mean, mean_stddev[p], kGravity), nullptr,
            parameters_.data(), direction);
      } else {
        TriadPoseContext context;
        context.time_s = poses[p].time_s - time_origin_s;
        problem_.AddResidualBlock(
            TriadPoseResidual::CreateWithEffects(poses[p].mean, mean_stddev[p], kGravity, context),
            nullptr, parameters_.data(), effects_.data(), direction);
      }
      problem_.SetManifold(direction, new ceres::SphereManifold<3>());
      blocks_.push_back(direction);
    }
    if (!estimated.empty() && static_cast<int>(estimated.size()) < kTriadEffectCoefficientCount) {
      std::vector<int> held;
      for (int c = 0; c < kTriadEffectCoefficientCount; ++c)
        if (!std::binary_search(estimated.begin(), estimated.end(), c)) held.push_back(c);
      problem_.SetManifold(effects_.data(),
                           new ceres::SubsetManifold(kTriadEffectCoefficientCount, held));
    }
  }

  TriadArrowJacobian Jacobian(int sensor_columns) {
    ceres::Problem::EvaluateOptions options;
    options.parameter_blocks = blocks_;
    ceres::CRSMatrix crs;
    double cost = 0.0;
    EXPECT_TRUE(problem_.Evaluate(options, &cost, nullptr, nullptr, &crs));
    TriadArrowJacobian jacobian;
    EXPECT_TRUE(TriadArrowJacobianFromCrs(crs, sensor_columns, &jacobian));
    return jacobian;
  }

  ceres::Problem* problem() { return &problem_; }
  double* parameters() { return parameters_.data(); }
  double* effects() { return effects_.data(); }

 private:
  ceres::Problem problem_;
  TriadParameters parameters_;
  TriadEffectCoefficients effects_;
  std::vector<std::array<double, 3>> directions_;
  std::vector<double*> blocks_;
};

std::vector<std::string> ParameterNames(const std::vector<int>& estimated) {
  std::vector<std::string> names;
  for (const TriadParameterInfo& info : TriadParameterInfos()) names.push_back(info.name);
  for (int c : estimated) names.push_back(TriadEffectCoefficientList()[c].name);
  return names;
}

std::string Joined(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) text += name + " ";
  return text;
}

// Planar pose sets (the sensor turned about x, y or z only), at the simulated truth and at the
// ML problem's initial guess, with the 9 parameters and with the second-order scale terms too:
// the reduced rule names exactly the parameters the whole Jacobian's SVD names (and some).
TEST(TriadReducedInformation, NamesTheParametersTheWholeJacobianNamesOnPlanarPoses) {
  const int first_k2 = TriadEffectCoefficientIndex("scale_nonlinearity_x");
  for (const bool with_k2 : {false, true}) {
    const std::vector<int> estimated =
        with_k2 ? std::vector<int>{first_k2, first_k2 + 1, first_k2 + 2} : std::vector<int>{};
    const std::vector<std::string> names = ParameterNames(estimated);
    for (int axis = 0; axis < 3; ++axis) {
      RandomSource random(5, axis);
      const std::vector<std::array<double, 3>> directions = PlanarPoseDirections(20, axis);
      const std::vector<TriadPoseMean> poses =
          SimulateTriadPoses(TriadTestSimulationOptions(), directions, &random);
      const std::vector<std::array<double, 3>> mean_stddev(poses.size(), {0.3, 0.25, 0.35});
      for (const bool at_truth : {true, false}) {
        const TriadParameters parameters =
            at_truth ? XsensLikeTriad() : TriadTestMlOptions().initial;
        MlProblem problem(poses, parameters, TriadEffectCoefficients{}, estimated, directions,
                          mean_stddev, 0.0);
        const TriadArrowJacobian jacobian = problem.Jacobian(static_cast<int>(names.size()));
        const TriadReducedInformation reduced = ReducedInformation(jacobian);
        ASSERT_TRUE(reduced.directions_determined);
        const std::vector<std::string> whole = UnidentifiableParametersWhole(jacobian, names, 1e-4);
        const std::vector<std::string> by_reduction =
            UnidentifiableParametersReduced(jacobian, reduced, names, 1e-4);
        SCOPED_TRACE("axis " + std::to_string(axis) + (with_k2 ? " with k2" : "") +
                     (at_truth ? " at the truth" : " at the initial guess"));
        if (at_truth)
          std::printf("  axis %c%s: %s\n", "xyz"[axis], with_k2 ? " with k2" : "",
                      Joined(by_reduction).c_str());
        EXPECT_FALSE(whole.empty());
        EXPECT_EQ(by_reduction, whole)
            << "reduced: " << Joined(by_reduction) << "\nwhole:   " << Joined(whole);
        const std::string axis_name(1, "xyz"[axis]);
        EXPECT_NE(std::find(whole.begin(), whole.end(), "gain_" + axis_name), whole.end());
        EXPECT_NE(std::find(whole.begin(), whole.end(), "offset_" + axis_name), whole.end());
      }
    }
  }
}

TEST(TriadReducedInformation, FindsFullRankWhereTheWholeJacobianDoes) {
  RandomSource random(11, 0);
  const std::vector<std::array<double, 3>> directions = RandomPoseDirections(30, &random);
  const std::vector<TriadPoseMean> poses =
      SimulateTriadPoses(TriadTestSimulationOptions(), directions, &random);
  const std::vector<std::array<double, 3>> mean_stddev(poses.size(), {0.3, 0.25, 0.35});
  MlProblem problem(poses, XsensLikeTriad(), TriadEffectCoefficients{}, {}, directions, mean_stddev,
                    0.0);
  const std::vector<std::string> names = ParameterNames({});
  const TriadArrowJacobian jacobian = problem.Jacobian(kTriadParameterCount);
  EXPECT_TRUE(UnidentifiableParametersWhole(jacobian, names, 1e-4).empty());
  EXPECT_TRUE(
      UnidentifiableParametersReduced(jacobian, ReducedInformation(jacobian), names, 1e-4).empty());
}

// CalibrateTriadMl's covariance (the reduced information's inverse) against ceres::Covariance
// over every block of the same problem at the solution, with and without the second-order
// scale terms: every entry within 1e-9 of sqrt(c_ii c_jj).
TEST(TriadReducedInformation, CovarianceIsCeresCovarianceOverEveryBlock) {
  const int first_k2 = TriadEffectCoefficientIndex("scale_nonlinearity_x");
  for (const bool with_k2 : {false, true}) {
    SCOPED_TRACE(with_k2 ? "with k2" : "9 parameters");
    RandomSource random(2036, with_k2 ? 1 : 0);
    const std::vector<TriadPoseMean> poses = SimulateTriadPoses(
        TriadTestSimulationOptions(), RandomPoseDirections(40, &random), &random);
    TriadMlOptions options = TriadTestMlOptions();
    options.scale_nonlinearity = with_k2;
    TriadMlResult result;
    const Status status = CalibrateTriadMl(poses, options, &result);
    ASSERT_TRUE(status.ok()) << status.message();

    MlProblem problem(poses, result.parameters, result.effects, result.effects_estimated,
                      result.directions, result.mean_stddev, result.time_origin_s);
    ceres::Covariance::Options covariance_options;
    covariance_options.algorithm_type = ceres::SPARSE_QR;
    covariance_options.num_threads = 1;
    ceres::Covariance covariance(covariance_options);
    std::vector<std::pair<const double*, const double*>> pairs = {
        {problem.parameters(), problem.parameters()}};
    if (with_k2) {
      pairs.push_back({problem.effects(), problem.effects()});
      pairs.push_back({problem.parameters(), problem.effects()});
    }
    ASSERT_TRUE(covariance.Compute(pairs, problem.problem()));
    constexpr int kN = kTriadParameterCount;
    constexpr int kE = kTriadEffectCoefficientCount;
    double block[kN * kN];
    covariance.GetCovarianceBlock(problem.parameters(), problem.parameters(), block);
    for (int i = 0; i < kN; ++i) {
      for (int j = 0; j < kN; ++j) {
        const double scale = std::sqrt(block[i * kN + i] * block[j * kN + j]);
        EXPECT_NEAR(result.covariance[i][j], block[i * kN + j], 1e-9 * scale) << i << " " << j;
      }
    }
    if (!with_k2) continue;
    std::vector<double> effects(kE * kE), cross(kN * kE);
    covariance.GetCovarianceBlock(problem.effects(), problem.effects(), effects.data());
    covariance.GetCovarianceBlock(problem.parameters(), problem.effects(), cross.data());
    for (int a = 0; a < kE; ++a) {
      for (int b = 0; b < kE; ++b) {
        const double scale = std::sqrt(effects[a * kE + a] * effects[b * kE + b]);
        EXPECT_NEAR(result.effects_covariance[a][b], effects[a * kE + b], 1e-9 * scale)
            << a << " " << b;
      }
      for (int i = 0; i < kN; ++i) {
        const double scale = std::sqrt(block[i * kN + i] * effects[a * kE + a]);
        EXPECT_NEAR(result.cross_covariance[i][a], cross[i * kE + a], 1e-9 * scale)
            << i << " " << a;
      }
    }
    // The estimated terms have a variance; the held ones none.
    for (int k = 0; k < 3; ++k) EXPECT_GT(result.effects_stddev[first_k2 + k], 0.0);
  }
}

}  // namespace
}  // namespace accelcal
