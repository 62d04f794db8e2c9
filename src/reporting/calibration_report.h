#ifndef ACCELCAL_REPORTING_CALIBRATION_REPORT_H_
#define ACCELCAL_REPORTING_CALIBRATION_REPORT_H_

// What calibrate says: the calibration file's record of a baseline fit (io/calibration_file.h),
// the fit's verdict, and the table a person reads; the file and the table come from the same
// record, so they cannot disagree.

#include <string>

#include "estimation/tilt_table/baseline_parameters.h"
#include "io/calibration_file.h"
#include "io/provenance.h"

namespace accelcal {

// The noise_variance_from of variances estimated from the fit's residuals.
inline constexpr char kNoiseEstimatedFromResiduals[] = "estimated from the residuals";

// The level of the verdict's chi-square test.
inline constexpr double kCalibrationVerdictAlpha = 0.01;

// One sentence: whether the stated noise explains the residuals (each axis's two-sided
// chi-square p-value at least `alpha`), or that variances estimated from the residuals leave
// nothing to check them against.
std::string CalibrationVerdict(const BaselineFit& fit, bool noise_estimated, double alpha);

// The two-axis calibration file's record of `fit`: parameters, covariance, g, the noise
// variances and where they came from (`noise_from`: a flag, a file, or
// kNoiseEstimatedFromResiduals), the chi-square and verdict, and the tilt test's `source`.
CalibrationRecord TwoAxisCalibrationRecord(const BaselineFit& fit, double gravity_mps2,
                                           double noise_variance_x, double noise_variance_y,
                                           const std::string& noise_from, const DataSource& source);

// The table calibrate prints after its data line; `out` is the calibration file written.
std::string CalibrationTable(const CalibrationRecord& record, const std::string& out);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_CALIBRATION_REPORT_H_
