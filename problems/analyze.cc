// analyze: from measured data to a report a person can read. Baseline fit, trajectory and
// landmark decision, discovery (what the baseline gets wrong, the named cause, the gain),
// the joint solution with what discovery selected, and the minimum number of samples,
// in that order; then report.md, a self-contained report.html, results.json and the
// figures, written to a temporary sibling of --out_dir and renamed into place at the end.
//
// Without --data_dir it simulates the course's setting (data/scenarios/tp2-2018.json) with
// one effect hidden in it (--set, default angle_offset=0.004), stated in the report as
// the truth.
//
//   build/bin/analyze --data_dir=../shared/data/tp2-2018 --out_dir=report --overwrite

#include <gflags/gflags.h>
#include <unistd.h>

#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>

#include "common/format.h"
#include "estimation/ceres_linear_ls.h"
#include "estimation/discovery.h"
#include "estimation/error_budget.h"
#include "estimation/landmark_decision.h"
#include "estimation/linear_ls.h"
#include "estimation/trajectory.h"
#include "io/atomic_file.h"
#include "io/course_data.h"
#include "io/json_file.h"
#include "io/subprocess.h"
#include "problem_support.h"
#include "reporting/discovery_report.h"
#include "reporting/linear_ls_report.h"
#include "reporting/min_samples_report.h"
#include "reporting/report_document.h"
#include "reporting/trajectory_report.h"
#include "studies/min_samples.h"

DEFINE_string(data_dir, "",
              "Folder with the course layout or the CSV layout. Empty: simulate the embedded "
              "tp2-2018 scenario with --set hidden in it.");
DEFINE_string(set, "angle_offset=0.004",
              "Without data: the effects hidden in the simulated data, name=value,... in the "
              "spec's units (the report states them as the truth).");
DEFINE_uint64(seed, 1, "Without data: the seed of the simulation.");
ACCELCAL_DEFINE_THETA_UNIT_FLAG();
DEFINE_string(out_dir, "report", "The report folder to create (replaced only with --overwrite).");
DEFINE_bool(overwrite, false, "Replace --out_dir if it exists and is not empty.");
DEFINE_double(alpha, 0.01,
              "Significance level of the landmark decision and family-wise error rate of "
              "discovery, in (0, 0.5).");
DEFINE_double(max_error, 0.01,
              "The minimum-N criterion: the largest acceptable P(wrong landmark), 1e-6 to 0.499.");
DEFINE_double(g, 9.8, "Gravity in m/s^2.");
DEFINE_string(tools_dir, ACCELCAL_TOOLS_DIR, "Folder of the plot scripts (tools/plot_*.py).");
DEFINE_string(python, "/usr/bin/python3", "Python with matplotlib, for the figures.");
ACCELCAL_FLAG_OPEN_RANGE(alpha, 0.0, 0.5);
ACCELCAL_FLAG_RANGE(max_error, 1e-6, 0.499);
ACCELCAL_FLAG_RANGE(g, 1.0, 100.0);

namespace accelcal {
namespace {

constexpr char kUsage[] =
    "Runs every stage on measured (or simulated) data and writes a report folder: report.md,\n"
    "report.html (figures embedded), results.json and the figures as PNG. Units: m, s, m/s^2, "
    "rad.\n"
    "Exit status: 0 on success, 2 on bad input; an interrupted run leaves no partial report.\n\n"
    "  analyze --data_dir=../shared/data/tp2-2018 --out_dir=report [--overwrite]";

using Inputs = Experiment;

// A progress line per stage, on a terminal only.
class Progress {
 public:
  void Start(int stage, const char* name) {
    start_ = std::chrono::steady_clock::now();
    if (isatty(STDERR_FILENO)) std::fprintf(stderr, "[%d/5] %s ... ", stage, name);
  }
  void Done() {
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    if (isatty(STDERR_FILENO)) std::fprintf(stderr, "done (%.2f s)\n", seconds);
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

Status Load(Inputs* inputs) {
  LoadOptions options;
  ACCELCAL_RETURN_IF_ERROR(LoadOptionsFromFlags(FLAGS_theta_unit, &options));
  return LoadExperiment(FLAGS_data_dir, FLAGS_set, FLAGS_seed, options,
                        {{"--out_dir", FLAGS_out_dir, OutputPath::Kind::kFolder}}, inputs);
}

struct Results {
  LinearLsReport linear;
  TrajectoryReport trajectory;
  DiscoveryResult discovery;
  std::vector<DesignCurve> designs;
  EndpointModel endpoint_model;
};

Status Analyse(const Inputs& inputs, double gravity, Results* results) {
  Progress progress;
  progress.Start(1, "baseline fit (closed form and Ceres)");
  LinearLsOptions linear;
  linear.gravity_mps2 = gravity;
  linear.noise_variance_x = inputs.conditions.noise_variance_x;
  linear.noise_variance_y = inputs.conditions.noise_variance_y;
  ACCELCAL_RETURN_IF_ERROR(EstimateLinearLs(inputs.test, linear, &results->linear.closed_form));
  CeresLinearLsOptions ceres;
  ceres.model = linear;
  ACCELCAL_RETURN_IF_ERROR(EstimateLinearLsWithCeres(inputs.test, ceres, &results->linear.ceres));
  results->linear.gravity_mps2 = gravity;
  results->linear.noise_variance_x = linear.noise_variance_x;
  results->linear.noise_variance_y = linear.noise_variance_y;
  results->linear.input_files = inputs.files;
  progress.Done();

  progress.Start(2, "trajectory and landmark decision");
  TrajectoryReport& t = results->trajectory;
  t.fit = results->linear.closed_form;
  t.conditions = inputs.conditions;
  t.input_files = inputs.files;
  ACCELCAL_RETURN_IF_ERROR(
      DeadReckon(inputs.run, inputs.conditions, t.fit, TrajectoryOptions(), &t.trajectory));
  t.decision =
      DecideLandmark(t.trajectory.endpoint, t.trajectory.covariance, inputs.landmarks, FLAGS_alpha);
  t.budget = ComputeErrorBudget(t.trajectory, t.fit, inputs.run, inputs.conditions);
  progress.Done();

  progress.Start(3, "discovery and the joint model with what it selected");
  DiscoveryOptions discovery;
  discovery.alpha = FLAGS_alpha;
  discovery.gravity_mps2 = gravity;
  ACCELCAL_RETURN_IF_ERROR(Discover(inputs.test, inputs.run, inputs.conditions, inputs.landmarks,
                                    discovery, &results->discovery));
  progress.Done();

  progress.Start(4, "how many calibration samples");
  EndpointModel& model = results->endpoint_model;
  model.jacobian = t.trajectory.jacobian;
  model.noise_part = t.trajectory.noise_part;
  model.endpoint = t.trajectory.endpoint;
  model.gravity_mps2 = gravity;
  model.noise_variance_x = linear.noise_variance_x;
  model.noise_variance_y = linear.noise_variance_y;
  const int truth = t.decision.best;
  if (truth >= 0 && inputs.landmarks.size() > 1) {
    int uniform_n_min = 100;
    for (const char* name : {"uniform", "four", "two", "optimal"}) {
      DesignCurve design;
      design.name = name;
      if (design.name == "optimal") {
        design = OptimalTwoPositionDesign(model, inputs.landmarks, truth,
                                          uniform_n_min > 0 ? uniform_n_min : 100);
      }
      design = AnalyseDesign(model, inputs.landmarks, truth, design, FLAGS_max_error,
                             inputs.test.size());
      if (design.name == "uniform") uniform_n_min = design.n_min;
      results->designs.push_back(design);
    }
  }
  progress.Done();
  return Status::Ok();
}

std::string Num(double value, const char* format = "%.4g") { return StringPrintf(format, value); }

// `value` with `format`, or "n/a" when it is not finite.
std::string Finite(double value, const char* format) {
  return std::isfinite(value) ? StringPrintf(format, value) : std::string("n/a");
}

// `text` with its first letter capitalised, to start a sentence.
std::string Sentence(std::string text) {
  if (!text.empty()) text[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(text[0])));
  return text;
}

// A figure takes a few seconds; a plot program still running after this is stopped.
constexpr double kPlotTimeoutS = 300.0;

// Runs a plot script with an argument vector (no shell); returns "" or why the figure is
// absent.
std::string Plot(const std::string& script, const std::vector<std::string>& arguments) {
  const std::string path = FLAGS_tools_dir + "/" + script;
  if (access(path.c_str(), R_OK) != 0) return "the script " + path + " is not there (--tools_dir)";
  int exit_status = 0;
  Status status =
      RunProgram({FLAGS_python, "-c", "import matplotlib, numpy"}, kPlotTimeoutS, &exit_status);
  if (!status.ok()) return status.message() + " (--python)";
  if (exit_status != 0) {
    return FLAGS_python +
           " has no matplotlib/numpy (apt-get install python3-matplotlib python3-numpy)";
  }
  std::vector<std::string> argv = {FLAGS_python, path};
  argv.insert(argv.end(), arguments.begin(), arguments.end());
  status = RunProgram(argv, kPlotTimeoutS, &exit_status);
  if (!status.ok()) return status.message();
  return exit_status == 0 ? ""
                          : script + " failed (exit status " + std::to_string(exit_status) + ")";
}

// The verdict box's discovery part: the verdict in its four-verdict form, and whatever of
// the remaining structure, the ambiguities and the noise findings its sentence does not
// already say.
std::string DiscoveryBox(const DiscoveryResult& d) {
  std::string box = d.verdict + ".";
  auto says = [&](const std::string& text) { return d.verdict.find(text) != std::string::npos; };
  std::string left;
  for (const std::string& line : d.remaining)
    if (!says(line)) left += (left.empty() ? "" : "; ") + line;
  if (!left.empty()) box += " What remains that no effect of the catalogue explains: " + left + ".";
  for (const Ambiguity& ambiguity : d.ambiguities) {
    if (ambiguity.separation.empty() || says(ambiguity.separation)) continue;
    box += StringPrintf(" %s cannot be told apart from ", Info(ambiguity.effect).name);
    for (size_t i = 0; i < ambiguity.alternatives.size(); ++i) {
      box += std::string(i == 0                                   ? ""
                         : i + 1 == ambiguity.alternatives.size() ? " or "
                                                                  : ", ") +
             ambiguity.alternatives[i].Name();
    }
    box += "; what would separate them: " + ambiguity.separation + ".";
  }
  std::string noise;
  for (const NoiseFinding& finding : d.noise_findings)
    if (!says(finding.description)) noise += (noise.empty() ? "" : "; ") + finding.description;
  if (!noise.empty()) box += " Noise: " + noise + ".";
  return box;
}

ReportDocument Document(const Inputs& inputs, const Results& r,
                        const std::map<std::string, std::string>& absent) {
  ReportDocument doc;
  doc.title = "accelcal report";
  const DiscoveryResult& d = r.discovery;
  const LandmarkDecision& decision = r.trajectory.decision;
  doc.verdict = DiscoveryBox(d) + " Landmark: " +
                (decision.reached.empty()
                     ? std::string("no landmark is consistent with the endpoint")
                     : decision.reached +
                           StringPrintf(" (p = %.3g)", decision.scores[decision.best].p_value)) +
                ". Data: " + inputs.source + ".";
  if (!inputs.truth.is_null()) {
    std::string truth;
    for (const auto& item : inputs.truth["parameters"].items()) {
      const ParameterInfo* info = FindParameter(item.key());
      if (info != nullptr && !info->baseline && item.value().get<double>() != info->neutral) {
        truth += std::string(truth.empty() ? "" : ", ") + item.key() + " = " +
                 Num(item.value().get<double>()) + " " + info->unit;
      }
    }
    doc.verdict +=
        " The truth hidden in it: " + (truth.empty() ? std::string("no effect") : truth) +
        "; the run ends at " + inputs.truth["reached_landmark"].get<std::string>() + ".";
  }

  ReportSection baseline{"1. Baseline: bias and scale by linear least squares"};
  const BaselineFit& fit = r.linear.closed_form;
  baseline.paragraphs.push_back(
      StringPrintf("%d tilt-test samples, stated noise variances %g and %g (m/s^2)^2, g = %g "
                   "m/s^2. Chi-square per axis: %.1f and "
                   "%.1f on %d degrees of freedom. The closed form and Ceres agree to %.1e.",
                   fit.sample_count, r.linear.noise_variance_x, r.linear.noise_variance_y,
                   r.linear.gravity_mps2, fit.chi2_x.chi2, fit.chi2_y.chi2, fit.chi2_x.dof,
                   CompareFits(fit, r.linear.ceres.fit).parameters));
  baseline.table.push_back({"parameter", "estimate", "1 sigma", "unit"});
  for (const Parameter parameter : kBaselineParameters) {
    baseline.table.push_back({Info(parameter).name, Num(fit.Value(parameter), "%+.4e"),
                              Num(fit.StandardDeviation(parameter), "%.3e"), Info(parameter).unit});
  }
  doc.sections.push_back(baseline);

  ReportSection trajectory{"2. Trajectory and landmark"};
  const DeadReckoningResult& tr = r.trajectory.trajectory;
  trajectory.paragraphs.push_back(
      StringPrintf("Corrected endpoint (%.2f, %.2f) m, 1 sigma %.2f m and %.2f m; the raw outputs "
                   "integrated end at (%.2f, %.2f) m. "
                   "Of the endpoint variance, the run's own noise is %.0f%% in x and %.0f%% in y; "
                   "the parameters the rest.",
                   tr.endpoint.x(), tr.endpoint.y(), std::sqrt(tr.covariance(0, 0)),
                   std::sqrt(tr.covariance(1, 1)), tr.raw_endpoint.x(), tr.raw_endpoint.y(),
                   100 * tr.noise_part(0, 0) / tr.covariance(0, 0),
                   100 * tr.noise_part(1, 1) / tr.covariance(1, 1)));
  const AxisErrorBudget& bx = r.trajectory.budget[0];
  trajectory.paragraphs.push_back(StringPrintf(
      "The reference report's bound takes the run's noise as 3 sigma_eta = %.2f m in x; its double "
      "integral is %.2f m "
      "(3 sigma), %.1f times more.",
      bx.noise.report_m, bx.noise.three_sigma_m, bx.noise.three_sigma_m / bx.noise.report_m));
  trajectory.table.push_back(
      {"landmark", "x (m)", "y (m)", "Mahalanobis^2", "posterior", "p-value"});
  for (const LandmarkScore& score : r.trajectory.decision.scores) {
    trajectory.table.push_back({score.landmark.name, Num(score.landmark.x_m, "%.2f"),
                                Num(score.landmark.y_m, "%.2f"), Num(score.mahalanobis2, "%.3f"),
                                Num(score.posterior, "%.3g"), Num(score.p_value, "%.3g")});
  }
  trajectory.figure = "trajectory.png";
  trajectory.figure_caption = "Raw and corrected paths, 1-sigma and 3-sigma ellipses, landmarks";
  doc.sections.push_back(trajectory);

  ReportSection discovery{"3. What the baseline gets wrong: discovery"};
  discovery.paragraphs.push_back(
      StringPrintf("Verdict: %s (of explained, missing, unexplained, cannot_tell_apart). ",
                   VerdictCode(d.verdict_code)) +
      Sentence(d.verdict) + ".");
  discovery.paragraphs.push_back(
      StringPrintf("Noise level against the statement (von Neumann): ratio %.4f +- %.4f (x), %.4f "
                   "+- %.4f (y). %s.",
                   d.axes[0].noise.ratio, d.axes[0].noise.ratio_stddev, d.axes[1].noise.ratio,
                   d.axes[1].noise.ratio_stddev, Sentence(d.landmark_note).c_str()));
  {
    // The noise read from local differences of the baseline's residuals, and what was named.
    std::string noise = "Noise read from local differences:";
    for (int k = 0; k < 2; ++k) {
      const NoiseAnalysis& a = d.noise_analysis[k];
      noise += StringPrintf(
          "%s %s level ratio %s, lag-1 correlation %s, %zu outlier candidates, excess kurtosis %s",
          k == 0 ? "" : ";", k == 0 ? "x" : "y", Finite(a.variance_ratio, "%.4f").c_str(),
          Finite(a.correlation, "%+.3f").c_str(), a.outlier_candidates.size(),
          Finite(a.excess_kurtosis, "%+.2f").c_str());
    }
    noise += ".";
    if (d.noise_findings.empty()) {
      noise += " No correlation, outliers or heavy tails named.";
    } else {
      // Their sentences are in the verdict above.
      noise += " Named:";
      for (const NoiseFinding& finding : d.noise_findings)
        noise += StringPrintf(" %s on %s,", NoiseFindingName(finding.kind),
                              finding.axis == 0 ? "x" : "y");
      noise.back() = '.';
    }
    if (d.robust_fit) noise += " The final estimates are Huber's (sandwich covariance).";
    discovery.paragraphs.push_back(noise);
  }
  {
    std::string remains = "What the final model leaves: ";
    if (d.remaining.empty()) {
      remains += "nothing the checks can see";
      if (!d.checks.empty()) remains += StringPrintf(" (%zu checks)", d.checks.size());
    } else {
      for (size_t i = 0; i < d.remaining.size(); ++i)
        remains += (i == 0 ? "" : "; ") + d.remaining[i];
    }
    const CrossValidation& cv = d.cross_validation;
    if (cv.folds > 0 && cv.null_stddev > 0.0 && std::isfinite(cv.z)) {
      remains += StringPrintf(
          ". Cross-validation: held-out error %.4f against %.4f +- %.4f for a right model (z = "
          "%+.2f), %s",
          cv.extended, cv.null_mean, cv.null_stddev, cv.z,
          cv.z > 3.0    ? "above its null spread: the model misses something"
          : cv.z < -3.0 ? "below its null spread"
                        : "within its null spread");
    }
    discovery.paragraphs.push_back(remains + ".");
  }
  for (const Ambiguity& ambiguity : d.ambiguities) {
    std::string text =
        StringPrintf("Cannot tell apart: %s = %s +- %s %s", Info(ambiguity.effect).name,
                     Finite(ambiguity.effect_estimate, "%.4g").c_str(),
                     Finite(ambiguity.effect_stddev, "%.2g").c_str(), Info(ambiguity.effect).unit);
    for (const Ambiguity::Alternative& alternative : ambiguity.alternatives) {
      text += StringPrintf(" or %s = %s +- %s %s (delta chi2 %s)", alternative.Name().c_str(),
                           Finite(alternative.estimate, "%.4g").c_str(),
                           Finite(alternative.stddev, "%.2g").c_str(), alternative.Unit().c_str(),
                           Finite(alternative.delta_chi2, "%+.2f").c_str());
    }
    if (!ambiguity.separation.empty())
      text += ". What would separate them: " + ambiguity.separation;
    discovery.paragraphs.push_back(text + ".");
  }
  discovery.table.push_back({"step", "candidate", "delta chi2", "p-value", "significant"});
  for (const CandidateScore& c : d.candidates) {
    if (c.step == 1 || c.significant) {
      discovery.table.push_back({std::to_string(c.step), Info(c.effect).name,
                                 Num(c.delta_chi2, "%.2f"), Num(c.p_value, "%.3g"),
                                 c.significant ? "yes" : ""});
    }
  }
  discovery.figure = "discovery.png";
  discovery.figure_caption =
      "The baseline's residual against theta with the named effects' signatures; endpoint before "
      "and after; what the final model leaves, against theta and against the sample's place in "
      "the test, with a running mean";
  doc.sections.push_back(discovery);

  ReportSection joint{"4. The joint model with what discovery selected"};
  const ParameterEstimate linear = FromBaselineFit(fit);
  joint.paragraphs.push_back(
      StringPrintf("One Ceres problem over the tilt test and the run tied to %s; covariance from "
                   "ceres::Covariance. "
                   "Cross-validation over 5 contiguous theta blocks: held-out mean squared "
                   "whitened error %.4f (baseline), %.4f (extended).",
                   d.tied_landmark.empty() ? "no landmark" : d.tied_landmark.c_str(),
                   d.cross_validation.baseline, d.cross_validation.extended));
  joint.table.push_back({"parameter", "unit", "baseline", "joint", "shift (baseline sigma)"});
  for (const Parameter parameter : d.extended.estimate.free) {
    const bool in_baseline = linear.IndexOf(parameter) >= 0;
    joint.table.push_back(
        {Info(parameter).name, Info(parameter).unit,
         in_baseline ? Num(linear.Value(parameter), "%+.4e") + " +- " +
                           Num(linear.StandardDeviation(parameter), "%.2e")
                     : "",
         Num(d.extended.estimate.Value(parameter), "%+.4e") + " +- " +
             Num(d.extended.estimate.StandardDeviation(parameter), "%.2e"),
         in_baseline ? Num((d.extended.estimate.Value(parameter) - linear.Value(parameter)) /
                               linear.StandardDeviation(parameter),
                           "%+.2f")
                     : ""});
  }
  doc.sections.push_back(joint);

  ReportSection samples{"5. How many calibration samples decide the landmark"};
  samples.paragraphs.push_back(
      StringPrintf("Criterion: P(deciding a wrong landmark) <= %g, with the endpoint covariance J "
                   "sigma^2 (A^T A)^-1 J^T (shrinks "
                   "with N) plus the run's own noise (does not). The analytic curves are checked "
                   "by Monte Carlo in build/bin/min_samples.",
                   FLAGS_max_error));
  samples.table.push_back({"design", "N_min", "N for one landmark in the 3-sigma ellipse"});
  for (const DesignCurve& design : r.designs) {
    std::string name = design.name;
    if (name == "optimal")
      name += StringPrintf(" (%.0f and %.0f deg)", design.theta_a * 180 / M_PI,
                           design.theta_b * 180 / M_PI);
    samples.table.push_back({name, SampleCountText(design.n_min, inputs.test.size()),
                             SampleCountText(design.n_min_3sigma, inputs.test.size())});
  }
  samples.figure = "min_samples.png";
  samples.figure_caption = "P(wrong landmark) against the number of tilt-test samples, per design";
  doc.sections.push_back(samples);

  if (!absent.empty()) {
    ReportSection missing{"Figures not drawn"};
    for (const auto& [figure, why] : absent)
      missing.paragraphs.push_back(figure + ": " + why + ".");
    doc.sections.push_back(missing);
  }
  return doc;
}

// `figures_drawn` receives how many of the three figures were drawn.
Status Write(const Inputs& inputs, const Results& r, int* figures_drawn) {
  return WriteDirectoryAtomically(FLAGS_out_dir, FLAGS_overwrite, [&](const std::string& dir) {
    nlohmann::json designs = nlohmann::json::array();
    for (const DesignCurve& design : r.designs)
      designs.push_back(DesignJson(design, nlohmann::json::array()));
    const nlohmann::json min_samples = {
        {"problem", "min_samples"},
        {"truth", r.trajectory.decision.best >= 0
                      ? nlohmann::json(
                            r.trajectory.decision.scores[r.trajectory.decision.best].landmark.name)
                      : nlohmann::json(nullptr)},
        {"max_error", FLAGS_max_error},
        {"full_samples", inputs.test.size()},
        {"designs", designs}};
    const nlohmann::json results = {{"source", inputs.source},
                                    {"truth", inputs.truth},
                                    {"linear_ls", LinearLsJson(r.linear)},
                                    {"trajectory", TrajectoryJson(r.trajectory)},
                                    {"discover", DiscoveryJson(r.discovery, FLAGS_alpha)},
                                    {"min_samples", min_samples}};
    ACCELCAL_RETURN_IF_ERROR(WriteJsonAtomically(dir + "/results.json", results));
    ACCELCAL_RETURN_IF_ERROR(WriteJsonAtomically(dir + "/trajectory.json", results["trajectory"]));
    ACCELCAL_RETURN_IF_ERROR(WriteJsonAtomically(dir + "/discover.json", results["discover"]));
    ACCELCAL_RETURN_IF_ERROR(WriteJsonAtomically(dir + "/min_samples.json", min_samples));
    ACCELCAL_RETURN_IF_ERROR(
        WriteFileAtomically(dir + "/path.csv", TrajectoryPathCsv(r.trajectory.trajectory)));
    ACCELCAL_RETURN_IF_ERROR(WriteFileAtomically(dir + "/bins.csv", DiscoveryBinsCsv(r.discovery)));
    ACCELCAL_RETURN_IF_ERROR(WriteFileAtomically(dir + "/residuals.csv",
                                                 DiscoveryResidualsCsv(r.discovery, inputs.test)));
    std::map<std::string, std::string> absent;
    const std::map<std::string, std::pair<std::string, std::vector<std::string>>> figures = {
        {"trajectory.png",
         {"plot_trajectory.py",
          {"--json=" + dir + "/trajectory.json", "--path_csv=" + dir + "/path.csv"}}},
        {"discovery.png",
         {"plot_discovery.py",
          {"--json=" + dir + "/discover.json", "--bins_csv=" + dir + "/bins.csv",
           "--residuals_csv=" + dir + "/residuals.csv"}}},
        {"min_samples.png", {"plot_min_samples.py", {"--json=" + dir + "/min_samples.json"}}}};
    for (const auto& [figure, script] : figures) {
      std::vector<std::string> arguments = script.second;
      arguments.push_back("--out=" + dir + "/" + figure);
      const std::string why = Plot(script.first, arguments);
      if (!why.empty()) absent[figure] = why;
    }
    *figures_drawn = static_cast<int>(figures.size() - absent.size());
    const ReportDocument document = Document(inputs, r, absent);
    ACCELCAL_RETURN_IF_ERROR(WriteFileAtomically(dir + "/report.md", RenderMarkdown(document)));
    return WriteFileAtomically(dir + "/report.html", RenderHtml(document, dir));
  });
}

int Run(int argc, char** argv) {
  if (!InitProblem("analyze", kUsage, "problems/analyze", &argc, &argv)) return kExitBadInput;
  Status status;
  if (FLAGS_out_dir.empty()) status = Status::Error("--out_dir must name a folder");
  Inputs inputs;
  if (status.ok()) status = Load(&inputs);
  Results results;
  if (status.ok()) status = Analyse(inputs, ChooseGravity(inputs.conditions, FLAGS_g), &results);
  int figures_drawn = 0;
  if (status.ok()) status = Write(inputs, results, &figures_drawn);
  if (!status.ok()) return ExitWithError("analyze", status);
  std::cout << "accelcal analyze: " << results.discovery.verdict << "\n  report: " << FLAGS_out_dir
            << "/report.html (and report.md, results.json"
            << (figures_drawn == 3   ? ", figures)"
                : figures_drawn == 0 ? "; no figures were drawn: the report says why)"
                                     : "; some figures were not drawn: the report says why)")
            << "\n";
  return 0;
}

}  // namespace
}  // namespace accelcal

int main(int argc, char** argv) {
  return accelcal::GuardedMain("analyze", accelcal::Run, argc, argv);
}
