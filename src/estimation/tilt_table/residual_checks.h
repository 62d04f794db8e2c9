#ifndef ACCELCAL_ESTIMATION_TILT_TABLE_RESIDUAL_CHECKS_H_
#define ACCELCAL_ESTIMATION_TILT_TABLE_RESIDUAL_CHECKS_H_

// Checks of what a fitted model leaves, each a statistic of the whitened residuals with a
// p-value under "the model and its noise model are right", a sentence, and (for a shape)
// the columns that describe it, so that discovery can ask whether an effect it named is
// still needed once the shape is allowed for (docs/discovery.md). Per axis:
//
//   theta harmonic k     cos k theta and sin k theta, k = 1..max_harmonic, projected off
//                        what the model can already make: the chi-square they remove
//                        (dof = the rank left), chi-square tail;               orientation
//   curved trend         u^2 and u^3 of the sample's place u in the test, likewise; its
//                        sentence says whether what is left over time is monotonic or
//                        turns (a cubic in u fitted to the raw residuals);      time
//   step                 the largest chi-square a step removes over the change points
//                        in the middle 96% of the test, each projected off the model,
//                        against the sup of a standardised Brownian bridge (Miller and
//                        Siegmund's approximation); the step's place and size with it; time
//   turn direction       +1 while the table turns up (theta increasing), -1 while it turns
//                        down (TurnDirection), projected off the model, chi-square(1);
//                        none when the table turns one way only;       turn direction
//   full scale +, -      per sign s, the one-sided hinge -s max(0, s f_i - tau) in the
//                        force f_i along the axis that the model predicts, at thresholds
//                        tau among the top 20% of s f (FullScaleThresholds): the largest
//                        z of a shortfall (outputs smaller in magnitude than the model),
//                        Bonferroni over the thresholds;                   full scale
//   one position         when the test holds static positions (StaticPositions), each
//                        position's offset column projected off the model: the largest
//                        chi-square(1), Bonferroni over the positions;     pose order
//   lag-1 correlation    sqrt(n) r_1, two-sided normal;                          noise
//   portmanteau          Ljung-Box over `ljung_box_lags` lags, chi-square tail;  noise
//
// and, when the run is tied to a landmark, the endpoint's chi-square (2 dof; noise). Every
// check carries its shape class and a sentence of advice (estimation/discovery/check.h).
//
// The model is linearised at its solution (LinearizeJoint): rows x_0, y_0, x_1, y_1, ...,
// then the endpoint's two; a shape column is whitened with the axis's noise model before
// it is projected, so the chi-squares keep their meaning with correlated noise.

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "common/measurements.h"
#include "common/tilt_motion.h"
#include "estimation/discovery/check.h"
#include "estimation/statistics/extra_chi_square.h"
#include "models/effects.h"
#include "models/noise_model.h"

namespace accelcal {

struct ResidualChecksOptions {
  int max_harmonic = 6;
  int ljung_box_lags = 20;
  double gravity_mps2 = 9.8;  // only to state a full-scale level in g
};

// The fitted model at its solution, per axis and in sample order (m/s^2): what it leaves of
// each output (measured minus predicted), and the force along the axis it predicts (the force
// the axis's scale acts on, models/sensor_model.h), which is what an axis clips in.
struct FittedOutputs {
  std::array<std::vector<double>, 2> residual;
  std::array<std::vector<double>, 2> force_along;
};
FittedOutputs EvaluateFit(const CalibrationTest& test, const ModelParameters<double>& values,
                          double gravity_mps2);

// The whitened rows of a shape column on axis `axis` (the full linearised problem's rows).
Eigen::VectorXd WhitenedShapeColumn(const std::vector<double>& shape, int axis,
                                    const AxisNoise& noise, int rows);

// The whitened residuals of axis `axis`'s tilt-test rows, in sample order, outliers left out.
std::vector<double> AxisWhiteResiduals(const Eigen::VectorXd& residual, int axis, int samples,
                                       int endpoint_rows, const AxisNoise& noise);

// The lag-1 correlation and portmanteau checks of one axis's whitened residuals (at least 16).
std::vector<ResidualCheck> CorrelationChecks(const std::vector<double>& white, int axis,
                                             int ljung_box_lags);

// Runs every check; `jacobian` and `residual` from LinearizeJoint at the solution, `fitted`
// from EvaluateFit at it; `endpoint_rows` is 2 when the run is tied to a landmark, else 0.
std::vector<ResidualCheck> CheckResiduals(const CalibrationTest& test,
                                          const Eigen::MatrixXd& jacobian,
                                          const Eigen::VectorXd& residual,
                                          const FittedOutputs& fitted, int endpoint_rows,
                                          const AxisNoise noise[2],
                                          const ResidualChecksOptions& options);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TILT_TABLE_RESIDUAL_CHECKS_H_
