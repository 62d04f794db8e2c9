#ifndef ACCELCAL_REPORTING_ALLAN_REPORT_H_
#define ACCELCAL_REPORTING_ALLAN_REPORT_H_

// What `allan` prints and writes (docs/noise.md): per axis the Allan deviation table with its
// intervals and the fitted noise terms with sigma and units, and, when the log's poses are
// known, how much more a pose mean varies than white noise alone says (the factor by which
// white-noise weights inflate a calibration's chi2/dof). Formatting only.

#include <array>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "estimation/statistics/allan_variance.h"

namespace accelcal {

struct AllanSegment {
  double start_s = 0.0;
  double end_s = 0.0;
  long long sample_count = 0;
};

// One pose: its duration, and per axis the variance of its mean under the fitted model over
// the white-noise variance s_k^2 / n the calibration weighs it with (s_k^2 pooled within poses).
struct AllanPoseRatio {
  double start_s = 0.0;
  double duration_s = 0.0;
  long long sample_count = 0;
  std::array<double, 3> model_over_white{};
};

struct AllanReport {
  std::string log_path;
  std::string unit;         // of the results: "m/s^2" or the log's own ("count")
  std::string output_unit;  // the log's
  double gain = 1.0;        // results = gain * output
  std::string selection;    // how the segments were chosen
  double sample_period_s = 0.0;
  std::vector<AllanSegment> segments;
  AllanOptions options;
  int bootstrap_series = 0;
  std::array<AllanCurve, 3> curves;
  std::array<AllanNoiseFit, 3> fits;
  std::array<double, 3> pooled_pose_variance{};  // s_k^2 in the result unit squared
  std::vector<AllanPoseRatio> poses;
};

std::string AllanTable(const AllanReport& report);
nlohmann::json AllanJson(const AllanReport& report);

// The mean over poses and axes of model_over_white: the chi2/dof a calibration weighted by white
// noise should expect from this noise (0 when no pose is known).
double MeanPoseInflation(const AllanReport& report);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_ALLAN_REPORT_H_
