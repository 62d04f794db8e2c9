#include "reporting/triad_report.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "common/format.h"
#include "io/atomic_file.h"
#include "io/cleanup.h"
#include "io/json_file.h"
#include "models/triad.h"
#include "reporting/gyroscope_report.h"
#include "reporting/report_document.h"
#include "reporting/triad_discovery_report.h"

namespace accelcal {
namespace {

constexpr char kResidualFigure[] = "triad_residuals.png";
constexpr char kNormFigure[] = "triad_norm.png";
constexpr char kPlotData[] = "triad_report.json";
constexpr char kNormCsv[] = "triad_norm.csv";

// The norm figure shows the whole log; more points than a figure has pixels only slow the
// plot down, so longer logs are thinned to about this many samples.
constexpr size_t kMaxNormPoints = 20000;

// A whitened residual beyond this is worth a look: white noise passes it once in 22 draws.
constexpr double kResidualBand = 2.0;

std::string Num(double value, const char* format = "%.4g") {
  return std::isfinite(value) ? StringPrintf(format, value) : std::string("n/a");
}

std::string Triple(const std::array<double, 3>& v, const char* format) {
  return Num(v[0], format) + ", " + Num(v[1], format) + ", " + Num(v[2], format);
}

std::string Sentence(std::string text) {
  if (!text.empty()) text[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(text[0])));
  return text;
}

// A folder of our own for the plot script's inputs and figures, removed on every path out
// (and by the interrupt cleanup should we be stopped meanwhile).
class ScratchFolder {
 public:
  ScratchFolder() {
    const char* tmpdir = std::getenv("TMPDIR");
    std::string pattern = std::string(tmpdir != nullptr && *tmpdir ? tmpdir : "/tmp") +
                          "/accelcal_triad_report.XXXXXX";
    std::vector<char> buffer(pattern.begin(), pattern.end());
    buffer.push_back('\0');
    WithCleanupHeld([&] {
      if (mkdtemp(buffer.data()) != nullptr) {
        path_ = buffer.data();
        RegisterTemporary(path_);
      }
    });
  }
  ~ScratchFolder() {
    if (path_.empty()) return;
    for (const char* name : {kResidualFigure, kNormFigure, kPlotData, kNormCsv})
      std::remove((path_ + "/" + name).c_str());
    rmdir(path_.c_str());
    ForgetTemporary(path_);
  }
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// The fit keeps an interval as a pose when it has two samples or more, which every interval
// of the detectors has; the bound only keeps a table from reading past either list.
size_t PoseCount(const CalibrateImuReport& report) {
  return std::min({report.pose_intervals.size(), report.ml.whitened_residuals.size(),
                   report.ml.directions.size()});
}

// What plot_triad.py draws from: each pose's time span and whitened residual.
nlohmann::json PlotData(const CalibrateImuReport& report) {
  nlohmann::json poses = nlohmann::json::array();
  for (size_t p = 0; p < PoseCount(report); ++p) {
    const StaticInterval& s = report.pose_intervals[p];
    poses.push_back({{"start_s", s.start_s},
                     {"end_s", s.end_s},
                     {"whitened_residual", report.ml.whitened_residuals[p]}});
  }
  return {{"gravity_mps2", report.ml_options.gravity_mps2},
          {"band", kResidualBand},
          {"chi2_per_dof", report.ml.chi2_per_dof},
          {"poses", poses}};
}

// t_s,norm_mps2: |a| = |T K (u - b)| of every (kept) sample with the ml parameters.
std::string NormCsv(const TriadLog& log, const TriadParameters& parameters) {
  const size_t stride = std::max<size_t>(1, (log.size() + kMaxNormPoints - 1) / kMaxNormPoints);
  std::string csv = "t_s,norm_mps2\n";
  for (size_t i = 0; i < log.size(); i += stride) {
    double a[3];
    TriadSpecificForce(parameters.data(), log.output[i].data(), a);
    const double norm = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    if (std::isfinite(norm)) csv += StringPrintf("%.10g,%.10g\n", log.timestamp_s[i], norm);
  }
  return csv;
}

ReportSection PosesSection(const CalibrateImuReport& report) {
  ReportSection section;
  section.title = "1. The poses found";
  std::string poses_line = Sentence(PosesLine(report));
  while (!poses_line.empty() && poses_line.back() == '\n') poses_line.pop_back();
  section.paragraphs.push_back(poses_line + ".");
  const char* unit = TriadOutputUnitName(report.unit);
  if (report.detector == "noise_floor") {
    const NoiseFloorDetection& d = report.noise_floor;
    section.paragraphs.push_back(StringPrintf(
        "Detector: noise floor s = (%s) %s per sample; a window of %d samples is still when its "
        "variance is below the threshold (%s) %s^2 on every axis (%g times s^2; white noise "
        "crosses it with probability %.2g); %.1f%% of the log is still; %zu still intervals "
        "shorter "
        "than %g s were not used.",
        Triple(d.floor_stddev, "%.4g").c_str(), unit, d.window_samples,
        Triple(d.threshold_variance, "%.4g").c_str(), unit,
        report.noise_floor_options.threshold_factor, d.white_false_alarm, 100.0 * d.still_fraction,
        d.short_intervals.size(), report.noise_floor_options.min_interval_s));
  }
  section.table.push_back({"pose", "start", "end", "start (s)", "end (s)", "duration (s)",
                           std::string("mean x (") + unit + ")", "mean y", "mean z",
                           std::string("noise x (") + unit + ")", "noise y", "noise z",
                           "gravity direction n (x, y, z)"});
  for (size_t p = 0; p < PoseCount(report); ++p) {
    const StaticInterval& s = report.pose_intervals[p];
    section.table.push_back(
        {std::to_string(p + 1), std::to_string(s.start), std::to_string(s.end),
         Num(s.start_s, "%.3f"), Num(s.end_s, "%.3f"), Num(s.duration_s, "%.2f"),
         Num(s.mean[0], "%.2f"), Num(s.mean[1], "%.2f"), Num(s.mean[2], "%.2f"),
         Num(s.noise_stddev[0], "%.3f"), Num(s.noise_stddev[1], "%.3f"),
         Num(s.noise_stddev[2], "%.3f"), Triple(report.ml.directions[p], "%+.4f")});
  }
  return section;
}

ReportSection ResidualSection(const CalibrateImuReport& report) {
  const TriadMlResult& ml = report.ml;
  ReportSection section;
  section.title = "2. The residual of every pose";
  int outside = 0;
  for (const auto& r : ml.whitened_residuals)
    for (double value : r) outside += std::fabs(value) > kResidualBand ? 1 : 0;
  const int count = 3 * static_cast<int>(ml.whitened_residuals.size());
  section.paragraphs.push_back(StringPrintf(
      "Each pose's mean minus the model's prediction, divided by its standard deviation under "
      "the noise model that weighted the fit (%s). Each pose's fitted gravity direction absorbs "
      "two of its three residuals' freedom, so when that noise model holds the squares sum to "
      "about the %d degrees of freedom and a value beyond +-%g is rarer still than for a unit "
      "normal. Here %d of the %d values lie outside +-%g, and the squares sum to %.4g.",
      report.allan_noise ? "the Allan variance of the pose's samples at its duration"
                         : "white noise: the pooled per-axis noise over the square root of the "
                           "pose's sample count",
      ml.degrees_of_freedom, kResidualBand, outside, count, kResidualBand, ml.chi2));
  section.table.push_back({"pose", "r x", "r y", "r z", "|r|^2"});
  for (size_t p = 0; p < ml.whitened_residuals.size(); ++p) {
    const std::array<double, 3>& r = ml.whitened_residuals[p];
    section.table.push_back({std::to_string(p + 1), Num(r[0], "%+.3f"), Num(r[1], "%+.3f"),
                             Num(r[2], "%+.3f"),
                             Num(r[0] * r[0] + r[1] * r[1] + r[2] * r[2], "%.3f")});
  }
  section.figure = kResidualFigure;
  section.figure_caption = StringPrintf(
      "Whitened residual per pose and axis; the shaded band is +-%g, which a unit normal "
      "leaves 5%% of the time.",
      kResidualBand);
  return section;
}

ReportSection ParameterSection(const CalibrateImuReport& report) {
  const TriadMlResult& ml = report.ml;
  const bool with_imu_tk = report.imu_tk_status.ok();
  const bool example = with_imu_tk && IsImuTkExample(report);
  ReportSection section;
  section.title = "3. The parameters";
  section.paragraphs.push_back(
      "Model a = T K (u - b) (docs/triad.md): T the non-orthogonality angles, K the gains, b "
      "the offsets; sigma from ceres::Covariance, true only as far as the verdict finds the "
      "model and its noise model right (section 4).");
  if (with_imu_tk) {
    section.paragraphs.push_back(StringPrintf(
        "imu_tk: its own rules on this log (threshold k = %d of its sweep), beside the maximum "
        "likelihood, with their difference in the latter's sigma.",
        report.result.best().multiplier));
  } else {
    section.paragraphs.push_back(
        "imu_tk's rules give no answer on this log: " + report.imu_tk_status.message() + ".");
  }
  if (example) {
    section.paragraphs.push_back(
        "This log is imu_tk's own Xsens example (recognised by its SHA-256): imu_tk's printed "
        "values and the sensor's datasheet are shown too, as printed (gains as 1/(counts per "
        "m/s^2); the datasheet gives the misalignment only to 0.01).");
  }
  std::vector<std::string> header = {"parameter", "unit", "ml", "sigma"};
  if (with_imu_tk) {
    header.push_back("imu_tk");
    header.push_back("(ml - imu_tk) / sigma");
  }
  if (example) {
    header.push_back("imu_tk printed");
    header.push_back("datasheet");
  }
  section.table.push_back(header);
  const auto& infos = TriadParameterInfos();
  for (int p = 0; p < kTriadParameterCount; ++p) {
    std::vector<std::string> row = {infos[p].name, TriadParameterUnit(p, report.unit),
                                    Num(ml.parameters[p], "%.8g"), Num(ml.stddev[p], "%.3g")};
    if (with_imu_tk) {
      const double imu_tk = report.result.best().parameters[p];
      row.push_back(Num(imu_tk, "%.8g"));
      row.push_back(Num((ml.parameters[p] - imu_tk) / ml.stddev[p], "%+.2f"));
    }
    if (example) {
      row.push_back(kImuTkPrinted[p]);
      row.push_back(kDatasheet[p]);
    }
    section.table.push_back(row);
  }
  if (report.unit == TriadOutputUnit::kCount) {
    std::string line = "Inverse gains (counts per m/s^2): ";
    for (int k = 0; k < 3; ++k) {
      const double gain = ml.parameters[kTriadGainX + k];
      line += StringPrintf("%s%c %.6g +- %.2g", k == 0 ? "" : ", ", "xyz"[k], 1.0 / gain,
                           ml.stddev[kTriadGainX + k] / (gain * gain));
    }
    section.paragraphs.push_back(line + ".");
  }
  std::string poorly = PoorlyDeterminedTable(report);
  while (!poorly.empty() && poorly.back() == '\n') poorly.pop_back();
  section.paragraphs.push_back(poorly);
  return section;
}

ReportSection FitSection(const CalibrateImuReport& report) {
  const TriadMlResult& ml = report.ml;
  ReportSection section;
  section.title = "4. The fit";
  section.paragraphs.push_back(
      StringPrintf("%d degrees of freedom: 3 residuals per pose, less 9 parameters and 2 "
                   "direction angles per pose.",
                   ml.degrees_of_freedom));
  section.paragraphs.push_back(Sentence(FitDescription(ml, report.allan_noise, report.discovery)) +
                               ".");
  section.figure = kNormFigure;
  section.figure_caption = StringPrintf(
      "The norm of the specific force corrected by this calibration over the log, with g = "
      "%.10g m/s^2 and the poses shaded: still, it should sit on g.",
      report.ml_options.gravity_mps2);
  return section;
}

// Discovery on the poses (estimation/triad/triad_discovery.h): the candidates as a table, what was
// found, what static poses cannot test, what remains, the verdict.
ReportSection DiscoverySection(const CalibrateImuReport& report) {
  const TriadDiscoveryResult& d = report.discovery;
  ReportSection section;
  section.title = "5. What the model misses (discovery)";
  section.paragraphs.push_back(StringPrintf(
      "alpha = %g: a session the 9-parameter model explains gets another verdict at most that "
      "often. Noise of the pose means: %s.",
      report.discovery_options.alpha, d.noise_note.c_str()));
  section.table.push_back({"step", "effect", "estimate", "sigma", "delta chi2", "p", "Holm"});
  for (const TriadCandidateScore& c : d.candidates) {
    section.table.push_back({StringPrintf("%d", c.step), c.name, StringPrintf("%.4g", c.estimate),
                             StringPrintf("%.3g", c.stddev), StringPrintf("%.3g", c.delta_chi2),
                             StringPrintf("%.3g", c.p_value), c.significant ? "significant" : "-"});
  }
  for (const TriadUntestable& u : d.untestable)
    section.paragraphs.push_back(u.effect + ": " + u.reason + ".");
  section.paragraphs.push_back(
      StringPrintf("Final model: chi2/dof = %.3g on %d dof (expected 1 +- %.2g), p = %.3g.",
                   d.final_fit.chi2_per_dof, d.final_fit.degrees_of_freedom,
                   d.final_fit.chi2_per_dof_spread, d.final_fit.p_value));
  if (d.cross_validation.folds > 0) {
    section.paragraphs.push_back(StringPrintf(
        "Leave-poses-out cross-validation (%d folds): mean held-out chi2 per pose %.3g for the "
        "baseline, %.3g for the final model (1 for a right model).",
        d.cross_validation.folds, d.cross_validation.baseline, d.cross_validation.final_model));
  }
  section.paragraphs.push_back(VerdictLine(d) + ".");
  return section;
}

// The gyroscope's maximum-likelihood calibration (estimation/gyroscope/), when the log had one:
// its parameters beside imu_tk's and the datasheet's, the noise model, the fit, the Earth's rate.
ReportSection GyroscopeSection(const CalibrateImuReport& report) {
  const GyroscopeMlResult& g = report.gyroscope_ml;
  ReportSection section;
  section.title = "6. The gyroscope";
  section.paragraphs.push_back(
      "Maximum likelihood jointly with the accelerometer's poses, w = T K (u - b) in rad/s "
      "(docs/gyroscope.md): the offsets from every pose's mean, the turns between consecutive "
      "poses integrated by the fourth-order rule, each parameter's sigma from ceres::Covariance.");
  section.paragraphs.push_back(StringPrintf(
      "Noise: white %.3g, %.3g, %.3g %s per sample; a bias wander between poses of %.3g, %.3g, "
      "%.3g %s (0: none needed).",
      std::sqrt(g.noise_variance[0]), std::sqrt(g.noise_variance[1]),
      std::sqrt(g.noise_variance[2]), GyroscopeOutputUnitName(report.gyroscope_ml_options.unit),
      std::sqrt(g.bias_wander_variance[0]), std::sqrt(g.bias_wander_variance[1]),
      std::sqrt(g.bias_wander_variance[2]),
      GyroscopeOutputUnitName(report.gyroscope_ml_options.unit)));
  section.table.push_back({"parameter", "unit", "estimate", "sigma", "imu_tk", "datasheet"});
  const bool example = IsImuTkGyroscopeExample(report);
  for (int i = 0; i < kGyroscopeCalibrationCount; ++i) {
    const double value =
        i < kGyroscopeParameterCount ? g.parameters[i] : g.offset[i - kGyroscopeParameterCount];
    const double imu_tk = i < kGyroscopeParameterCount
                              ? report.gyroscope.parameters[i]
                              : report.gyroscope.offset[i - kGyroscopeParameterCount];
    section.table.push_back({g.names[i], g.units[i], StringPrintf("%.8g", value),
                             StringPrintf("%.2g", g.stddev[i]),
                             report.has_gyroscope_calibration ? StringPrintf("%.8g", imu_tk) : "-",
                             example ? DatasheetGyroscopeValue(i) : "-"});
  }
  section.paragraphs.push_back(StringPrintf(
      "Fit: chi2 %.1f on %d degrees of freedom added to the accelerometer's, p = %.3g (the "
      "poses' offsets %.1f, the turns %.1f on %zu components).",
      g.chi2_gyroscope, g.gyroscope_degrees_of_freedom, g.gyroscope_p_value, g.chi2_rest,
      g.chi2_turns, 2 * g.turns.size()));
  section.paragraphs.push_back(EarthRateSentence(report) + ".");
  std::string poorly = GyroscopePoorlyDeterminedTable(report);
  while (!poorly.empty() && poorly.back() == '\n') poorly.pop_back();
  section.paragraphs.push_back(poorly);
  return section;
}

// Each turn's residual, and discovery on the gyroscope.
ReportSection GyroscopeTurnsSection(const CalibrateImuReport& report) {
  const GyroscopeMlResult& g = report.gyroscope_ml;
  const GyroscopeDiscoveryResult& d = report.gyroscope_discovery;
  ReportSection section;
  section.title = "7. The gyroscope's turns, and what its model misses";
  section.table.push_back({"turn", "poses", "duration (s)", "tilt (deg)", "rotation (deg)",
                           "residual (mrad)", "sigma (mrad)", "whitened"});
  for (size_t t = 0; t < g.turns.size(); ++t) {
    const GyroscopeMlTurn& turn = g.turns[t];
    section.table.push_back({StringPrintf("%zu", t + 1),
                             StringPrintf("%d -> %d", turn.pose_before + 1, turn.pose_before + 2),
                             StringPrintf("%.2f", turn.duration_s),
                             StringPrintf("%.2f", turn.angle_rad * 180 / M_PI),
                             StringPrintf("%.2f", turn.rotation_angle_rad * 180 / M_PI),
                             StringPrintf("%.3g", 1e3 * turn.residual_angle_rad),
                             StringPrintf("%.3g", 1e3 * turn.angle_stddev_rad),
                             StringPrintf("%+.2f, %+.2f", turn.whitened[0], turn.whitened[1])});
  }
  section.paragraphs.push_back("Noise: " + d.noise_note + ".");
  for (const GyroscopeEffectScore& score : d.scores) {
    section.paragraphs.push_back(StringPrintf("Step %d: %s removes chi2 %.2f on %d, p = %.3g%s.",
                                              score.step, score.effect.c_str(), score.delta_chi2,
                                              score.coefficients, score.p_value,
                                              score.significant ? " (significant)" : ""));
  }
  section.paragraphs.push_back(std::string("Verdict (gyroscope, ") + VerdictCode(d.verdict_code) +
                               "): " + d.verdict + ".");
  return section;
}

ReportDocument Document(const CalibrateImuReport& report, const DataSource& source,
                        const std::map<std::string, std::string>& absent) {
  const TriadMlResult& ml = report.ml;
  ReportDocument doc;
  const std::string name = report.log_path.substr(report.log_path.rfind('/') + 1);
  doc.title = "calibrate_imu --mode=ml: " + name;
  doc.summary.push_back(StringPrintf("%d poses, %d samples in their means; %zu samples in the log.",
                                     ml.pose_count, report.ml_sample_count, report.sample_count));
  doc.summary.push_back(StringPrintf("chi2/dof = %.4g on %d degrees of freedom, p = %.3g.",
                                     ml.chi2_per_dof, ml.degrees_of_freedom, ml.p_value));
  if (!report.imu_tk_status.ok())
    doc.summary.push_back("imu_tk's rules give no answer on this log.");
  doc.verdict = VerdictLine(report.discovery) + ".";
  if (!report.poorly_determined.empty()) {
    doc.summary.push_back("Poorly determined by these poses: " +
                          PoorlyDeterminedNames(report.poorly_determined) + " (section 3).");
  }
  doc.sections.push_back(PosesSection(report));
  doc.sections.push_back(ResidualSection(report));
  doc.sections.push_back(ParameterSection(report));
  doc.sections.push_back(FitSection(report));
  doc.sections.push_back(DiscoverySection(report));
  if (report.has_gyroscope_ml) {
    doc.summary.push_back(std::string("The gyroscope: ") +
                          VerdictCode(report.gyroscope_discovery.verdict_code) + ", " +
                          report.gyroscope_discovery.verdict + " (sections 6 and 7).");
    if (!report.gyroscope_discovery.poorly_determined.empty()) {
      doc.summary.push_back("Poorly determined by this session (gyroscope): " +
                            PoorlyDeterminedNames(report.gyroscope_discovery.poorly_determined) +
                            " (section 6).");
    }
    doc.sections.push_back(GyroscopeSection(report));
    doc.sections.push_back(GyroscopeTurnsSection(report));
  }
  doc.sections.push_back(
      ProvenanceSection(source, report.has_gyroscope_ml ? "8. Provenance" : "6. Provenance"));
  // A figure that could not be drawn is named where it would stand, with the reason.
  int not_drawn = 0;
  for (ReportSection& section : doc.sections) {
    const auto why = absent.find(section.figure);
    if (section.figure.empty() || why == absent.end()) continue;
    section.paragraphs.push_back("Figure not drawn (" + section.figure + "): " + why->second + ".");
    section.figure.clear();
    ++not_drawn;
  }
  if (not_drawn > 0) {
    doc.summary.push_back(StringPrintf("%d figure%s not drawn: the section says why.", not_drawn,
                                       not_drawn == 1 ? "" : "s"));
  }
  return doc;
}

// RenderHtml links each figure to its PNG beside the report; this page is one file, so the
// image stands alone.
std::string WithoutFigureLinks(std::string html) {
  for (const char* figure : {kResidualFigure, kNormFigure}) {
    const std::string link = std::string("<a href=\"") + figure + "\">";
    const size_t start = html.find(link);
    if (start == std::string::npos) continue;
    html.erase(start, link.size());
    const size_t end = html.find("</a><figcaption>", start);
    if (end != std::string::npos) html.erase(end, 4);
  }
  return html;
}

}  // namespace

Status TriadReportHtml(const TriadLog& log, const CalibrateImuReport& report,
                       const DataSource& source, const FigureTools& tools, std::string* html,
                       FigureOutcome* figures) {
  ScratchFolder scratch;
  if (scratch.path().empty()) {
    return Status::Error(
        "cannot create a temporary folder for the report's figures (set TMPDIR to a writable "
        "folder)");
  }
  const std::string dir = scratch.path();
  ACCELCAL_RETURN_IF_ERROR(WriteJsonAtomically(dir + "/" + kPlotData, PlotData(report)));
  ACCELCAL_RETURN_IF_ERROR(
      WriteFileAtomically(dir + "/" + kNormCsv, NormCsv(log, report.ml.parameters)));
  const std::string why = Plot(
      tools, "plot_triad.py",
      {"--json=" + dir + "/" + kPlotData, "--norm_csv=" + dir + "/" + kNormCsv,
       "--residuals_out=" + dir + "/" + kResidualFigure, "--norm_out=" + dir + "/" + kNormFigure});
  figures->drawn.clear();
  figures->absent.clear();
  for (const char* figure : {kResidualFigure, kNormFigure}) {
    if (why.empty() && access((dir + "/" + figure).c_str(), R_OK) == 0) {
      figures->drawn.push_back(figure);
    } else {
      figures->absent[figure] = why.empty() ? "plot_triad.py did not write it" : why;
    }
  }
  *html = WithoutFigureLinks(RenderHtml(Document(report, source, figures->absent), dir));
  return Status::Ok();
}

}  // namespace accelcal
