#ifndef ACCELCAL_ESTIMATION_TILT_TABLE_JOINT_DATA_H_
#define ACCELCAL_ESTIMATION_TILT_TABLE_JOINT_DATA_H_

// A dataset prepared once for the joint problem. Discovery solves, scores and linearises
// dozens of models of one dataset under one noise model; each of them starts from the same
// closed-form baseline, whitens the endpoint with the same baseline run-noise covariance and
// compresses the tilt test into the same Gram matrices. JointData computes each of these
// once per noise model (g, the stated variances, the correlation and the outliers of
// JointOptions) and hands out the results:
//
//   Baseline(options)            the linear least-squares fit the solves start from
//   BaselineTrajectory(options)  its dead-reckoned run: endpoint, covariance, noise part
//   CompressedResiduals(options) each axis's tilt test as one CompressedCalibrationResidual,
//                                about the baseline (or why the model cannot be compressed)
//
// The measurements are referenced, not copied, and must outlive the JointData. A JointData
// is not thread-safe (it fills its cache on first use); give each thread its own.

#include <memory>
#include <vector>

#include "common/measurements.h"
#include "common/status.h"
#include "estimation/tilt_table/baseline_parameters.h"
#include "estimation/tilt_table/joint_estimator.h"
#include "estimation/tilt_table/trajectory.h"
#include "residuals/compressed_calibration_residual.h"

namespace accelcal {

class JointData {
 public:
  JointData(const CalibrationTest& test, const VehicleRun& run, const RunConditions& conditions,
            const std::vector<Landmark>& landmarks);
  ~JointData();
  JointData(const JointData&) = delete;
  JointData& operator=(const JointData&) = delete;

  const CalibrationTest& test() const { return test_; }
  const VehicleRun& run() const { return run_; }
  const RunConditions& conditions() const { return conditions_; }
  const std::vector<Landmark>& landmarks() const { return landmarks_; }
  const Landmark* FindLandmark(const std::string& name) const;

  // Each fails as the computation it caches would (and keeps failing the same way).
  Status Baseline(const JointOptions& options, const BaselineFit** fit) const;
  Status BaselineTrajectory(const JointOptions& options,
                            const DeadReckoningResult** trajectory) const;
  // A fresh copy of each axis's compressed residual (index 0: x, 1: y), for a solve to own.
  Status CompressedResiduals(const JointOptions& options,
                             std::unique_ptr<CompressedCalibrationResidual> residuals[2]) const;

 private:
  struct Prepared;
  Prepared& For(const JointOptions& options) const;

  const CalibrationTest& test_;
  const VehicleRun& run_;
  const RunConditions& conditions_;
  const std::vector<Landmark>& landmarks_;
  mutable std::vector<std::unique_ptr<Prepared>> prepared_;
};

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TILT_TABLE_JOINT_DATA_H_
