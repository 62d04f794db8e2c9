#ifndef ACCELCAL_RESIDUALS_SCALAR_PRIOR_RESIDUAL_H_
#define ACCELCAL_RESIDUALS_SCALAR_PRIOR_RESIDUAL_H_

// A Gaussian prior on one unknown x, entry `index` of a parameter block of `size` values, as a
// whitened residual: (x - mean) / stddev. With it an unknown that the data may not determine (the
// Earth's vertical rate, an effect coefficient of the gyroscope, where the latitude is not given:
// estimation/gyroscope/gyroscope_ml_calibration.h) is bounded by what is known of it beforehand,
// and a fit's chi-square counts its one residual against its one unknown.

#include <ceres/cost_function.h>

namespace accelcal {

class ScalarPrior : public ceres::CostFunction {
 public:
  ScalarPrior(int size, int index, double mean, double stddev)
      : index_(index), mean_(mean), stddev_(stddev) {
    set_num_residuals(1);
    mutable_parameter_block_sizes()->push_back(size);
  }

  bool Evaluate(double const* const* blocks, double* residuals, double** jacobians) const override {
    residuals[0] = (blocks[0][index_] - mean_) / stddev_;
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      const int size = parameter_block_sizes()[0];
      for (int i = 0; i < size; ++i) jacobians[0][i] = i == index_ ? 1.0 / stddev_ : 0.0;
    }
    return true;
  }

 private:
  const int index_;
  const double mean_;
  const double stddev_;
};

}  // namespace accelcal

#endif  // ACCELCAL_RESIDUALS_SCALAR_PRIOR_RESIDUAL_H_
