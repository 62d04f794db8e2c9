#ifndef ACCELCAL_RESIDUALS_SCALAR_PRIOR_RESIDUAL_H_
#define ACCELCAL_RESIDUALS_SCALAR_PRIOR_RESIDUAL_H_

// A Gaussian prior on one unknown x, as a whitened residual: (x - mean) / stddev. With it an
// unknown that the data may not determine (the Earth's vertical rate where the latitude is not
// given: estimation/gyroscope/gyroscope_ml_calibration.h) is bounded by what is known of it
// beforehand, and a fit's chi-square counts its one residual against its one unknown.

#include <ceres/ceres.h>

namespace accelcal {

class ScalarPrior {
 public:
  ScalarPrior(double mean, double stddev) : mean_(mean), stddev_(stddev) {}

  template <typename T>
  bool operator()(const T* const x, T* residual) const {
    residual[0] = (x[0] - T(mean_)) / T(stddev_);
    return true;
  }

  static ceres::CostFunction* Create(double mean, double stddev) {
    return new ceres::AutoDiffCostFunction<ScalarPrior, 1, 1>(new ScalarPrior(mean, stddev));
  }

 private:
  const double mean_;
  const double stddev_;
};

}  // namespace accelcal

#endif  // ACCELCAL_RESIDUALS_SCALAR_PRIOR_RESIDUAL_H_
