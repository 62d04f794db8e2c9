#include "reporting/ferraris_report.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "common/format.h"
#include "models/triad.h"

namespace accelcal {
namespace {

std::string Row(const Eigen::Vector3d& v) {
  return StringPrintf("%17.12g %17.12g %17.12g", v[0], v[1], v[2]);
}

nlohmann::json MatrixJson(const Eigen::Matrix3d& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (int i = 0; i < 3; ++i) rows.push_back({m(i, 0), m(i, 1), m(i, 2)});
  return rows;
}

nlohmann::json VectorJson(const Eigen::Vector3d& v) { return {v[0], v[1], v[2]}; }

nlohmann::json ImucalJson(const ImucalCalibration& calibration) {
  const ImucalAccelerometer& acc = calibration.accelerometer;
  nlohmann::json json = {
      {"K_a", MatrixJson(acc.k_a)}, {"R_a", MatrixJson(acc.r_a)}, {"b_a", VectorJson(acc.b_a)}};
  if (calibration.has_gyroscope) {
    const ImucalGyroscope& gyr = calibration.gyroscope;
    json["K_g"] = MatrixJson(gyr.k_g);
    json["R_g"] = MatrixJson(gyr.r_g);
    json["K_ga"] = MatrixJson(gyr.k_ga);
    json["b_g"] = VectorJson(gyr.b_g);
  }
  return json;
}

nlohmann::json ByName(const TriadParameters& values) {
  nlohmann::json json = nlohmann::json::object();
  for (int i = 0; i < kTriadParameterCount; ++i) json[TriadParameterInfos()[i].name] = values[i];
  return json;
}

nlohmann::json UnitsJson() {
  nlohmann::json json = nlohmann::json::object();
  for (const TriadParameterInfo& info : TriadParameterInfos()) json[info.name] = info.unit;
  return json;
}

// One imucal matrix, row by row, beside the reference's when there is one.
void MatrixLines(const char* name, const Eigen::Matrix3d& ours, const Eigen::Matrix3d* reference,
                 std::ostringstream* out) {
  for (int i = 0; i < 3; ++i) {
    *out << StringPrintf("  %-4s %s", i == 0 ? name : "", Row(ours.row(i).transpose()).c_str());
    if (reference != nullptr) *out << "   | " << Row(reference->row(i).transpose());
    *out << "\n";
  }
}

void VectorLine(const char* name, const Eigen::Vector3d& ours, const Eigen::Vector3d* reference,
                std::ostringstream* out) {
  *out << StringPrintf("  %-4s %s", name, Row(ours).c_str());
  if (reference != nullptr) *out << "   | " << Row(*reference);
  *out << "\n";
}

void ImucalLines(const FerrarisReport& report, std::ostringstream* out) {
  const ImucalCalibration& ours = report.analysis.closed_form;
  const ImucalCalibration* reference = report.has_reference ? &report.reference : nullptr;
  *out << "imucal's convention: a = R_a^-1 K_a^-1 (u - b_a), a in m/s^2, K_a in counts per m/s^2, "
          "b_a in counts\n";
  *out << StringPrintf("       %-53s", "closed form (this session)")
       << (reference != nullptr ? "   | " + report.reference_path : std::string()) << "\n";
  MatrixLines("K_a", ours.accelerometer.k_a, reference ? &reference->accelerometer.k_a : nullptr,
              out);
  MatrixLines("R_a", ours.accelerometer.r_a, reference ? &reference->accelerometer.r_a : nullptr,
              out);
  VectorLine("b_a", ours.accelerometer.b_a, reference ? &reference->accelerometer.b_a : nullptr,
             out);
  if (ours.has_gyroscope) {
    const ImucalGyroscope* gyr =
        reference != nullptr && reference->has_gyroscope ? &reference->gyroscope : nullptr;
    *out << "  gyroscope: w = R_g^-1 K_g^-1 (u_g - K_ga a - b_g), w in deg/s\n";
    MatrixLines("K_g", ours.gyroscope.k_g, gyr ? &gyr->k_g : nullptr, out);
    MatrixLines("R_g", ours.gyroscope.r_g, gyr ? &gyr->r_g : nullptr, out);
    MatrixLines("K_ga", ours.gyroscope.k_ga, gyr ? &gyr->k_ga : nullptr, out);
    VectorLine("b_g", ours.gyroscope.b_g, gyr ? &gyr->b_g : nullptr, out);
  }
  if (reference != nullptr) {
    *out << StringPrintf(
        "  largest relative difference from the reference, element by element: %.2g\n",
        FerrarisMaxRelativeDifference(ours, *reference));
  }
}

std::string Sigmas(double difference, double sigma) {
  return sigma > 0.0 ? StringPrintf("%8.2f", difference / sigma) : std::string(8, ' ');
}

// The names of `indices` with a figure each, "gain_x 0.017, gain_y 0.0095".
std::string NamedFigures(const std::vector<std::string>& names, const TriadParameters& figures,
                         const char* format) {
  std::string text;
  for (const std::string& name : names) {
    for (int i = 0; i < kTriadParameterCount; ++i) {
      if (name != TriadParameterInfos()[i].name) continue;
      text += (text.empty() ? "" : ", ") + name + " " + StringPrintf(format, figures[i]);
    }
  }
  return text;
}

// The whitened residuals of the known-directions fit, largest first.
std::string LargestResiduals(const FerrarisKnownDirectionsFit& fit, int count) {
  std::vector<std::pair<double, std::string>> all;
  for (int p = 0; p < kFerrarisHoldCount; ++p) {
    for (int k = 0; k < 3; ++k) {
      all.emplace_back(fit.whitened_residuals[p][k],
                       StringPrintf("%s %c", kFerrarisSectionLabels[p], "xyz"[k]));
    }
  }
  std::sort(all.begin(), all.end(),
            [](const auto& a, const auto& b) { return std::abs(a.first) > std::abs(b.first); });
  std::string text;
  for (int i = 0; i < count; ++i)
    text += (i == 0 ? "" : ", ") + all[i].second + StringPrintf(" %.1f", all[i].first);
  return text;
}

// "p = 0.12", or "p < 1e-300" where the chi-square's tail underflows.
std::string PValue(double p) { return p > 0.0 ? StringPrintf("p = %.3g", p) : "p < 1e-300"; }

constexpr char kIdentifiabilityStatement[] =
    "With the holds' gravity directions unknown, six holds give 18 numbers for 21 unknowns (9 "
    "triad parameters, 2 per direction): the three misalignment angles are not determined (any "
    "small angles fit the holds exactly, the directions turning along); offsets and gains are "
    "determined once the angles are given, with no redundancy to check them. Ferraris's closed "
    "form determines the angles only by assuming that the holds are exactly +-g along three "
    "orthogonal axes; the least-squares fit with that assumption (6 degrees of freedom) tests "
    "that opposite holds are antiparallel, not that the pairs are orthogonal. To determine the "
    "angles, add holds between the axes (calibrate_imu --mode=ml on a dozen or more poses).";

}  // namespace

double FerrarisMaxRelativeDifference(const ImucalCalibration& ours,
                                     const ImucalCalibration& reference) {
  double largest = 0.0;
  auto compare = [&largest](const auto& a, const auto& b) {
    for (int i = 0; i < b.rows(); ++i) {
      for (int j = 0; j < b.cols(); ++j) {
        const double difference = std::abs(a(i, j) - b(i, j));
        largest = std::max(largest, b(i, j) == 0.0 ? difference : difference / std::abs(b(i, j)));
      }
    }
  };
  compare(ours.accelerometer.k_a, reference.accelerometer.k_a);
  compare(ours.accelerometer.r_a, reference.accelerometer.r_a);
  compare(ours.accelerometer.b_a, reference.accelerometer.b_a);
  if (ours.has_gyroscope && reference.has_gyroscope) {
    compare(ours.gyroscope.k_g, reference.gyroscope.k_g);
    compare(ours.gyroscope.r_g, reference.gyroscope.r_g);
    compare(ours.gyroscope.k_ga, reference.gyroscope.k_ga);
    compare(ours.gyroscope.b_g, reference.gyroscope.b_g);
  }
  return largest;
}

std::string FerrarisTable(const FerrarisReport& report) {
  const FerrarisAnalysis& analysis = report.analysis;
  const FerrarisLeastSquaresResult& ls = analysis.least_squares;
  const FerrarisKnownDirectionsFit& known = ls.known_directions;
  const FerrarisUnknownDirectionsFit& unknown = ls.unknown_directions;
  const FerrarisIdentifiability& id = ls.identifiability;
  std::ostringstream out;
  out << "Ferraris calibration: imucal's closed form, and its least-squares counterpart with "
         "sigma\n";
  out << StringPrintf("session: %s; g = %.10g m/s^2", report.session_path.c_str(),
                      report.options.gravity_mps2);
  if (analysis.closed_form.has_gyroscope) {
    out << StringPrintf("; gyroscope integrated at %.10g Hz over turns of %.10g deg",
                        report.options.sampling_rate_hz, report.options.expected_angle_deg);
  }
  out << "\n\n";

  out << "section  lines            samples   accelerometer mean x, y, z (counts)           sd "
         "per sample x, y, z\n";
  for (int s = 0; s < kFerrarisSectionCount; ++s) {
    const FerrarisSectionData& section = report.session.sections[s];
    const TriadPoseMean& acc = section.accelerometer;
    out << StringPrintf("  %-6s %6lld..%-6lld %8d  %13.6f %13.6f %13.6f   %7.3f %7.3f %7.3f\n",
                        kFerrarisSectionLabels[s], section.first_line, section.last_line,
                        acc.sample_count, acc.mean[0], acc.mean[1], acc.mean[2],
                        std::sqrt(acc.variance[0]), std::sqrt(acc.variance[1]),
                        std::sqrt(acc.variance[2]));
  }
  out << StringPrintf(
      "holds' axes x_p - x_a, y_p - y_a, z_p - z_a: normalised determinant %.6f (1: orthogonal); "
      "pooled noise sd per sample %.3f, %.3f, %.3f counts\n\n",
      analysis.hold_orthogonality, std::sqrt(ls.noise_variance[0]), std::sqrt(ls.noise_variance[1]),
      std::sqrt(ls.noise_variance[2]));

  ImucalLines(report, &out);

  const Eigen::AngleAxisd frame(analysis.frame_rotation);
  out << StringPrintf(
      "\naccelcal's convention (docs/triad.md): a' = T K (u - b); imucal's a = Q a', Q a "
      "rotation by %.4f deg\n",
      frame.angle() * 180.0 / M_PI);
  out << "  (a) known directions: each hold +-g along an axis of one orthogonal frame (Ferraris's "
         "assumption), 12 unknowns\n";
  out << "  (b) unknown directions: angles held at the closed form's, offsets and gains solved, "
         "18 unknowns\n";
  out << StringPrintf("  %-16s %-14s %14s   %-28s %8s    %-28s %8s\n", "parameter", "unit",
                      "closed form", "    (a) value +- sigma", "(a)-cf", "    (b) value +- sigma",
                      "(b)-cf");
  out << StringPrintf("%89s%42s\n", "/sigma", "/sigma");
  for (int i = 0; i < kTriadParameterCount; ++i) {
    const TriadParameterInfo& info = TriadParameterInfos()[i];
    const double cf = analysis.closed_form_triad[i];
    const std::string b_value =
        unknown.stddev[i] > 0.0
            ? StringPrintf("%14.8g +- %-10.3g", unknown.parameters[i], unknown.stddev[i])
            : StringPrintf("%14.8g (held)%15s", unknown.parameters[i], "");
    std::string line =
        StringPrintf("  %-16s %-14s %14.8g   %14.8g +- %-10.3g %8s    %s %8s", info.name, info.unit,
                     cf, known.parameters[i], known.stddev[i],
                     Sigmas(known.parameters[i] - cf, known.stddev[i]).c_str(), b_value.c_str(),
                     Sigmas(unknown.parameters[i] - cf, unknown.stddev[i]).c_str());
    line.erase(line.find_last_not_of(' ') + 1);  // a held angle has no last column
    out << line << "\n";
  }

  out << StringPrintf(
      "\n(a) chi2 = %.6g on %d degrees of freedom, %s (chi2/dof = %.4g; %.2g +- %.2g when "
      "the holds are antiparallel and the noise white)\n",
      known.chi2, known.degrees_of_freedom, PValue(known.p_value).c_str(),
      known.chi2 / known.degrees_of_freedom, 1.0, std::sqrt(2.0 / known.degrees_of_freedom));
  if (known.p_value < 0.01) {
    out << StringPrintf(
        "    opposite holds are not antiparallel, or the pairs do not share one centre, beyond "
        "the noise: the sigma of (a) are white noise's and understate its uncertainty (by "
        "sqrt(chi2/dof) = %.3g if the misfit were noise-like).\n",
        std::sqrt(known.chi2 / known.degrees_of_freedom));
  } else {
    out << "    the holds are antiparallel within the noise: the white-noise model explains the "
           "residuals.\n";
  }
  out << "    largest whitened residuals (hold, axis): " << LargestResiduals(known, 4) << "\n";
  TriadParameters zero_shift{};
  for (int i = 0; i < kTriadParameterCount; ++i) {
    zero_shift[i] =
        unknown.stddev[i] > 0.0
            ? (unknown.parameters_at_zero_angles[i] - unknown.parameters[i]) / unknown.stddev[i]
            : 0.0;
  }
  out << StringPrintf(
      "(b) an exact fit (chi2 = %.2g, 0 degrees of freedom): nothing is left to test it.\n",
      unknown.chi2);
  out << "    with the angles held at 0 instead, in sigma of (b): "
      << NamedFigures(id.identifiable, zero_shift, "%+.2f") << "\n\n";

  out << StringPrintf(
      "Identifiability (unknown directions): %d observations, %d unknowns, Jacobian rank %d.\n",
      id.observations, id.unknowns, id.rank);
  out << "  not identifiable (null-space weight): "
      << NamedFigures(id.not_identifiable, id.null_space_weight, "%.3f") << "\n";
  out << "  identifiable once the angles are given: "
      << NamedFigures(id.identifiable, id.null_space_weight, "%.3f") << "\n";
  out << "  " << kIdentifiabilityStatement << "\n";
  return out.str();
}

nlohmann::json FerrarisJson(const FerrarisReport& report) {
  const FerrarisAnalysis& analysis = report.analysis;
  const FerrarisLeastSquaresResult& ls = analysis.least_squares;
  const FerrarisKnownDirectionsFit& known = ls.known_directions;
  const FerrarisUnknownDirectionsFit& unknown = ls.unknown_directions;
  const FerrarisIdentifiability& id = ls.identifiability;
  nlohmann::json sections = nlohmann::json::array();
  for (int s = 0; s < kFerrarisSectionCount; ++s) {
    const FerrarisSectionData& section = report.session.sections[s];
    sections.push_back({{"label", kFerrarisSectionLabels[s]},
                        {"samples", section.accelerometer.sample_count},
                        {"first_line", section.first_line},
                        {"last_line", section.last_line},
                        {"acc_mean", section.accelerometer.mean},
                        {"acc_variance", section.accelerometer.variance},
                        {"gyr_mean", section.gyroscope.mean},
                        {"gyr_variance", section.gyroscope.variance}});
  }
  nlohmann::json weights = ByName(id.null_space_weight);
  nlohmann::json json = {
      {"mode", "ferraris"},
      {"session", {{"path", report.session_path}, {"sections", sections}}},
      {"options",
       {{"gravity_mps2", report.options.gravity_mps2},
        {"sampling_rate_hz", report.options.sampling_rate_hz},
        {"expected_angle_deg", report.options.expected_angle_deg}}},
      {"units", UnitsJson()},
      // The least-squares fit under Ferraris's assumption: all nine with sigma.
      {"parameters", ByName(known.parameters)},
      {"stddev", ByName(known.stddev)},
      {"chi2", known.chi2},
      {"dof", known.degrees_of_freedom},
      {"p_value", known.p_value},
      {"noise_variance",
       {{"x", ls.noise_variance[0]},
        {"y", ls.noise_variance[1]},
        {"z", ls.noise_variance[2]},
        {"unit", "count^2"}}},
      {"frame_rotation", MatrixJson(known.frame_rotation)},
      {"closed_form",
       {{"parameters", ByName(analysis.closed_form_triad)},
        {"units", UnitsJson()},
        {"frame_rotation", MatrixJson(analysis.frame_rotation)},
        {"hold_orthogonality", analysis.hold_orthogonality}}},
      {"imucal", ImucalJson(analysis.closed_form)},
      {"unknown_directions",
       {{"held", {"misalignment_yz", "misalignment_zy", "misalignment_zx"}},
        {"parameters", ByName(unknown.parameters)},
        {"units", UnitsJson()},
        {"stddev", ByName(unknown.stddev)},
        {"parameters_at_zero_angles", ByName(unknown.parameters_at_zero_angles)},
        {"chi2", unknown.chi2},
        {"dof", 0}}},
      {"identifiable", id.identifiable},
      {"not_identifiable", id.not_identifiable},
      {"identifiability",
       {{"observations", id.observations},
        {"unknowns", id.unknowns},
        {"rank", id.rank},
        {"singular_values", id.singular_values},
        {"null_space_weight", weights},
        {"statement", kIdentifiabilityStatement}}},
  };
  json["reference"] = nullptr;
  if (report.has_reference) {
    json["reference"] = ImucalJson(report.reference);
    json["reference"]["path"] = report.reference_path;
    json["reference"]["max_relative_difference"] =
        FerrarisMaxRelativeDifference(analysis.closed_form, report.reference);
  }
  return json;
}

}  // namespace accelcal
