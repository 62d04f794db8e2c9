#ifndef ACCELCAL_ESTIMATION_TILT_TABLE_JOINT_ESTIMATOR_H_
#define ACCELCAL_ESTIMATION_TILT_TABLE_JOINT_ESTIMATOR_H_

// The joint nonlinear problem: bias and scale of each axis plus any chosen effects of the
// catalogue (angle_offset, nonorthogonality, bias_drift_k, scale_nonlinearity_k,
// run_bias_shift_k), estimated in one Ceres problem from every tilt-test sample
// (residuals/calibration_residual.h) and, when the run is tied to a landmark, from the
// dead-reckoned endpoint (residuals/endpoint_residual.h). Every residual is whitened by
// the stated noise, so 2 x cost is a chi-square and ceres::Covariance gives the
// parameters' covariance in the spec's units.
//
// Before the covariance, the information matrix J^T J (columns scaled to unit norm) is
// checked for near-null directions (estimation/solver/identifiability.h); parameters that move
// together along one are reported as not separable, and no covariance is claimed for them.
//
// Beside it: estimation/tilt_table/joint_data.h (the data and the baseline every solve starts from,
// prepared once), estimation/tilt_table/score_test.h (what a candidate effect would gain, for
// discovery), estimation/tilt_table/robust_covariance.h (the Huber fit's sandwich covariance) and
// models/effect_names.h (effects by name).

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "common/measurements.h"
#include "common/status.h"
#include "estimation/solver/solver_report.h"
#include "estimation/tilt_table/parameter_estimate.h"
#include "models/effect_names.h"
#include "models/noise_model.h"

namespace accelcal {

// A robust loss on the tilt-test residuals (Ceres' HuberLoss and CauchyLoss).
enum class RobustLoss { kNone, kHuber, kCauchy };
// "none", "huber", "cauchy".
const char* RobustLossName(RobustLoss loss);
// The loss named `name` (as RobustLossName writes it); anything else is an error naming the
// choices.
Status ParseRobustLoss(const std::string& name, RobustLoss* loss);

struct JointOptions {
  std::vector<Parameter> effects;  // estimated beyond bias and scale (no noise_variance_k)
  double gravity_mps2 = 9.8;
  double noise_variance_x = 0.0;  // stated, (m/s^2)^2
  double noise_variance_y = 0.0;
  // The noise's structure beyond its variance (models/noise_model.h): each axis's
  // correlation of consecutive samples (tilt test and run), and the tilt-test samples set
  // aside as outliers (ascending).
  std::array<double, 2> noise_correlation = {0.0, 0.0};
  std::array<std::vector<int>, 2> outliers;
  // The noise model of axis k (0: x, 1: y) these options describe.
  AxisNoise Noise(int axis) const {
    return {axis == 0 ? noise_variance_x : noise_variance_y, noise_correlation[axis],
            outliers[axis]};
  }
  enum class Landmark { kNone, kNamed, kAuto };
  Landmark landmark_mode = Landmark::kNone;
  std::string landmark_name;      // with kNamed
  double landmark_sigma_m = 0.0;  // the landmark's position uncertainty
  // Robust loss on the calibration residuals; its scale is in units of the (whitened)
  // residual, i.e. of sigma.
  RobustLoss loss = RobustLoss::kNone;
  double loss_scale = 1.345;
  int max_iterations = 100;
  // Each axis's tilt-test residuals as one CompressedCalibrationResidual (exact, and its
  // cost does not grow with the test's size); false: one block per sample, as the robust
  // losses need anyway. The two give the same solution; a test checks it.
  bool compress_calibration = true;
  int num_threads = 1;
  // A near-null direction of the scaled information matrix: eigenvalue ratio below this.
  double identifiability_threshold = 1e-10;
  // A landmark farther than this many sigma from the baseline's dead-reckoned endpoint
  // (Mahalanobis distance, parameters + run noise + landmark_sigma) is not a hypothesis any
  // sensor error of the catalogue can produce: a named one is refused, an auto one is not
  // solved (its posterior is 0). Tying the run to it would drive the scale factors past -1
  // and the residuals to NaN. A run bias shift of 0.5 m/s^2 over the course's 60 s run is
  // about 90 sigma, so the bound leaves room for every effect discovery looks for.
  double implausible_landmark_sigma = 1000.0;
};

// The options of a joint solve under the run's stated noise (white, every sample) and gravity
// `gravity_mps2`: the baseline and no landmark until the caller adds effects and a tie.
inline JointOptions JointOptionsFor(const RunConditions& conditions, double gravity_mps2) {
  JointOptions options;
  options.gravity_mps2 = gravity_mps2;
  options.noise_variance_x = conditions.noise_variance_x;
  options.noise_variance_y = conditions.noise_variance_y;
  return options;
}

struct LandmarkHypothesis {
  std::string name;
  double cost = 0.0;            // half the total chi-square at the optimum
  double chi2_endpoint = 0.0;   // the endpoint residual's share
  double posterior = 0.0;       // equal priors: exp(-cost) normalised
  double baseline_sigma = 0.0;  // Mahalanobis distance from the baseline endpoint
  bool solved = true;           // false: beyond implausible_landmark_sigma, not solved, posterior 0
};

struct JointResult {
  ParameterEstimate estimate;
  double chi2_x = 0.0;  // tilt-test residuals of each axis (without the robust loss)
  double chi2_y = 0.0;
  int samples = 0;
  double chi2_endpoint = 0.0;                  // 0 without a landmark
  std::string landmark;                        // the landmark the run was tied to, or empty
  std::vector<LandmarkHypothesis> hypotheses;  // with Landmark::kAuto, one per landmark
  SolverReport solver;
};

class JointData;  // estimation/tilt_table/joint_data.h: the data, prepared once for many solves

// Fails (naming the parameters) when the chosen effects cannot be separated with these
// data, e.g. run_bias_shift_x without a landmark, or bias, scale and scale_nonlinearity
// from a test with two static positions.
Status SolveJoint(const JointData& data, const JointOptions& options, JointResult* result);
// The same for one solve: prepares the data and forgets them.
Status SolveJoint(const CalibrationTest& test, const VehicleRun& run,
                  const RunConditions& conditions, const std::vector<Landmark>& landmarks,
                  const JointOptions& options, JointResult* result);

// The whitened residuals of the joint problem at `at` and their Jacobian with respect to
// at.estimate.free (or `columns` when given). Rows: x_0, y_0, x_1, y_1, ... for the tilt
// test (an outlier's rows are zero), then the endpoint's two when the run is tied to a
// landmark.
Status LinearizeJoint(const JointData& data, const JointOptions& options, const JointResult& at,
                      Eigen::MatrixXd* jacobian, Eigen::VectorXd* residual,
                      const std::vector<Parameter>* columns = nullptr);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TILT_TABLE_JOINT_ESTIMATOR_H_
