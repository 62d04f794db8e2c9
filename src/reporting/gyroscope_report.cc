#include "reporting/gyroscope_report.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/format.h"
#include "estimation/gyroscope/gyroscope_determination.h"
#include "reporting/calibrate_imu_report.h"

namespace accelcal {
namespace {

// Unknown i's estimate (the 9, the offsets, then the effect coefficients estimated).
double GyroscopeUnknownValue(const GyroscopeMlResult& g, int i) {
  return i < kGyroscopeParameterCount ? g.parameters[i]
         : i < kGyroscopeCalibrationCount
             ? g.offset[i - kGyroscopeParameterCount]
             : g.effects[g.effects_estimated[i - kGyroscopeCalibrationCount]];
}

// imu_tk's value of unknown i (the 9, then the offsets) on this session, when it ran.
double ImuTkValue(const CalibrateImuReport& report, int i) {
  return i < kGyroscopeParameterCount ? report.gyroscope.parameters[i]
                                      : report.gyroscope.offset[i - kGyroscopeParameterCount];
}

}  // namespace

// What the fit does with the Earth's rate: its vertical part held (latitude given) or estimated
// with its prior, the horizontal part as noise; or nothing.
std::string EarthVerticalClause(const CalibrateImuReport& report) {
  const GyroscopeMlOptions& options = report.gyroscope_ml_options;
  const GyroscopeMlResult& g = report.gyroscope_ml;
  if (!options.earth_rate_as_noise) return "; the fit leaves it out";
  if (options.latitude_given) {
    return StringPrintf(
        "; its vertical part, Omega sin(%.4g deg) = %.3g rad/s about the up direction in every "
        "pose (--latitude_deg), is in the model, its horizontal part (direction in the body not "
        "known) counted as noise, and over the turns all of it",
        options.latitude_rad * 180.0 / M_PI, g.earth_vertical_rate_rad_s);
  }
  if (g.earth_vertical_held) {
    return "; its vertical part (Omega sin(latitude) about the up direction in every pose, the "
           "latitude not given) traded with the gains when estimated with them (they fell towards "
           "0: a pose-dependent offset the 12 unknowns do not model, such as a g-sensitivity), so "
           "it is held at its prior's mean, 0 (give --latitude_deg to hold the Earth's share); its "
           "horizontal part is counted as noise";
  }
  const bool determined = g.earth_vertical_rate_stddev < 0.5 * g.earth_vertical_prior_stddev;
  return StringPrintf(
      "; its vertical part (Omega sin(latitude) about the up direction in every pose, the "
      "latitude not given) is an unknown with the prior 0 +- %.2g rad/s: %.3g +- %.2g rad/s, %s; "
      "static poses cannot tell it from a g-sensitivity's isotropic part (G = (e/g) I), so it is "
      "held apart and never named as one: give --latitude_deg to hold the Earth's share and test "
      "the rest; its horizontal part is counted as noise",
      g.earth_vertical_prior_stddev, g.earth_vertical_rate_rad_s, g.earth_vertical_rate_stddev,
      determined ? "determined by the poses"
                 : "bounded by its prior more than determined by the poses");
}

std::string EarthRateSentence(const CalibrateImuReport& report) {
  const GyroscopeMlResult& g = report.gyroscope_ml;
  const double earth = kEarthRateRadPerS;
  auto compare = [&](double sigma) {
    return StringPrintf("%s (%.2g rad/s)", earth > sigma ? "above" : "below", sigma);
  };
  return StringPrintf(
      "Earth's rate (%.3g rad/s): %s one pose mean's sigma, %s the offsets' sigma; over a turn it "
      "adds %.2g rad, %s the turn's angle noise (%.2g rad)%s",
      earth, compare(g.pose_mean_sigma_rad_s).c_str(), compare(g.offset_sigma_rad_s).c_str(),
      g.turn_earth_angle_rad, g.turn_earth_angle_rad > g.turn_angle_sigma_rad ? "above" : "below",
      g.turn_angle_sigma_rad, EarthVerticalClause(report).c_str());
}

std::string GyroscopeTurnedAboutSentence(const GyroscopeMlResult& g) {
  const std::array<double, 3> shares = GyroscopeTurnShares(g);
  return StringPrintf(
      "The turns went %.3g rad about x, %.3g about y, %.3g about z (%.0f%%, %.0f%%, %.0f%%; a gain "
      "or a misalignment column is determined by turns about its axis)",
      g.turned_about_rad[0], g.turned_about_rad[1], g.turned_about_rad[2], 100.0 * shares[0],
      100.0 * shares[1], 100.0 * shares[2]);
}

std::string GyroscopePoorlyDeterminedTable(const CalibrateImuReport& report) {
  const GyroscopeMlResult& g = report.gyroscope_ml;
  return GyroscopeTurnedAboutSentence(g) + ".\n" +
         PoorlyDeterminedLines("Poorly determined, gyroscope", "this session's turns and poses",
                               report.gyroscope_discovery.poorly_determined,
                               [&](int i) { return GyroscopeUnknownValue(g, i); });
}

std::string GyroscopeMlTable(const CalibrateImuReport& report) {
  const GyroscopeMlResult& g = report.gyroscope_ml;
  const GyroscopeOutputUnit unit = report.gyroscope_ml_options.unit;
  const char* unit_name = GyroscopeOutputUnitName(unit);
  const bool with_imu_tk = report.has_gyroscope_calibration;
  const bool example = IsImuTkGyroscopeExample(report);
  std::ostringstream out;
  out << "\nGyroscope: maximum likelihood with the accelerometer's poses, w = T K (u - b) in rad/s "
         "(docs/gyroscope.md)\n";
  out << StringPrintf(
      "gyroscope log: %s, outputs in %s (--gyro_unit); offsets from every pose's mean, turns "
      "integrated by the fourth-order rule; start: %s\n",
      report.gyroscope_path.empty() ? "the log's gyroscope columns" : report.gyroscope_path.c_str(),
      unit_name,
      with_imu_tk
          ? "imu_tk's result"
          : StringPrintf("gains %.9g (%s)", report.gyroscope_options.initial[kGyroscopeGainX],
                         report.initial_gyro_gain_from.c_str())
                .c_str());
  out << StringPrintf(
      "noise: white %.3g, %.3g, %.3g %s per sample (pooled within the %zu poses); bias wander "
      "between poses %.3g, %.3g, %.3g %s (sd, from the scatter of the poses' offsets; 0: none "
      "beyond the white noise); the turns' angle sigma %.2g rad (median over %zu turns)\n\n",
      std::sqrt(g.noise_variance[0]), std::sqrt(g.noise_variance[1]),
      std::sqrt(g.noise_variance[2]), unit_name, g.rest_means.size(),
      std::sqrt(g.bias_wander_variance[0]), std::sqrt(g.bias_wander_variance[1]),
      std::sqrt(g.bias_wander_variance[2]), unit_name, g.turn_angle_sigma_rad, g.turns.size());
  const GyroscopeMlResult& baseline = report.gyroscope_discovery.baseline;
  const bool with_baseline = !g.effects_estimated.empty();
  if (with_baseline) {
    out << "The model discovery settled on, its effect terms below the 12; the 12 unknowns' fit "
           "beside them (baseline):\n";
  }
  out << StringPrintf("  %-32s %-16s %-28s", "parameter", "unit", "estimate +- sigma");
  if (with_baseline) out << StringPrintf(" %-14s %-9s", "baseline", "(ml-baseline)/sigma");
  if (with_imu_tk) out << StringPrintf(" %-14s %-9s", "imu_tk", "(ml-imu_tk)/sigma");
  if (example) out << StringPrintf(" %s", "datasheet");
  out << "\n";
  for (int i = 0; i < g.stddev.size(); ++i) {
    const double value = GyroscopeUnknownValue(g, i);
    out << StringPrintf("  %-32s %-16s %-28s", g.names[i].c_str(), g.units[i].c_str(),
                        StringPrintf("%.8g +- %.2g", value, g.stddev[i]).c_str());
    if (with_baseline && i < kGyroscopeCalibrationCount) {
      const double before = GyroscopeUnknownValue(baseline, i);
      out << StringPrintf(" %-14.8g %+9.2f", before, (value - before) / g.stddev[i]);
    } else if (with_baseline) {
      out << " -";  // an effect term: no baseline value (nor imu_tk's or the datasheet's)
    }
    if (with_imu_tk && i < kGyroscopeCalibrationCount) {
      const double imu_tk = ImuTkValue(report, i);
      out << StringPrintf(" %-14.8g %+9.2f", imu_tk, (value - imu_tk) / g.stddev[i]);
    }
    if (example && i < kGyroscopeCalibrationCount)
      out << StringPrintf("   %s", DatasheetGyroscopeValue(i));
    out << "\n";
  }
  out << StringPrintf("  inverse gain (%s per rad/s):", unit_name);
  for (int k = 0; k < 3; ++k) {
    const double gain = g.parameters[kGyroscopeGainX + k];
    out << StringPrintf(" %c %.6g +- %.2g", "xyz"[k], 1.0 / gain,
                        g.stddev[kGyroscopeGainX + k] / (gain * gain));
  }
  if (with_imu_tk) {
    const std::array<double, 3> inverse = report.gyroscope.inverse_gains();
    out << StringPrintf("   (imu_tk: %.6g %.6g %.6g)", inverse[0], inverse[1], inverse[2]);
  }
  out << "\n";
  if (with_imu_tk) {
    out << "  (imu_tk's offsets are its initial rest's means, not estimated; it gives no sigma)\n";
  } else if (!report.imu_tk_gyroscope_status.ok()) {
    out << "  (imu_tk's gyroscope calibration gave no result: "
        << report.imu_tk_gyroscope_status.message() << ")\n";
  }
  out << "\n" << GyroscopePoorlyDeterminedTable(report);
  double worst_angle = 0.0;
  int worst = -1;
  for (size_t t = 0; t < g.turns.size(); ++t) {
    if (g.turns[t].residual_angle_rad > worst_angle) {
      worst_angle = g.turns[t].residual_angle_rad;
      worst = static_cast<int>(t);
    }
  }
  out << StringPrintf(
      "\nFit: chi2 %.1f on %d degrees of freedom added to the accelerometer's (p = %.3g; the "
      "gyroscope's %zu pose means and %zu turns, each turn's two components)",
      g.chi2_gyroscope, g.gyroscope_degrees_of_freedom, g.gyroscope_p_value, g.rest_means.size(),
      g.turns.size());
  out << StringPrintf(
      "; rest %.1f, turns %.1f. The largest turn residual: %.3g mrad (turn %d, poses %d to %d, "
      "its angle sigma %.3g mrad). The joint fit moves the accelerometer's parameters by at "
      "most %.2f sigma.\n",
      g.chi2_rest, g.chi2_turns, 1e3 * worst_angle, worst + 1,
      worst >= 0 ? g.turns[worst].pose_before + 1 : 0,
      worst >= 0 ? g.turns[worst].pose_before + 2 : 0,
      worst >= 0 ? 1e3 * g.turns[worst].angle_stddev_rad : 0.0, g.accelerometer_shift_sigma);
  out << EarthRateSentence(report) << ".\n";
  for (const GyroscopeClippedTurn& clipped : g.clipped_turns) {
    out << StringPrintf(
        "Turn from pose %d to %d left out: the gyroscope's %c output sits at %.9g, the end of its "
        "range, for %d samples (the rate was beyond what it measures; turn more slowly)\n",
        clipped.pose_before + 1, clipped.pose_before + 2, "xyz"[clipped.axis], clipped.rail,
        clipped.samples);
  }
  out << GyroscopeDiscoveryTable(report.gyroscope_discovery,
                                 report.gyroscope_discovery_options.alpha);
  return out.str();
}

std::string GyroscopeDiscoveryTable(const GyroscopeDiscoveryResult& d, double alpha) {
  std::ostringstream out;
  out << StringPrintf(
      "\nGyroscope discovery (alpha = %g: noise alpha/4, effects alpha/2, what remains "
      "alpha/4; docs/gyroscope.md)\n",
      alpha);
  out << "  noise: " << d.noise_note << "\n";
  for (const GyroscopeEffectScore& score : d.scores) {
    out << StringPrintf("  step %d  %-20s chi2 %8.2f on %d  p = %-10.3g%s\n", score.step,
                        score.effect.c_str(), score.delta_chi2, score.coefficients, score.p_value,
                        score.significant ? "  significant" : "");
  }
  for (const std::string& line : d.not_tested) out << "  not tested: " << line << "\n";
  for (const GyroscopeFoundEffect& effect : d.effects) {
    out << StringPrintf("  found %s (the final model loses chi2 %.1f without it, p = %.3g):",
                        effect.effect.c_str(), effect.delta_chi2, effect.p_value);
    for (size_t i = 0; i < effect.names.size(); ++i) {
      out << StringPrintf("%s %s = %.3g +- %.2g", i == 0 ? "" : ",", effect.names[i].c_str(),
                          effect.estimates[i], effect.stddevs[i]);
    }
    out << "\n";
  }
  for (const ResidualCheck& check : d.checks) {
    out << StringPrintf("  check %-12s %s  p = %.3g%s\n", check.name.c_str(),
                        check.description.c_str(), check.p_value, check.flagged ? "  flagged" : "");
  }
  for (const GyroscopeLookAlike& look_alike : d.look_alikes) {
    out << StringPrintf("  look-alike: %s and %s (chi2 %.1f apart)\n", look_alike.effect.c_str(),
                        look_alike.alternative.c_str(), look_alike.worse);
  }
  out << "Verdict (gyroscope, " << VerdictCode(d.verdict_code) << "): " << d.verdict << "\n";
  return out.str();
}

nlohmann::json GyroscopeDiscoveryJson(const GyroscopeDiscoveryResult& d, double alpha) {
  nlohmann::json scores = nlohmann::json::array();
  for (const GyroscopeEffectScore& score : d.scores) {
    scores.push_back({{"step", score.step},
                      {"effect", score.effect},
                      {"delta_chi2", score.delta_chi2},
                      {"coefficients", score.coefficients},
                      {"p_value", score.p_value},
                      {"significant", score.significant}});
  }
  nlohmann::json effects = nlohmann::json::array();
  for (const GyroscopeFoundEffect& effect : d.effects) {
    effects.push_back({{"effect", effect.effect},
                       {"coefficients", effect.names},
                       {"estimates", effect.estimates},
                       {"stddev", effect.stddevs},
                       {"delta_chi2", effect.delta_chi2},
                       {"p_value", effect.p_value}});
  }
  nlohmann::json checks = nlohmann::json::array();
  for (const ResidualCheck& check : d.checks) {
    checks.push_back({{"name", check.name},
                      {"statistic", check.statistic},
                      {"dof", check.dof},
                      {"p_value", check.p_value},
                      {"flagged", check.flagged},
                      {"description", check.description},
                      {"shape_class", ShapeClassName(check.shape_class)},
                      {"advice", check.advice}});
  }
  nlohmann::json look_alikes = nlohmann::json::array();
  for (const GyroscopeLookAlike& look_alike : d.look_alikes) {
    look_alikes.push_back({{"effect", look_alike.effect},
                           {"alternative", look_alike.alternative},
                           {"delta_chi2", look_alike.worse}});
  }
  return {{"alpha", alpha},
          {"noise", d.noise_note},
          {"bias_wander", d.bias_wander},
          {"turn_sampling", d.turn_sampling},
          {"scores", scores},
          {"not_tested", d.not_tested},
          {"effects", effects},
          {"checks", checks},
          {"remaining", d.remaining},
          {"look_alikes", look_alikes},
          {"verdict", VerdictCode(d.verdict_code)},
          {"verdict_text", d.verdict}};
}

nlohmann::json GyroscopeMlJson(const CalibrateImuReport& report) {
  const GyroscopeMlResult& g = report.gyroscope_ml;
  nlohmann::json parameters, stddev, units;
  nlohmann::json order = nlohmann::json::array();
  for (int i = 0; i < g.stddev.size(); ++i) {
    const double value = GyroscopeUnknownValue(g, i);
    parameters[g.names[i]] = value;
    stddev[g.names[i]] = g.stddev[i];
    units[g.names[i]] = g.units[i];
    order.push_back(g.names[i]);
  }
  nlohmann::json covariance = nlohmann::json::array();
  for (int i = 0; i < g.covariance.rows(); ++i) {
    nlohmann::json row = nlohmann::json::array();
    for (int j = 0; j < g.covariance.cols(); ++j) row.push_back(g.covariance(i, j));
    covariance.push_back(row);
  }
  nlohmann::json turns = nlohmann::json::array();
  for (const GyroscopeMlTurn& turn : g.turns) {
    turns.push_back({{"pose_before", turn.pose_before + 1},
                     {"first_sample", turn.first_sample},
                     {"last_sample", turn.last_sample},
                     {"duration_s", turn.duration_s},
                     {"tilt_angle_rad", turn.angle_rad},
                     {"rotation_angle_rad", turn.rotation_angle_rad},
                     {"residual_angle_rad", turn.residual_angle_rad},
                     {"angle_stddev_rad", turn.angle_stddev_rad},
                     {"sampling_measure_rad", turn.sampling_measure_rad},
                     {"peak_rate_rad_s", turn.peak_rate_rad_s},
                     {"time_s", turn.time_s},
                     {"whitened_residual", turn.whitened}});
  }
  nlohmann::json clipped = nlohmann::json::array();
  for (const GyroscopeClippedTurn& turn : g.clipped_turns) {
    clipped.push_back({{"pose_before", turn.pose_before + 1},
                       {"axis", std::string(1, "xyz"[turn.axis])},
                       {"rail", turn.rail},
                       {"samples", turn.samples}});
  }
  nlohmann::json effect_terms = nlohmann::json::array();
  for (size_t i = kGyroscopeCalibrationCount; i < g.names.size(); ++i)
    effect_terms.push_back(g.names[i]);
  nlohmann::json baseline_json = nullptr;
  if (!g.effects_estimated.empty()) {
    const GyroscopeMlResult& baseline = report.gyroscope_discovery.baseline;
    nlohmann::json values, sigmas, baseline_units;
    for (int i = 0; i < kGyroscopeCalibrationCount; ++i) {
      values[baseline.names[i]] = GyroscopeUnknownValue(baseline, i);
      sigmas[baseline.names[i]] = baseline.stddev[i];
      baseline_units[baseline.names[i]] = baseline.units[i];
    }
    baseline_json = {{"description",
                      "the 12 unknowns' fit of the same session, before the effect terms "
                      "discovery settled on"},
                     {"parameters", values},
                     {"stddev", sigmas},
                     {"units", baseline_units},
                     {"chi2", baseline.chi2_gyroscope},
                     {"degrees_of_freedom", baseline.gyroscope_degrees_of_freedom}};
  }
  nlohmann::json imu_tk = nullptr;
  if (report.has_gyroscope_calibration) {
    nlohmann::json values, imu_tk_units;
    for (int i = 0; i < kGyroscopeCalibrationCount; ++i) {
      values[g.names[i]] = ImuTkValue(report, i);
      imu_tk_units[g.names[i]] = g.units[i];
    }
    imu_tk = {{"parameters", values}, {"units", imu_tk_units}, {"cost", report.gyroscope.cost}};
  }
  return {{"model", "w = T K (u - b), docs/gyroscope.md"},
          {"method",
           "maximum likelihood, jointly with the accelerometer's poses: its pose means, the "
           "gyroscope's pose means and the turns between consecutive poses"},
          {"output_unit", GyroscopeOutputUnitName(report.gyroscope_ml_options.unit)},
          {"parameter_order", order},
          {"effect_terms", effect_terms},
          {"baseline", baseline_json},
          {"parameters", parameters},
          {"stddev", stddev},
          {"units", units},
          {"covariance", covariance},
          {"noise_variance", g.noise_variance},
          {"bias_wander_variance", g.bias_wander_variance},
          {"turn_sampling_variance", g.turn_sampling_variance},
          {"fit",
           {{"chi2", g.chi2_gyroscope},
            {"degrees_of_freedom", g.gyroscope_degrees_of_freedom},
            {"p_value", g.gyroscope_p_value},
            {"chi2_rest", g.chi2_rest},
            {"chi2_turns", g.chi2_turns},
            {"joint_chi2", g.chi2},
            {"joint_degrees_of_freedom", g.degrees_of_freedom},
            {"accelerometer_shift_sigma", g.accelerometer_shift_sigma}}},
          {"earth_rate",
           {{"rate_rad_s", kEarthRateRadPerS},
            {"pose_mean_sigma_rad_s", g.pose_mean_sigma_rad_s},
            {"offset_sigma_rad_s", g.offset_sigma_rad_s},
            {"turn_angle_sigma_rad", g.turn_angle_sigma_rad},
            {"turn_earth_angle_rad", g.turn_earth_angle_rad},
            {"counted_as_noise", report.gyroscope_ml_options.earth_rate_as_noise},
            {"latitude_deg",
             report.gyroscope_ml_options.latitude_given
                 ? nlohmann::json(report.gyroscope_ml_options.latitude_rad * 180.0 / M_PI)
                 : nlohmann::json(nullptr)},
            {"vertical_rate_rad_s", g.earth_vertical_rate_rad_s},
            {"vertical_rate_stddev", g.earth_vertical_rate_stddev},
            {"vertical_prior_stddev", g.earth_vertical_prior_stddev},
            {"vertical_held", g.earth_vertical_held},
            {"text", EarthRateSentence(report)}}},
          {"turns", turns},
          {"turned_about_rad", g.turned_about_rad},
          {"poorly_determined", PoorlyDeterminedJson(report.gyroscope_discovery.poorly_determined)},
          {"clipped_turns", clipped},
          {"imu_tk", imu_tk},
          {"discovery", GyroscopeDiscoveryJson(report.gyroscope_discovery,
                                               report.gyroscope_discovery_options.alpha)},
          {"verdict", VerdictCode(report.gyroscope_discovery.verdict_code)},
          {"verdict_text", report.gyroscope_discovery.verdict}};
}

}  // namespace accelcal
