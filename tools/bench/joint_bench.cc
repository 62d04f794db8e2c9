// The joint nonlinear solve with covariance on course-sized data (the tp2-2018 scenario:
// 20001 tilt samples, a 6000-sample run), for several effect sets; the baseline as a
// per-sample Ceres problem (estimation/tilt_table/ceres_linear_ls.h, the cross-check of the closed
// form); and one evaluation of the endpoint residual with its Jacobian (cost per run sample).
//
//   build/bin/joint_bench --benchmark_min_time=2

#include <benchmark/benchmark.h>

#include <cstdlib>
#include <memory>

#include "estimation/tilt_table/ceres_linear_ls.h"
#include "estimation/tilt_table/joint_estimator.h"
#include "io/scenario_json.h"
#include "models/tilt_table.h"
#include "residuals/endpoint_residual.h"

namespace accelcal {
namespace {

const SimulatedData& CourseSizedData() {
  static const SimulatedData data = [] {
    Scenario scenario;
    if (!LoadDefaultScenario(&scenario).ok()) std::abort();  // the compiled-in scenario
    return SimulateScenario(scenario, 1);
  }();
  return data;
}

void BM_JointSolveWithCovariance(benchmark::State& state, const std::string& effects,
                                 JointOptions::Landmark mode) {
  const SimulatedData& data = CourseSizedData();
  JointOptions options = JointOptionsFor(data.conditions, kCourseGravityMps2);
  options.landmark_mode = mode;
  options.landmark_name = "C";
  if (!ParseEffects(effects, &options.effects).ok()) state.SkipWithError("bad effects");
  for (auto _ : state) {
    JointResult result;
    if (!SolveJoint(data.test, data.run, data.conditions, data.landmarks, options, &result).ok()) {
      state.SkipWithError("solve failed");
      break;
    }
    benchmark::DoNotOptimize(result.estimate.covariance.data());
  }
}
BENCHMARK_CAPTURE(BM_JointSolveWithCovariance, baseline_no_landmark, std::string(""),
                  JointOptions::Landmark::kNone)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_JointSolveWithCovariance, angle_nonorth_landmark_C,
                  std::string("angle_offset,nonorthogonality"), JointOptions::Landmark::kNamed)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_JointSolveWithCovariance, all_effects_landmark_C, std::string("all"),
                  JointOptions::Landmark::kNamed)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_JointSolveWithCovariance, angle_nonorth_auto_4_landmarks,
                  std::string("angle_offset,nonorthogonality"), JointOptions::Landmark::kAuto)
    ->Unit(benchmark::kMillisecond);

void BM_CeresBaselineWithCovariance(benchmark::State& state) {
  const SimulatedData& data = CourseSizedData();
  CeresLinearLsOptions options;
  options.model.gravity_mps2 = data.conditions.gravity_mps2;
  options.model.noise_variance_x = data.conditions.noise_variance_x;
  options.model.noise_variance_y = data.conditions.noise_variance_y;
  for (auto _ : state) {
    CeresLinearLsResult result;
    if (!EstimateLinearLsWithCeres(data.test, options, &result).ok()) {
      state.SkipWithError("solve failed");
      break;
    }
    benchmark::DoNotOptimize(result.fit.covariance.data());
  }
  state.SetItemsProcessed(state.iterations() * data.test.size());
}
BENCHMARK(BM_CeresBaselineWithCovariance)->Unit(benchmark::kMillisecond);

void BM_EndpointResidualWithJacobian(benchmark::State& state) {
  const SimulatedData& data = CourseSizedData();
  const std::unique_ptr<ceres::CostFunction> cost(EndpointResidual::Create(new EndpointResidual(
      data.run.measured_x, data.run.measured_y, 0.01, Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 3),
      Eigen::Vector2d(460, 60), Eigen::Matrix2d::Identity() * 200.0, 0.0)));
  double values[9] = {0.07, -0.03, 0.0, 0.0, -0.02, 0.01, 0.0, 0.0, 0.0};
  const double* blocks[9];
  for (int i = 0; i < 9; ++i) blocks[i] = &values[i];
  double residual[2];
  double jacobian_storage[9][2];
  double* jacobians[9];
  for (int i = 0; i < 9; ++i) jacobians[i] = jacobian_storage[i];
  for (auto _ : state) {
    cost->Evaluate(blocks, residual, jacobians);
    benchmark::DoNotOptimize(jacobian_storage[0][0]);
  }
  state.SetItemsProcessed(state.iterations() * data.run.size());
}
BENCHMARK(BM_EndpointResidualWithJacobian)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace accelcal

BENCHMARK_MAIN();
