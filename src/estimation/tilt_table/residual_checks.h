#ifndef ACCELCAL_ESTIMATION_TILT_TABLE_RESIDUAL_CHECKS_H_
#define ACCELCAL_ESTIMATION_TILT_TABLE_RESIDUAL_CHECKS_H_

// Checks of what a fitted model leaves, each a statistic of the whitened residuals with a
// p-value under "the model and its noise model are right", a sentence, and (for a shape)
// the columns that describe it, so that discovery can ask whether an effect it named is
// still needed once the shape is allowed for (docs/discovery.md). Per axis:
//
//   theta harmonic k     cos k theta and sin k theta, k = 1..max_harmonic, projected off
//                        what the model can already make: the chi-square they remove
//                        (dof = the rank left), chi-square tail;
//   curved trend         u^2 and u^3 of the sample's place u in the test, likewise;
//   step                 the largest chi-square a step removes over the change points
//                        in the middle 96% of the test, each projected off the model,
//                        against the sup of a standardised Brownian bridge (Miller and
//                        Siegmund's approximation); the step's place and size with it;
//   lag-1 correlation    sqrt(n) r_1, two-sided normal;
//   portmanteau          Ljung-Box over `ljung_box_lags` lags, chi-square tail;
//
// and, when the run is tied to a landmark, the endpoint's chi-square (2 dof).
//
// The model is linearised at its solution (LinearizeJoint): rows x_0, y_0, x_1, y_1, ...,
// then the endpoint's two; a shape column is whitened with the axis's noise model before
// it is projected, so the chi-squares keep their meaning with correlated noise.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "common/measurements.h"
#include "estimation/discovery/check.h"
#include "estimation/statistics/extra_chi_square.h"
#include "models/noise_model.h"

namespace accelcal {

struct ResidualChecksOptions {
  int max_harmonic = 6;
  int ljung_box_lags = 20;
};

// The whitened rows of a shape column on axis `axis` (the full linearised problem's rows).
Eigen::VectorXd WhitenedShapeColumn(const std::vector<double>& shape, int axis,
                                    const AxisNoise& noise, int rows);

// Runs every check; `jacobian` and `residual` from LinearizeJoint at the solution;
// `endpoint_rows` is 2 when the run is tied to a landmark, else 0.
std::vector<ResidualCheck> CheckResiduals(const CalibrationTest& test,
                                          const Eigen::MatrixXd& jacobian,
                                          const Eigen::VectorXd& residual, int endpoint_rows,
                                          const AxisNoise noise[2],
                                          const ResidualChecksOptions& options);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TILT_TABLE_RESIDUAL_CHECKS_H_
