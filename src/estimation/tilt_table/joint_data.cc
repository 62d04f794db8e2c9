#include "estimation/tilt_table/joint_data.h"

#include <algorithm>
#include <optional>

#include "estimation/tilt_table/linear_ls.h"
#include "estimation/tilt_table/parameter_estimate.h"

namespace accelcal {

// What one noise model of the data prepares. Each part is computed on first use, so a
// caller that never ties the run to a landmark never dead-reckons it.
struct JointData::Prepared {
  // The noise model these were computed for.
  double gravity_mps2 = 0.0;
  AxisNoise noise[2];

  Status baseline_status;
  BaselineFit baseline;

  std::optional<Status> trajectory_status;
  DeadReckoningResult trajectory;

  std::optional<Status> compressed_status;
  std::unique_ptr<CompressedCalibrationResidual> compressed[2];

  bool Matches(const JointOptions& options) const {
    if (options.gravity_mps2 != gravity_mps2) return false;
    for (int a = 0; a < 2; ++a) {
      const AxisNoise other = options.Noise(a);
      if (other.variance != noise[a].variance || other.correlation != noise[a].correlation ||
          other.outliers != noise[a].outliers) {
        return false;
      }
    }
    return true;
  }
};

JointData::JointData(const CalibrationTest& test, const VehicleRun& run,
                     const RunConditions& conditions, const std::vector<Landmark>& landmarks)
    : test_(test), run_(run), conditions_(conditions), landmarks_(landmarks) {}

JointData::~JointData() = default;

const Landmark* JointData::FindLandmark(const std::string& name) const {
  for (const Landmark& landmark : landmarks_) {
    if (landmark.name == name) return &landmark;
  }
  return nullptr;
}

JointData::Prepared& JointData::For(const JointOptions& options) const {
  for (const std::unique_ptr<Prepared>& prepared : prepared_) {
    if (prepared->Matches(options)) return *prepared;
  }
  auto prepared = std::make_unique<Prepared>();
  prepared->gravity_mps2 = options.gravity_mps2;
  prepared->noise[0] = options.Noise(0);
  prepared->noise[1] = options.Noise(1);
  // The closed-form baseline every joint solve starts from (and whose run-noise covariance
  // whitens the endpoint residual): the stated variances, every sample.
  LinearLsOptions linear;
  linear.gravity_mps2 = options.gravity_mps2;
  linear.noise_variance_x = options.noise_variance_x;
  linear.noise_variance_y = options.noise_variance_y;
  prepared->baseline_status = EstimateLinearLs(test_, linear, &prepared->baseline);
  prepared_.push_back(std::move(prepared));
  return *prepared_.back();
}

Status JointData::Baseline(const JointOptions& options, const BaselineFit** fit) const {
  const Prepared& prepared = For(options);
  *fit = &prepared.baseline;
  return prepared.baseline_status;
}

// The baseline with the noise model's variance ratios and correlation: the start of every
// solve, and the estimate whose run is dead-reckoned.
static ParameterEstimate BaselineStart(const BaselineFit& fit, const JointOptions& options,
                                       const RunConditions& conditions) {
  ParameterEstimate start = FromBaselineFit(fit);
  start.values[Parameter::kNoiseVarianceX] = options.noise_variance_x / conditions.noise_variance_x;
  start.values[Parameter::kNoiseVarianceY] = options.noise_variance_y / conditions.noise_variance_y;
  start.noise_correlation = options.noise_correlation;
  return start;
}

Status JointData::BaselineTrajectory(const JointOptions& options,
                                     const DeadReckoningResult** trajectory) const {
  Prepared& prepared = For(options);
  ACCELCAL_RETURN_IF_ERROR(prepared.baseline_status);
  if (!prepared.trajectory_status) {
    TrajectoryOptions trajectory_options;
    trajectory_options.path_stride = std::max(1, run_.size());
    prepared.trajectory_status =
        DeadReckon(run_, conditions_, BaselineStart(prepared.baseline, options, conditions_),
                   trajectory_options, &prepared.trajectory);
  }
  *trajectory = &prepared.trajectory;
  return *prepared.trajectory_status;
}

Status JointData::CompressedResiduals(
    const JointOptions& options,
    std::unique_ptr<CompressedCalibrationResidual> residuals[2]) const {
  Prepared& prepared = For(options);
  ACCELCAL_RETURN_IF_ERROR(prepared.baseline_status);
  if (!prepared.compressed_status) {
    // About the point every solve starts from: the baseline, every effect neutral.
    ModelParameters<double> reference;
    const ParameterEstimate start = BaselineStart(prepared.baseline, options, conditions_);
    for (const Parameter parameter : start.free) reference[parameter] = start.Value(parameter);
    reference[Parameter::kNoiseVarianceX] = start.values[Parameter::kNoiseVarianceX];
    reference[Parameter::kNoiseVarianceY] = start.values[Parameter::kNoiseVarianceY];
    prepared.compressed_status = CompressedCalibrationResidual::Make(
        test_, options.gravity_mps2, prepared.noise, reference, prepared.compressed);
  }
  ACCELCAL_RETURN_IF_ERROR(*prepared.compressed_status);
  for (int a = 0; a < 2; ++a) {
    residuals[a] = std::make_unique<CompressedCalibrationResidual>(*prepared.compressed[a]);
  }
  return Status::Ok();
}

}  // namespace accelcal
