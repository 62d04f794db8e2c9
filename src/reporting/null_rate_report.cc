#include "reporting/null_rate_report.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "common/format.h"

namespace accelcal {
namespace {

std::string JoinNumbers(const std::vector<double>& values) {
  std::string text;
  for (const double value : values) text += (text.empty() ? "" : ",") + RoundTripDouble(value);
  return text;
}

// What the design's tilt test is, in numbers.
std::string DescribeTilt(const TiltSchedule& tilt) {
  switch (tilt.kind) {
    case TiltSchedule::Kind::kUniform:
      return StringPrintf("%d samples uniform over [%.6g, %.6g] rad", tilt.sample_count,
                          tilt.theta_begin_rad, tilt.theta_end_rad);
    case TiltSchedule::Kind::kStaticPositions:
      return StringPrintf("%d samples at %zu static positions", tilt.sample_count,
                          tilt.positions_rad.size());
    case TiltSchedule::Kind::kList:
      return StringPrintf("%zu listed angles", tilt.angles_rad.size());
  }
  return "";
}

std::string NameCounts(const std::map<std::string, int>& counts) {
  std::string text;
  for (const auto& [name, count] : counts)
    text += (text.empty() ? "" : ", ") + name + StringPrintf(" %d", count);
  return text.empty() ? "none" : text;
}

void AddCounts(const std::map<std::string, int>& from, std::map<std::string, int>* to) {
  for (const auto& [name, count] : from) (*to)[name] += count;
}

std::string Table(const std::string& header, const NullRateResult& result) {
  std::string text = header;
  text += StringPrintf("\n  %-16s %6s %6s %6s %10s %7s  %7s %6s %7s %9s %6s\n", "design", "noise",
                       "alpha", "n", "not expl.", "rate", "effects", "noise", "checks", "ambiguous",
                       "errors");
  bool any_cell_above = false;
  for (const NullRateCell& cell : result.cells) {
    // The cell alone against its own bound: with many cells, one above is expected by chance.
    const double n = std::max(cell.verdicts, 1);
    const bool above = cell.rate > cell.alpha + 2.0 * std::sqrt(cell.alpha * (1 - cell.alpha) / n);
    any_cell_above = any_cell_above || above;
    text += StringPrintf("  %-16s %6s %6g %6d %10d %6.1f%%%s %7d %6d %7d %9d %6d\n",
                         cell.design.c_str(), ("x" + RoundTripDouble(cell.noise_factor)).c_str(),
                         cell.alpha, cell.verdicts, cell.not_explained, 100.0 * cell.rate,
                         above ? "*" : " ", cell.with_effects, cell.with_noise_findings,
                         cell.with_flagged_checks, cell.cannot_tell_apart, cell.errors);
  }
  text +=
      "  (n: datasets with a verdict; not expl.: verdict other than \"explained\"; then how many\n"
      "   named an effect, a noise finding, a flagged residual check, or could not tell apart)\n";
  if (any_cell_above)
    text += "  (*: above alpha + 2 sd for that cell alone; a few such cells are chance)\n";

  text += "\n  pooled over every design and noise factor, per alpha:\n";
  for (const PooledNullRate& pooled : result.pooled) {
    text += StringPrintf(
        // clang-format off
        "  alpha %-6g %d/%d = %.2f%% (sd %.2f%%); bound alpha + 2 sqrt(alpha(1-alpha)/n) = %.2f%%: %s\n",
        // clang-format on
        pooled.alpha, pooled.not_explained, pooled.verdicts, 100.0 * pooled.rate,
        100.0 * pooled.rate_stddev, 100.0 * pooled.bound,
        pooled.within ? "within" : "ABOVE the bound");
    if (pooled.errors > 0)
      text += StringPrintf("  alpha %-6g %d datasets where discover returned an error\n",
                           pooled.alpha, pooled.errors);
  }
  text += "\n  what the false discoveries claimed, per alpha (datasets):\n";
  for (const PooledNullRate& pooled : result.pooled) {
    std::map<std::string, int> verdicts, effects, noise, checks;
    for (const NullRateCell& cell : result.cells) {
      if (cell.alpha != pooled.alpha) continue;
      AddCounts(cell.verdict_counts, &verdicts);
      AddCounts(cell.effects_named, &effects);
      AddCounts(cell.noise_findings_named, &noise);
      AddCounts(cell.checks_flagged, &checks);
    }
    verdicts.erase("explained");
    text += StringPrintf("  alpha %g: verdicts %s; effects %s; noise %s; checks %s\n", pooled.alpha,
                         NameCounts(verdicts).c_str(), NameCounts(effects).c_str(),
                         NameCounts(noise).c_str(), NameCounts(checks).c_str());
  }
  text += StringPrintf("\n  (%.0f s on %d thread%s)\n", result.seconds, result.threads,
                       result.threads == 1 ? "" : "s");
  return text;
}

nlohmann::json Json(const nlohmann::json& header, const NullRateResult& result) {
  nlohmann::json json = header;
  nlohmann::json cells = nlohmann::json::array();
  for (const NullRateCell& cell : result.cells) {
    cells.push_back({{"design", cell.design},
                     {"noise_factor", cell.noise_factor},
                     {"alpha", cell.alpha},
                     {"datasets", cell.datasets},
                     {"errors", cell.errors},
                     {"verdicts", cell.verdicts},
                     {"not_explained", cell.not_explained},
                     {"rate", cell.rate},
                     {"with_effects", cell.with_effects},
                     {"with_noise_findings", cell.with_noise_findings},
                     {"with_flagged_checks", cell.with_flagged_checks},
                     {"cannot_tell_apart", cell.cannot_tell_apart},
                     {"verdict_counts", cell.verdict_counts},
                     {"effects_named", cell.effects_named},
                     {"noise_findings_named", cell.noise_findings_named},
                     {"checks_flagged", cell.checks_flagged}});
  }
  nlohmann::json pooled = nlohmann::json::array();
  for (const PooledNullRate& rate : result.pooled) {
    pooled.push_back({{"alpha", rate.alpha},
                      {"verdicts", rate.verdicts},
                      {"errors", rate.errors},
                      {"not_explained", rate.not_explained},
                      {"rate", rate.rate},
                      {"rate_stddev", rate.rate_stddev},
                      {"alpha_stddev", rate.alpha_stddev},
                      {"bound", rate.bound},
                      {"within", rate.within}});
  }
  json["cells"] = cells;
  json["pooled"] = pooled;
  json["seconds"] = result.seconds;
  json["threads"] = result.threads;
  return json;
}

// Where the data came from and the command that reproduces it, for the screen and the JSON.
void Header(const NullRateReport& report, std::string* text, nlohmann::json* json) {
  const NullRateOptions& options = report.options;
  const Scenario& course = report.course;
  const std::string command = StringPrintf(
      "null_rate --designs=%s --noise_factors=%s --alphas=%s --datasets=%d --seed=%llu",
      JoinStrings(options.designs, ",").c_str(), JoinNumbers(options.noise_factors).c_str(),
      JoinNumbers(options.alphas).c_str(), options.datasets,
      static_cast<unsigned long long>(options.seed));
  *text = StringPrintf(
      "accelcal null_rate: how often discover says anything but \"explained\" on null data\n"
      "  data     simulated in-process: scenario %s, seed %llu; truth: bias and scale of Table 1,\n"
      "           every other effect neutral, white Gaussian noise of the stated variance (both\n"
      "           scaled by the noise factor)\n",
      course.name.c_str(), static_cast<unsigned long long>(options.seed));
  nlohmann::json designs = nlohmann::json::array();
  for (const std::string& name : options.designs) {
    // The course's schedule is whatever the scenario says; the others are fixed.
    const std::string tilt = NullRateDesignDescription(name) +
                             (name == "course" ? ", " + DescribeTilt(course.tilt) : std::string());
    *text += StringPrintf("  %-8s %s: %s\n", name == options.designs.front() ? "designs" : "",
                          name.c_str(), tilt.c_str());
    designs.push_back({{"name", name}, {"tilt", tilt}});
  }
  *text += StringPrintf("  command  %s\n", command.c_str());
  *json = {{"problem", "null_rate"},
           {"data", "simulated"},
           {"scenario", course.name},
           {"seed", options.seed},
           {"command", command},
           {"designs", designs},
           {"noise_factors", options.noise_factors},
           {"alphas", options.alphas},
           {"datasets_per_cell", options.datasets}};
}

}  // namespace

std::string NullRateText(const NullRateReport& report) {
  std::string header;
  nlohmann::json json_header;
  Header(report, &header, &json_header);
  return Table(header, report.study);
}

nlohmann::json NullRateJson(const NullRateReport& report) {
  std::string header;
  nlohmann::json json_header;
  Header(report, &header, &json_header);
  return Json(json_header, report.study);
}

}  // namespace accelcal
