#include "reporting/allan_report.h"

#include <cmath>

#include "common/format.h"

namespace accelcal {
namespace {

constexpr const char* kAxes[3] = {"x", "y", "z"};

std::string TermLine(const char* name, const AllanTerm& term, const std::string& unit,
                     double confidence) {
  if (!term.fitted) return StringPrintf("  %-17s not fitted\n", name);
  if (term.below_model) {
    return StringPrintf(
        "  %-17s not resolved: fitted %.4g, lower than the model gives with it at 0; "
        "%.0f%% upper bound %.4g %s\n",
        name, term.value, 100.0 * confidence, term.high, unit.c_str());
  }
  if (!term.resolved) {
    return StringPrintf("  %-17s not resolved: %.4g, %.0f%% upper bound %.4g %s\n", name,
                        term.value, 100.0 * confidence, term.high, unit.c_str());
  }
  return StringPrintf("  %-17s %.4g +- %.2g %s  (%.0f%%: %.4g .. %.4g)\n", name, term.value,
                      term.stddev, unit.c_str(), 100.0 * confidence, term.low, term.high);
}

nlohmann::json TermJson(const AllanTerm& term, const std::string& unit) {
  nlohmann::json json = {{"fitted", term.fitted}, {"resolved", term.resolved}, {"unit", unit}};
  if (!term.fitted) {
    for (const char* key :
         {"value", "stddev", "low", "high", "below_model", "squared", "squared_stddev"})
      json[key] = nullptr;
    return json;
  }
  json["value"] = term.value;
  json["stddev"] = term.stddev;
  json["low"] = term.low;
  json["high"] = term.high;
  json["below_model"] = term.below_model;
  json["squared"] = term.squared_raw;
  json["squared_stddev"] = term.squared_stddev;
  return json;
}

}  // namespace

double MeanPoseInflation(const AllanReport& report) {
  double sum = 0.0;
  int count = 0;
  for (const AllanPoseRatio& pose : report.poses) {
    for (double ratio : pose.model_over_white) {
      sum += ratio;
      ++count;
    }
  }
  return count > 0 ? sum / count : 0.0;
}

std::string AllanTable(const AllanReport& report) {
  const std::string& u = report.unit;
  std::string text = StringPrintf(
      "Allan deviation of %zu static segment%s (%s), %.6g s per sample, results in %s%s\n",
      report.segments.size(), report.segments.size() == 1 ? "" : "s", report.selection.c_str(),
      report.sample_period_s, u.c_str(),
      report.gain != 1.0
          ? StringPrintf(" (%.6g %s per %s)", report.gain, u.c_str(), report.output_unit.c_str())
                .c_str()
          : "");
  for (const AllanSegment& segment : report.segments) {
    text += StringPrintf("  segment %.3f .. %.3f s, %lld samples\n", segment.start_s, segment.end_s,
                         segment.sample_count);
  }
  for (int k = 0; k < 3; ++k) {
    const AllanCurve& curve = report.curves[k];
    const AllanNoiseFit& fit = report.fits[k];
    text += StringPrintf("\naxis %s: Allan deviation (%s), %.0f%% interval, model\n", kAxes[k],
                         u.c_str(), 100.0 * report.options.confidence);
    text +=
        "  tau_s      adev        low         high        model       clusters  edf     dominant\n";
    for (const AllanPoint& p : curve.points) {
      text += StringPrintf("  %-10.4g %-11.4g %-11.4g %-11.4g %-11.4g %-9lld %-7.1f %s\n", p.tau_s,
                           std::sqrt(p.avar), std::sqrt(p.avar_low), std::sqrt(p.avar_high),
                           std::sqrt(ModelAllanVariance(fit, p.tau_s)), p.independent_clusters,
                           p.edf, AllanNoiseKindName(p.dominant));
    }
    text += StringPrintf(
        "  fit: chi2 %.3g on %d dof; intervals from %s%s\n", fit.chi2, fit.dof,
        fit.covariance_method.c_str(),
        fit.bootstrap_series > 0 ? StringPrintf(" (%d series)", fit.bootstrap_series).c_str() : "");
    if (fit.chi2_bootstrap_fraction >= 0.0) {
      text += StringPrintf("  chi2 reached by %.1f%% of the series simulated from the terms%s\n",
                           100.0 * fit.chi2_bootstrap_fraction,
                           fit.chi2_bootstrap_fraction < 0.01
                               ? ": the terms do not describe this curve, and the intervals "
                                 "assume they do"
                               : "");
    }
    const double c = report.options.confidence;
    text += TermLine("white noise N", fit.white, u + "/sqrt(Hz)", c);
    text += TermLine("bias instability B", fit.bias_instability, u, c);
    text += TermLine("random walk K", fit.random_walk, u + "*sqrt(Hz)", c);
  }
  if (!report.poses.empty()) {
    text += StringPrintf(
        "\n%zu poses: variance of a pose mean from the fitted model over white noise's "
        "(s^2/n)\n  axis  mean   min    max\n",
        report.poses.size());
    for (int k = 0; k < 3; ++k) {
      double sum = 0.0, low = 1e300, high = 0.0;
      for (const AllanPoseRatio& pose : report.poses) {
        sum += pose.model_over_white[k];
        low = std::min(low, pose.model_over_white[k]);
        high = std::max(high, pose.model_over_white[k]);
      }
      text += StringPrintf("  %-5s %-6.3g %-6.3g %-6.3g\n", kAxes[k], sum / report.poses.size(),
                           low, high);
    }
    text += StringPrintf(
        "  chi2/dof a fit weighted by white noise should expect from this noise: %.3g\n",
        MeanPoseInflation(report));
  }
  return text;
}

nlohmann::json AllanJson(const AllanReport& report) {
  nlohmann::json json;
  json["problem"] = "allan";
  json["log"] = report.log_path;
  json["unit"] = report.unit;
  json["output_unit"] = report.output_unit;
  json["gain"] = report.gain;
  json["selection"] = report.selection;
  json["sample_period_s"] = report.sample_period_s;
  json["confidence"] = report.options.confidence;
  json["segments"] = nlohmann::json::array();
  for (const AllanSegment& s : report.segments)
    json["segments"].push_back(
        {{"start_s", s.start_s}, {"end_s", s.end_s}, {"samples", s.sample_count}});
  nlohmann::json axes = nlohmann::json::object();
  for (int k = 0; k < 3; ++k) {
    const AllanNoiseFit& fit = report.fits[k];
    nlohmann::json points = nlohmann::json::array();
    for (const AllanPoint& p : report.curves[k].points) {
      points.push_back({{"tau_s", p.tau_s},
                        {"cluster_samples", p.cluster_samples},
                        {"adev", std::sqrt(p.avar)},
                        {"adev_low", std::sqrt(p.avar_low)},
                        {"adev_high", std::sqrt(p.avar_high)},
                        {"adev_model", std::sqrt(ModelAllanVariance(fit, p.tau_s))},
                        {"independent_clusters", p.independent_clusters},
                        {"edf", p.edf},
                        {"dominant", AllanNoiseKindName(p.dominant)}});
    }
    axes[kAxes[k]] = {
        {"points", points},
        {"white_noise", TermJson(fit.white, report.unit + "/sqrt(Hz)")},
        {"bias_instability", TermJson(fit.bias_instability, report.unit)},
        {"random_walk", TermJson(fit.random_walk, report.unit + "*sqrt(Hz)")},
        {"fit",
         {{"chi2", fit.chi2},
          {"dof", fit.dof},
          {"chi2_bootstrap_fraction", fit.chi2_bootstrap_fraction < 0.0
                                          ? nlohmann::json()
                                          : nlohmann::json(fit.chi2_bootstrap_fraction)},
          {"covariance", fit.covariance_method},
          {"bootstrap_series", fit.bootstrap_series}}},
        {"pooled_pose_variance", report.pooled_pose_variance[k]}};
  }
  json["axes"] = axes;
  if (!report.poses.empty()) {
    nlohmann::json poses = nlohmann::json::array();
    for (const AllanPoseRatio& pose : report.poses) {
      poses.push_back({{"start_s", pose.start_s},
                       {"duration_s", pose.duration_s},
                       {"samples", pose.sample_count},
                       {"model_over_white", pose.model_over_white}});
    }
    json["poses"] = poses;
    json["expected_chi2_per_dof"] = MeanPoseInflation(report);
  }
  return json;
}

}  // namespace accelcal
