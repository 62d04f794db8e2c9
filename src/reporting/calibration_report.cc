#include "reporting/calibration_report.h"

#include <cmath>

#include "common/format.h"

namespace accelcal {

std::string CalibrationVerdict(const BaselineFit& fit, bool noise_estimated, double alpha) {
  if (noise_estimated) {
    return "noise variances estimated from the residuals: the covariance assumes white noise, "
           "and nothing is left to check them against; state them (--noise_variance) to test "
           "the fit";
  }
  std::string verdict;
  const AxisChiSquare* axes[2] = {&fit.chi2_x, &fit.chi2_y};
  for (int axis = 0; axis < 2; ++axis) {
    const AxisChiSquare& chi2 = *axes[axis];
    if (chi2.p_value >= alpha) continue;
    verdict +=
        StringPrintf("%saxis %c: chi2/dof = %.3f (p = %.2g), residuals %s than the stated noise",
                     verdict.empty() ? "" : "; ", axis == 0 ? 'x' : 'y', chi2.chi2 / chi2.dof,
                     chi2.p_value, chi2.chi2 > chi2.dof ? "larger" : "smaller");
  }
  if (verdict.empty()) {
    return StringPrintf(
        "the stated noise explains the residuals (chi2/dof x %.4f, y %.4f; two-sided p >= %g)",
        fit.chi2_x.chi2 / fit.chi2_x.dof, fit.chi2_y.chi2 / fit.chi2_y.dof, alpha);
  }
  return verdict + ": the baseline or the stated variance is wrong; run discover on this test";
}

CalibrationRecord TwoAxisCalibrationRecord(const BaselineFit& fit, double gravity_mps2,
                                           double noise_variance_x, double noise_variance_y,
                                           const std::string& noise_from,
                                           const DataSource& source) {
  CalibrationRecord record;
  record.geometry = "two_axis";
  for (const Parameter parameter : kBaselineParameters) {
    record.parameter_order.push_back(Info(parameter).name);
  }
  record.values = fit.parameters;
  record.covariance = fit.covariance;
  record.gravity_mps2 = gravity_mps2;
  record.noise_variance = {noise_variance_x, noise_variance_y};
  record.noise_variance_from = noise_from;
  const double alpha = kCalibrationVerdictAlpha;
  record.fit = {
      {"samples", fit.sample_count},
      {"chi2", {{"x", fit.chi2_x.chi2}, {"y", fit.chi2_y.chi2}}},
      {"dof", {{"x", fit.chi2_x.dof}, {"y", fit.chi2_y.dof}}},
      {"chi2_p_value", {{"x", fit.chi2_x.p_value}, {"y", fit.chi2_y.p_value}}},
      {"alpha", alpha},
      {"verdict", CalibrationVerdict(fit, noise_from == kNoiseEstimatedFromResiduals, alpha)}};
  record.source = source;
  return record;
}

std::string CalibrationTable(const CalibrationRecord& record, const std::string& out) {
  GeometryInfo geometry;
  if (!GeometryOf(record.geometry, record.output_unit, &geometry).ok()) return "";
  std::string text =
      "accelcal calibrate: bias and scale per axis from the tilt test alone\n\n"
      "  parameter   unit         value          sigma\n";
  for (int i = 0; i < record.values.size(); ++i) {
    text += StringPrintf("  %-10s  %-8s %+14.6e  %12.4e\n", record.parameter_order[i].c_str(),
                         geometry.units[i].c_str(), record.values[i],
                         std::sqrt(record.covariance(i, i)));
  }
  const std::string& from = record.noise_variance_from;
  text += StringPrintf("\n  g %.6g m/s^2; noise variance x %.6g, y %.6g (m/s^2)^2, %s%s\n",
                       record.gravity_mps2, record.noise_variance[0], record.noise_variance[1],
                       from == kNoiseEstimatedFromResiduals ? "" : "from ", from.c_str());
  text += "  samples " + record.fit["samples"].dump() +
          "; verdict: " + record.fit["verdict"].get<std::string>() + "\n";
  text += "  calibration file: " + out + " (apply --calibration=" + out + " --in=LOG --out=CSV)\n";
  return text;
}

}  // namespace accelcal
