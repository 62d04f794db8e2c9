#include "reporting/coverage_report.h"

#include <cmath>

#include "common/format.h"
#include "reporting/estimate_json.h"

namespace accelcal {
namespace {

std::string Percentages(const std::array<double, 3>& coverage) {
  return StringPrintf("%6.1f%% %6.1f%% %6.1f%%", 100 * coverage[0], 100 * coverage[1],
                      100 * coverage[2]);
}

nlohmann::json Levels(const std::array<double, 3>& coverage) {
  nlohmann::json json = nlohmann::json::object();
  for (int level = 0; level < 3; ++level)
    json[StringPrintf("%.2f", kCoverageLevels[level])] = coverage[level];
  return json;
}

double MinimumCoverage95(const CoverageResult& result) {
  double minimum = 1.0;
  for (const ParameterCoverage& row : result.parameters)
    minimum = std::min(minimum, row.interval_coverage[1]);
  return minimum;
}

}  // namespace

std::string CoverageTable(const std::string& scenario_name, const CoverageResult& result) {
  // clang-format off
  std::string text = StringPrintf(
      "accelcal coverage: is the baseline's reported uncertainty right? scenario %s, %d trials (%d threads, %.1f s)\n\n",
      scenario_name.c_str(), result.trials, result.threads, result.seconds);
  text +=
      "  parameter        truth         mean  bias/sigma  empirical sd  reported sd  ratio      68%     95%     99%\n";
  // clang-format on
  for (const Parameter parameter : kBaselineParameters) {
    const ParameterCoverage& row = result.parameters[BaselineIndex(parameter)];
    text += StringPrintf("  %-9s %+.4e  %+.4e  %+10.2f  %12.3e  %11.3e  %5.3f  %s\n",
                         Info(parameter).name, row.truth, row.mean, row.bias_sigma,
                         row.empirical_sd, row.reported_sd, row.empirical_sd / row.reported_sd,
                         Percentages(row.interval_coverage).c_str());
  }
  text += StringPrintf(
      "\n  ellipse (bias_x, scale_x)                                                         %s\n",
      Percentages(result.axis_ellipse_coverage[0]).c_str());
  text += StringPrintf(
      "  ellipse (bias_y, scale_y)                                                         %s\n",
      Percentages(result.axis_ellipse_coverage[1]).c_str());
  text += StringPrintf(
      "  endpoint ellipse (parameters + run noise)                                         %s\n",
      Percentages(result.endpoint_ellipse_coverage).c_str());
  // clang-format off
  text += StringPrintf(
      "\n  endpoint: mean error %+.2f sigma (x), %+.2f sigma (y); empirical/reported sd %.3f (x), %.3f (y)\n",
      result.endpoint_bias_sigma.x(), result.endpoint_bias_sigma.y(), result.endpoint_sd_ratio.x(),
      result.endpoint_sd_ratio.y());
  text += StringPrintf("  chi2/dof: %.4f (x), %.4f (y)\n", result.mean_chi2_per_dof.x(),
                       result.mean_chi2_per_dof.y());
  text += StringPrintf(
      "  Monte Carlo error of a coverage from %d trials: +-%.1f%% at 95%%, +-%.1f%% at 68%% (1 sd)\n",
      // clang-format on
      result.trials, 100 * std::sqrt(0.95 * 0.05 / result.trials),
      100 * std::sqrt(0.68 * 0.32 / result.trials));
  if (result.failed_trials > 0)
    text += StringPrintf("  %d trials failed to fit\n", result.failed_trials);
  return text;
}

std::string EffectImpactText(const std::vector<EffectImpact>& table) {
  if (table.empty()) return "";
  // clang-format off
  std::string text = StringPrintf(
      "\n  one effect hidden in the data, left out of the model (%d trials each): bias of each estimate in\n"
      "  reported sigmas, chi2/dof, and the 95%% coverage that remains (the lowest of the four parameters'\n"
      "  intervals, and the endpoint ellipse). Every row uses the same noise (common random numbers),\n"
      "  so the rows differ only by their effect.\n\n",
      table.front().result.trials);
  text +=
      "  effect                  size  unit        bias_x scale_x  bias_y scale_y  end x  end y  chi2/dof x      y  95% params  95% endpoint\n";
  for (const EffectImpact& row : table) {
    const ParameterInfo& info = Info(row.effect);
    const CoverageResult& r = row.result;
    text += StringPrintf(
        "  %-20s %7.3g  %-10s %+7.1f %+7.1f %+7.1f %+7.1f %+6.1f %+6.1f  %10.3f %6.3f  %9.1f%%  %11.1f%%\n",
        // clang-format on
        info.name, row.size, info.unit, r.parameters[0].bias_sigma, r.parameters[1].bias_sigma,
        r.parameters[2].bias_sigma, r.parameters[3].bias_sigma, r.endpoint_bias_sigma.x(),
        r.endpoint_bias_sigma.y(), r.mean_chi2_per_dof.x(), r.mean_chi2_per_dof.y(),
        100 * MinimumCoverage95(r), 100 * r.endpoint_ellipse_coverage[1]);
  }
  return text;
}

nlohmann::json CoverageJson(const CoverageResult& result) {
  nlohmann::json parameters = nlohmann::json::object();
  std::vector<std::string> names;
  for (const Parameter parameter : kBaselineParameters) {
    names.push_back(Info(parameter).name);
    const ParameterCoverage& row = result.parameters[BaselineIndex(parameter)];
    parameters[Info(parameter).name] = {{"truth", row.truth},
                                        {"mean", row.mean},
                                        {"bias_sigma", row.bias_sigma},
                                        {"empirical_sd", row.empirical_sd},
                                        {"reported_sd", row.reported_sd},
                                        {"interval_coverage", Levels(row.interval_coverage)}};
  }
  return {
      {"trials", result.trials},
      {"failed_trials", result.failed_trials},
      {"threads", result.threads},
      {"seconds", result.seconds},
      {"parameters", parameters},
      {"units", UnitsJson(names)},
      {"ellipse_coverage",
       {{"x", Levels(result.axis_ellipse_coverage[0])},
        {"y", Levels(result.axis_ellipse_coverage[1])},
        {"endpoint", Levels(result.endpoint_ellipse_coverage)}}},
      {"endpoint_bias_sigma",
       {{"x", result.endpoint_bias_sigma.x()}, {"y", result.endpoint_bias_sigma.y()}}},
      {"endpoint_sd_ratio",
       {{"x", result.endpoint_sd_ratio.x()}, {"y", result.endpoint_sd_ratio.y()}}},
      {"chi2_per_dof", {{"x", result.mean_chi2_per_dof.x()}, {"y", result.mean_chi2_per_dof.y()}}}};
}

nlohmann::json EffectImpactJson(const std::vector<EffectImpact>& table) {
  nlohmann::json rows = nlohmann::json::array();
  for (const EffectImpact& row : table) {
    nlohmann::json entry = CoverageJson(row.result);
    entry["name"] = Info(row.effect).name;
    entry["size"] = row.size;
    entry["unit"] = Info(row.effect).unit;
    rows.push_back(entry);
  }
  return rows;
}

std::string CoverageText(const CoverageReport& report) {
  return CoverageTable(report.scenario_name, report.baseline) + EffectImpactText(report.effects);
}

nlohmann::json CoverageReportJson(const CoverageReport& report) {
  nlohmann::json json = CoverageJson(report.baseline);
  json["problem"] = "coverage";
  json["scenario"] = report.scenario_name;
  json["seed"] = report.seed;
  json["effects"] = EffectImpactJson(report.effects);
  return json;
}

}  // namespace accelcal
