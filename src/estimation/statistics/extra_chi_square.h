#ifndef ACCELCAL_ESTIMATION_STATISTICS_EXTRA_CHI_SQUARE_H_
#define ACCELCAL_ESTIMATION_STATISTICS_EXTRA_CHI_SQUARE_H_

// What columns outside a linearised model can still explain of its whitened residual: the
// chi-square they remove (a score test: the model is not refitted, the columns are projected
// off its span), the rank they add, and their coefficients. Every sensor geometry's checks of
// what remains are these on their own columns (estimation/tilt_table/residual_checks.h: the
// samples' rows; estimation/triad/triad_shape_checks.h: one contrast per pose).

#include <Eigen/Core>

namespace accelcal {

// A model's span, factored once, for many families of columns tested beside it (a maximum over
// change points or poses).
class ModelSpan {
 public:
  explicit ModelSpan(const Eigen::MatrixXd& model);
  // As ExtraChiSquare below, with this model.
  double ExtraChiSquare(const Eigen::MatrixXd& extra, const Eigen::VectorXd& r,
                        int* rank = nullptr) const;
  // `extra` less its part in the model's span.
  Eigen::MatrixXd Beside(const Eigen::MatrixXd& extra) const;
  // An orthonormal basis of the span (rows x the model's columns).
  const Eigen::MatrixXd& basis() const { return basis_; }

 private:
  Eigen::MatrixXd basis_;  // orthonormal, the model's columns' span
};

// The chi-square the columns `extra` remove when added to the span of `model` (same rows,
// whitened) from the residual `r`, and the rank they add (columns with almost nothing left
// outside the model's span add nothing).
double ExtraChiSquare(const Eigen::MatrixXd& model, const Eigen::MatrixXd& extra,
                      const Eigen::VectorXd& r, int* rank = nullptr);

// The least-squares coefficients of `r` on the columns of `extra` fitted beside `model`.
Eigen::VectorXd ProjectedCoefficients(const Eigen::MatrixXd& model, const Eigen::MatrixXd& extra,
                                      const Eigen::VectorXd& r);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_STATISTICS_EXTRA_CHI_SQUARE_H_
