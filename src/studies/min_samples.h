#ifndef ACCELCAL_STUDIES_MIN_SAMPLES_H_
#define ACCELCAL_STUDIES_MIN_SAMPLES_H_

// How many tilt-test samples still decide the landmark? (The reference report's last
// question.) For a tilt design with N samples the baseline's covariance is
// sigma^2 (A^T A)^-1 of that design; through the endpoint's Jacobian it adds
// J Sigma_params(N) J^T to the run's own noise part, which does not shrink with N:
//
//   Sigma_end(N) = J Sigma_params(N) J^T + Sigma_noise.
//
// With the endpoint estimate ~ N(L_true, Sigma_end(N)) and the decision "the landmark at
// the smallest Mahalanobis distance", the probability of a wrong decision is the Gaussian
// mass outside L_true's cell (convex, bounded by the bisectors in the whitened plane):
//
//   P(wrong) = (1/2 pi) integral over phi of exp(-r(phi)^2 / 2),
//
// r(phi) being the distance from the centre to the cell's boundary along phi (whitened).
// The refusal "no landmark is consistent" (p < alpha at the true landmark) happens with
// probability alpha whatever N is, so it is reported apart and the criterion is on
// P(wrong).

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "common/measurements.h"
#include "common/progress.h"
#include "common/status.h"
#include "estimation/tilt_table/trajectory.h"
#include "simulation/scenario.h"

namespace accelcal {

// Angles of an N-sample design: "uniform" (N evenly over [0, 2 pi], both ends, as the
// course), "four" (0, 90, 180, 270 degrees, N/4 each), "two" (45 and 225 degrees, N/2
// each: both axes see +-g/sqrt(2) at each), or two positions theta_a, theta_b (N/2 each).
std::vector<double> DesignAngles(const std::string& design, int samples, double theta_a = 0.0,
                                 double theta_b = 0.0);

// sigma^2 (A^T A)^-1 of the baseline for these angles, 4x4 in kBaselineParameters' order.
Eigen::Matrix4d BaselineCovarianceForDesign(const std::vector<double>& theta_rad,
                                            double gravity_mps2, double noise_variance_x,
                                            double noise_variance_y);

// Gaussian mass outside landmark `truth`'s decision cell: the estimate ~ N(center,
// distribution_covariance); cells from the Mahalanobis metric `decision_covariance`.
double ProbabilityOfWrongLandmark(const Eigen::Vector2d& center,
                                  const Eigen::Matrix2d& distribution_covariance,
                                  const Eigen::Matrix2d& decision_covariance,
                                  const std::vector<Landmark>& landmarks, int truth,
                                  int quadrature_points = 7200);

struct EndpointModel {
  Eigen::Matrix<double, 2, 4> jacobian;  // d endpoint / d kBaselineParameters
  Eigen::Matrix2d noise_part;            // the run's own noise, m^2
  Eigen::Vector2d endpoint;              // the full-data estimate, m
  double gravity_mps2 = 9.8;
  double noise_variance_x = 0.0;
  double noise_variance_y = 0.0;
};

struct CurvePoint {
  int samples = 0;
  Eigen::Matrix2d endpoint_covariance = Eigen::Matrix2d::Zero();
  double p_wrong = 0.0;
  int landmarks_in_3sigma = 0;  // around the full-data endpoint
};

struct DesignCurve {
  std::string name;
  double theta_a = 0.0;  // the two positions of the "optimal" design
  double theta_b = 0.0;
  std::vector<CurvePoint> curve;
  int n_min = -1;         // smallest N with P(wrong) <= max_error (-1: none up to the limit)
  int n_min_3sigma = -1;  // smallest N whose 3-sigma ellipse holds only one landmark
};

CurvePoint EvaluateDesign(const EndpointModel& model, const std::vector<Landmark>& landmarks,
                          int truth, const DesignCurve& design, int samples);

// The curve on a logarithmic grid from 10 to max_samples, and both N_min (by bisection,
// P(wrong) being monotone in N for these designs). `design` gives the name and positions.
DesignCurve AnalyseDesign(const EndpointModel& model, const std::vector<Landmark>& landmarks,
                          int truth, const DesignCurve& design, double max_error, int max_samples);

// The two-position design (5-degree grid) with the smallest P(wrong) at `reference_samples`.
DesignCurve OptimalTwoPositionDesign(const EndpointModel& model,
                                     const std::vector<Landmark>& landmarks, int truth,
                                     int reference_samples);

// The designs, in the order "all" analyses them.
const std::vector<std::string>& DesignNames();

// The optimal design is searched at the uniform design's N_min; when the uniform design was
// not analysed, or no N meets the criterion for it, at this many samples.
constexpr int kDefaultReferenceSamples = 100;

// The endpoint model of a dead-reckoned run (its Jacobian, noise part and endpoint).
EndpointModel EndpointModelOf(const DeadReckoningResult& trajectory, double gravity_mps2,
                              double noise_variance_x, double noise_variance_y);

// The endpoint model of a dataset: baseline fit with `gravity_mps2`, dead reckoning, and the
// landmark the endpoint decides (`truth`, -1 without landmarks).
Status BuildEndpointModel(const CalibrationTest& test, const VehicleRun& run,
                          const RunConditions& conditions, const std::vector<Landmark>& landmarks,
                          double gravity_mps2, EndpointModel* model, int* truth);

// The designs named in `names`, in that order, each analysed up to `max_samples`. The
// optimal one is searched at `*uniform_n_min`: kDefaultReferenceSamples, or the uniform
// design's N_min when it came before (left there for the caller).
std::vector<DesignCurve> AnalyseDesigns(const EndpointModel& model,
                                        const std::vector<Landmark>& landmarks, int truth,
                                        const std::vector<std::string>& names, double max_error,
                                        int max_samples, int* uniform_n_min);

// A Monte Carlo check of a design's analytic P(wrong) at one N.
struct MonteCarloCheck {
  enum class Kind {
    kFullSimulation,      // test and run simulated from the scenario
    kRealTestSubsets,     // random subsets of the real test, the real run
    kRealTestEvenSubsets  // evenly spaced subsets of the real test, the real run
  };
  Kind kind = Kind::kFullSimulation;
  int samples = 0;
  double analytic = 0.0;
  double monte_carlo = 0.0;
  double monte_carlo_sd = 0.0;  // the analytic binomial sd of the Monte Carlo rate
  int repetitions = 0;
  int independent = 0;  // independent outcomes among the repetitions
};

struct MinSamplesOptions {
  std::vector<std::string> designs = DesignNames();
  double max_error = 0.01;
  double gravity_mps2 = 9.8;
  int repetitions = 1000;  // per checked N; 0: no Monte Carlo
  uint64_t seed = 1;
  int threads = 0;
  // Check on subsets of the test as well (only meaningful for a measured test: a simulated
  // one is checked by full simulation already).
  bool subset_checks = true;
  // Per finished Monte Carlo trial of the checks (the curves are analytic and quick), of
  // every check's together, known once the designs' N_min are.
  ProgressFn progress;
};

struct MinSamplesResult {
  EndpointModel model;  // of the full data
  int truth = -1;       // the landmark the full data decides
  int full_samples = 0;
  int uniform_n_min = kDefaultReferenceSamples;  // see AnalyseDesigns
  std::vector<DesignCurve> designs;
  std::vector<std::vector<MonteCarloCheck>> checks;  // per design
};

// Every design of `options` on the data, checked by Monte Carlo: full simulations of
// `scenario` at N_min and N_min / 4 (at least 10), and for the uniform design subsets of
// the real test. Fails when the data decide no landmark among at least two.
Status RunMinSamplesStudy(const CalibrationTest& test, const VehicleRun& run,
                          const RunConditions& conditions, const std::vector<Landmark>& landmarks,
                          const Scenario& scenario, const MinSamplesOptions& options,
                          MinSamplesResult* result);

}  // namespace accelcal

#endif  // ACCELCAL_STUDIES_MIN_SAMPLES_H_
