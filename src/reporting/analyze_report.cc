#include "reporting/analyze_report.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>

#include "common/format.h"
#include "io/atomic_file.h"
#include "io/json_file.h"
#include "io/subprocess.h"
#include "reporting/discovery_report.h"
#include "reporting/min_samples_report.h"
#include "reporting/reference_report.h"
#include "reporting/report_document.h"

namespace accelcal {

ReportSection ProvenanceSection(const DataSource& source, const std::string& title) {
  ReportSection section;
  section.title = title;
  const std::string date = UtcNow("%Y-%m-%d %H:%M:%S UTC");
  section.paragraphs.push_back(DataLine(source) + ".");
  section.paragraphs.push_back(std::string("Written by accelcal ") + AccelcalVersion() + " on " +
                               date + " with: " + CommandLine());
  if (!source.files.empty()) {
    section.table.push_back({"role", "file", "bytes", "SHA-256"});
    for (const auto& [role, file] : source.files) {
      section.table.push_back({role, file.path, std::to_string(file.bytes), file.sha256});
    }
  } else {
    section.paragraphs.push_back(
        "No file was read: the scenario and the seed above reproduce these data exactly.");
  }
  return section;
}

namespace {

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

}  // namespace

std::string Plot(const FigureTools& tools, const std::string& script,
                 const std::vector<std::string>& arguments) {
  const std::string path = tools.tools_dir + "/" + script;
  if (access(path.c_str(), R_OK) != 0) return "the script " + path + " is not there (--tools_dir)";
  int exit_status = 0;
  Status status =
      RunProgram({tools.python, "-c", "import matplotlib, numpy"}, kPlotTimeoutS, &exit_status);
  if (!status.ok()) return status.message() + " (--python)";
  if (exit_status != 0) {
    return tools.python +
           " has no matplotlib/numpy (apt-get install python3-matplotlib python3-numpy)";
  }
  std::vector<std::string> argv = {tools.python, path};
  argv.insert(argv.end(), arguments.begin(), arguments.end());
  status = RunProgram(argv, kPlotTimeoutS, &exit_status);
  if (!status.ok()) return status.message();
  return exit_status == 0 ? ""
                          : script + " failed (exit status " + std::to_string(exit_status) + ")";
}

namespace {

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

// The step that added each effect forward selection added: the last step it was scored at
// (an added effect leaves the candidates, and one dropped later is not offered again).
std::map<std::string, int> StepsAdded(const DiscoveryResult& d) {
  std::map<std::string, int> last_scored;
  for (const CandidateScore& c : d.candidates) last_scored[Info(c.effect).name] = c.step;
  std::map<std::string, int> added;
  for (const SelectionEvent& event : d.history) {
    const auto scored = last_scored.find(Info(event.effect).name);
    if (event.kind == SelectionEvent::Kind::kAdded && scored != last_scored.end())
      added[scored->first] = scored->second;
  }
  return added;
}

// Why an effect left the model, in words.
std::string DropReason(SelectionEvent::Kind kind) {
  return kind == SelectionEvent::Kind::kDroppedForShape
             ? "explained by the remaining structure"
             : "not needed once the effects added after it were in";
}

// What became of each row of d.candidates: added (and dropped later, and why), or, for a
// significant one not added, which effect its step added instead and the step that scored it
// again.
std::vector<std::string> CandidateOutcomes(const DiscoveryResult& d) {
  const std::map<std::string, int> added = StepsAdded(d);
  std::map<std::string, std::string> dropped;
  for (const SelectionEvent& event : d.history)
    if (event.kind != SelectionEvent::Kind::kAdded)
      dropped[Info(event.effect).name] = DropReason(event.kind);
  std::map<int, std::string> added_at;
  for (const auto& [name, step] : added) added_at[step] = name;
  std::vector<std::string> outcomes;
  for (const CandidateScore& c : d.candidates) {
    const std::string name = Info(c.effect).name;
    const auto step = added.find(name);
    if (step != added.end() && step->second == c.step) {
      const auto gone = dropped.find(name);
      outcomes.push_back(gone == dropped.end() ? "added" : "added; dropped later: " + gone->second);
      continue;
    }
    if (!c.significant) {
      // One significant at an earlier step is explained by what was added since.
      bool was_significant = false;
      for (const CandidateScore& earlier : d.candidates)
        was_significant |=
            earlier.step < c.step && earlier.effect == c.effect && earlier.significant;
      std::string since;
      for (const auto& [step, effect] : added_at)
        if (step < c.step) since += (since.empty() ? "" : ", ") + effect;
      outcomes.push_back(was_significant && !since.empty()
                             ? "no longer significant with " + since + " in the model"
                             : "");
      continue;
    }
    // The first later step that scored it again, if any.
    int again = 0;
    for (const CandidateScore& later : d.candidates) {
      if (later.step > c.step && later.effect == c.effect) {
        again = later.step;
        break;
      }
    }
    const auto instead = added_at.find(c.step);
    std::string outcome = instead == added_at.end()
                              ? std::string("not added (not separable from the model)")
                              : instead->second + " added instead (larger delta chi2)";
    outcome += again > 0 ? StringPrintf("; scored again at step %d", again)
                         : std::string("; not scored again");
    outcomes.push_back(outcome);
  }
  return outcomes;
}

// How the model grew, in order: each addition with its step, each drop with its reason.
std::string ModelGrowth(const DiscoveryResult& d) {
  if (d.history.empty()) return "How the model grew: no step added an effect.";
  const std::map<std::string, int> added = StepsAdded(d);
  std::string text = "How the model grew: ";
  for (size_t i = 0; i < d.history.size(); ++i) {
    const SelectionEvent& event = d.history[i];
    const std::string name = Info(event.effect).name;
    text += i == 0 ? "" : "; ";
    if (event.kind == SelectionEvent::Kind::kAdded) {
      const auto step = added.find(name);
      text += step == added.end() ? "added " : StringPrintf("step %d added ", step->second);
    } else {
      text += "dropped ";
    }
    text += name + StringPrintf(" (delta chi2 %.2f, p = %.3g, run tied to %s)", event.delta_chi2,
                                event.p_value,
                                event.landmark.empty() ? "no landmark" : event.landmark.c_str());
    if (event.kind != SelectionEvent::Kind::kAdded) text += ": " + DropReason(event.kind);
  }
  const int last_step = d.candidates.empty() ? 0 : d.candidates.back().step;
  bool any_significant = false;
  for (const CandidateScore& c : d.candidates)
    any_significant |= c.step == last_step && c.significant;
  if (last_step > 0 && !any_significant)
    text +=
        StringPrintf("; step %d found no candidate significant, which ends the search", last_step);
  return text + ".";
}

// The effects hidden in simulated data with their values ("angle_offset = 0.004 rad"), or "".
std::string HiddenEffects(const nlohmann::json& truth) {
  std::string text;
  for (const auto& item : truth["parameters"].items()) {
    const ParameterInfo* info = FindParameter(item.key());
    if (info != nullptr && !info->baseline && item.value().get<double>() != info->neutral) {
      text += std::string(text.empty() ? "" : ", ") + item.key() + " = " +
              Num(item.value().get<double>()) + " " + info->unit;
    }
  }
  return text;
}

// The landmark decision in plain words: the landmark reached and how far (in sigma of the
// endpoint covariance) it and the nearest other one are.
std::string LandmarkSummary(const LandmarkDecision& decision) {
  if (decision.scores.empty() || decision.best < 0)
    return "No landmarks were given, so none is decided.";
  const LandmarkScore& best = decision.scores[decision.best];
  const LandmarkScore* runner_up = nullptr;
  for (const LandmarkScore& score : decision.scores) {
    if (&score != &best && (runner_up == nullptr || score.mahalanobis2 < runner_up->mahalanobis2))
      runner_up = &score;
  }
  std::string text =
      decision.reached.empty()
          ? StringPrintf(
                // clang-format off
                "No landmark is consistent with the endpoint: the nearest, %s, is %.2f sigma away (p = %.3g, below alpha = %g)",
                // clang-format on
                best.landmark.name.c_str(), std::sqrt(best.mahalanobis2), best.p_value,
                decision.alpha)
          : StringPrintf("The vehicle reached %s: the endpoint is %.2f sigma from it (p = %.3g)",
                         decision.reached.c_str(), std::sqrt(best.mahalanobis2), best.p_value);
  if (runner_up != nullptr) {
    const double sigmas = std::sqrt(runner_up->mahalanobis2);
    text += std::floor(sigmas) >= 1.0
                ? StringPrintf(
                      "; every other landmark is more than %.0f sigma away (the nearest, %s, %.2f "
                      "sigma)",
                      std::floor(sigmas), runner_up->landmark.name.c_str(), sigmas)
                : StringPrintf("; the next nearest, %s, is %.2f sigma away",
                               runner_up->landmark.name.c_str(), sigmas);
  }
  return text + ".";
}

// The baseline fit against the stated noise, and discovery's verdict, in one line.
std::string BaselineSummary(const AnalyzeReport& r) {
  const BaselineFit& fit = r.linear.closed_form;
  const AxisChiSquare* axes[2] = {&fit.chi2_x, &fit.chi2_y};
  std::string failing;
  for (int k = 0; k < 2; ++k)
    if (axes[k]->p_value < r.alpha)
      failing += std::string(failing.empty() ? "" : " and ") + "xy"[k];
  return StringPrintf(
      // clang-format off
             "The baseline fit (bias and scale per axis): the stated noise %s (chi2/dof %.4f in x, p = %.3g; %.4f in y, p = %.3g). %s: %s.",
      // clang-format on
      failing.empty() ? "explains the size of its residuals"
                      : ("does not explain the size of its residuals on " + failing).c_str(),
      fit.chi2_x.chi2 / fit.chi2_x.dof, fit.chi2_x.p_value, fit.chi2_y.chi2 / fit.chi2_y.dof,
      fit.chi2_y.p_value,
      failing.empty() && r.discovery.verdict_code != Verdict::kExplained
          ? "Yet discovery, which looks beyond their size, finds"
          : "Discovery",
      r.discovery.verdict.c_str());
}

// Why the joint column differs from the linear one: the run tied to a landmark (the endpoint
// residual pulls on what the endpoint depends on), then the effects discovery added; each
// shift in sigma of the linear estimate.
std::string JointShift(const AnalyzeReport& r, const ParameterEstimate& linear) {
  const DiscoveryResult& d = r.discovery;
  auto shifts = [&](const ParameterEstimate& from, const ParameterEstimate& to, bool* any) {
    std::string moved;
    std::string still;
    for (const Parameter parameter : kBaselineParameters) {
      if (from.IndexOf(parameter) < 0 || to.IndexOf(parameter) < 0) continue;
      const double sigmas =
          (to.Value(parameter) - from.Value(parameter)) / linear.StandardDeviation(parameter);
      std::string& list = std::abs(sigmas) >= 0.05 ? moved : still;
      list += std::string(list.empty() ? "" : ", ") + Info(parameter).name +
              (std::abs(sigmas) >= 0.05 ? StringPrintf(" %+.2f sigma", sigmas) : "");
    }
    *any = !moved.empty();
    return (moved.empty() ? std::string("no baseline parameter moves by 0.05 sigma or more")
                          : "it moves " + moved) +
           (still.empty() || moved.empty() ? "" : "; " + still + " by less than 0.05 sigma");
  };
  std::string text;
  bool any = false;
  if (d.tied_landmark.empty()) {
    text =
        "Why the joint column moves: the run is tied to no landmark, so only the effects "
        "discovery added can move the baseline parameters";
  } else {
    text = StringPrintf(
        // clang-format off
        "Why the joint column moves: the joint problem ties the run's endpoint to %s, the landmark decided, so the endpoint's residual (chi2 %.2f on 2) pulls on the parameters the endpoint depends on. Tied to %s with no effect added, ",
        // clang-format on
        d.tied_landmark.c_str(), d.baseline_joint.chi2_endpoint, d.tied_landmark.c_str());
    text += shifts(linear, d.baseline_joint.estimate, &any) +
            " (in sigma of the baseline's linear estimate)";
    const AxisErrorBudget& bx = r.trajectory.budget[0];
    const AxisErrorBudget& by = r.trajectory.budget[1];
    text += StringPrintf(
        // clang-format off
        ". Each moves in proportion to how much the endpoint depends on it: 3 sigma of the biases moves the endpoint %.2f m (x) and %.2f m (y), 3 sigma of the scales %.2f m and %.2f m",
        // clang-format on
        bx.bias.three_sigma_m, by.bias.three_sigma_m, bx.scale.three_sigma_m,
        by.scale.three_sigma_m);
  }
  if (!d.effects.empty()) {
    std::string names;
    for (const DiscoveredEffect& effect : d.effects)
      names += std::string(names.empty() ? "" : ", ") + Info(effect.effect).name;
    const ParameterEstimate& from = d.tied_landmark.empty() ? linear : d.baseline_joint.estimate;
    text += ". With the effects discovery added (" + names + "), " +
            shifts(from, d.extended.estimate, &any);
  } else {
    text += ". Discovery added no effect, so this is the whole shift";
  }
  return text + ".";
}

ReportDocument Document(const AnalyzeReport& r, const std::map<std::string, std::string>& absent) {
  ReportDocument doc;
  doc.title = "accelcal report";
  const DiscoveryResult& d = r.discovery;
  const LandmarkDecision& decision = r.trajectory.decision;
  doc.verdict = DiscoveryBox(d) + " Landmark: " +
                (decision.reached.empty()
                     ? std::string("no landmark is consistent with the endpoint")
                     : decision.reached +
                           StringPrintf(" (p = %.3g)", decision.scores[decision.best].p_value)) +
                ". Data: " + r.source + ".";
  const std::string hidden = r.truth.is_null() ? "" : HiddenEffects(r.truth);
  if (!r.truth.is_null()) {
    doc.verdict +=
        " The truth hidden in it: " + (hidden.empty() ? std::string("no effect") : hidden) +
        "; the run ends at " + r.truth["reached_landmark"].get<std::string>() + ".";
  }
  const ReferenceComparison reference = CompareWithReferenceReport(r);
  doc.summary.push_back(LandmarkSummary(decision));
  doc.summary.push_back(BaselineSummary(r));
  if (!r.truth.is_null()) {
    doc.summary.push_back("These data are simulated: " +
                          (hidden.empty() ? std::string("no effect is hidden in them")
                                          : "the truth hidden in them is " + hidden) +
                          ", and the run ends at " +
                          r.truth["reached_landmark"].get<std::string>() + ".");
  }
  if (!reference.summary.empty()) doc.summary.push_back(reference.summary);

  ReportSection baseline;
  baseline.title = "1. Baseline: bias and scale by linear least squares";
  const BaselineFit& fit = r.linear.closed_form;
  baseline.paragraphs.push_back(
      // clang-format off
      StringPrintf("%d tilt-test samples, stated noise variances %g and %g (m/s^2)^2, g = %g m/s^2. Chi-square per axis: %.1f and %.1f on %d degrees of freedom. The closed form and Ceres agree to %.1e.",
                   // clang-format on
                   fit.sample_count, r.linear.noise_variance_x, r.linear.noise_variance_y,
                   r.linear.gravity_mps2, fit.chi2_x.chi2, fit.chi2_y.chi2, fit.chi2_x.dof,
                   CompareFits(fit, r.linear.ceres.fit).parameters));
  baseline.table.push_back({"parameter", "estimate", "1 sigma", "unit"});
  for (const Parameter parameter : kBaselineParameters) {
    baseline.table.push_back({Info(parameter).name, Num(fit.Value(parameter), "%+.4e"),
                              Num(fit.StandardDeviation(parameter), "%.3e"), Info(parameter).unit});
  }
  doc.sections.push_back(baseline);

  ReportSection trajectory;
  trajectory.title = "2. Trajectory and landmark";
  const DeadReckoningResult& tr = r.trajectory.trajectory;
  trajectory.paragraphs.push_back(
      // clang-format off
      StringPrintf("Corrected endpoint (%.2f, %.2f) m, 1 sigma %.2f m and %.2f m; the raw outputs integrated end at (%.2f, %.2f) m. Of the endpoint variance, the run's own noise is %.0f%% in x and %.0f%% in y; the parameters the rest.",
                   // clang-format on
                   tr.endpoint.x(), tr.endpoint.y(), std::sqrt(tr.covariance(0, 0)),
                   std::sqrt(tr.covariance(1, 1)), tr.raw_endpoint.x(), tr.raw_endpoint.y(),
                   100 * tr.noise_part(0, 0) / tr.covariance(0, 0),
                   100 * tr.noise_part(1, 1) / tr.covariance(1, 1)));
  const AxisErrorBudget& bx = r.trajectory.budget[0];
  trajectory.paragraphs.push_back(StringPrintf(
      // clang-format off
      "The reference report's bound takes the run's noise as 3 sigma_eta = %.2f m in x; its double integral is %.2f m (3 sigma), %.1f times more.",
      // clang-format on
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

  ReportSection discovery;
  discovery.title = "3. What the baseline gets wrong: discovery";
  discovery.paragraphs.push_back(
      StringPrintf("Verdict: %s (of explained, missing, unexplained, cannot_tell_apart). ",
                   VerdictCode(d.verdict_code)) +
      Sentence(d.verdict) + ".");
  discovery.paragraphs.push_back(
      // clang-format off
      StringPrintf("Noise level against the statement (von Neumann): ratio %.4f +- %.4f (x), %.4f +- %.4f (y). %s.",
                   // clang-format on
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
          // clang-format off
          ". Cross-validation: held-out error %.4f against %.4f +- %.4f for a right model (z = %+.2f), %s",
          // clang-format on
          cv.extended, cv.null_mean, cv.null_stddev, cv.z,
          cv.z > 3.0    ? "above its null spread: the model misses something"
          : cv.z < -3.0 ? "below its null spread"
                        : "within its null spread");
    }
    discovery.paragraphs.push_back(remains + ".");
  }
  for (const Ambiguity& ambiguity : d.ambiguities) {
    std::string text = "Cannot tell apart: " + ambiguity.text;
    if (!ambiguity.separation.empty())
      text += ". What would separate them: " + ambiguity.separation;
    discovery.paragraphs.push_back(text + ".");
  }
  discovery.paragraphs.push_back(
      // clang-format off
      "Each step scores every candidate left against the model of that step (score test, Holm at alpha/2) and adds the most significant one; the next step scores the rest again against the grown model, so an effect significant at one step may be explained by the one added there. Backward elimination then drops what the grown model no longer needs.");
  // clang-format on
  discovery.paragraphs.push_back(ModelGrowth(d));
  discovery.table.push_back(
      {"step", "candidate", "delta chi2", "p-value", "significant", "outcome"});
  const std::vector<std::string> outcomes = CandidateOutcomes(d);
  for (size_t i = 0; i < d.candidates.size(); ++i) {
    const CandidateScore& c = d.candidates[i];
    discovery.table.push_back({std::to_string(c.step), Info(c.effect).name,
                               Num(c.delta_chi2, "%.2f"), Num(c.p_value, "%.3g"),
                               c.significant ? "yes" : "", outcomes[i]});
  }
  discovery.figure = "discovery.png";
  discovery.figure_caption =
      // clang-format off
      "The baseline's residual against theta with the named effects' signatures; endpoint before and after; what the final model leaves, against theta and against the sample's place in the test, with a running mean";
  // clang-format on
  doc.sections.push_back(discovery);

  ReportSection joint;
  joint.title = "4. The joint model with what discovery selected";
  const ParameterEstimate linear = FromBaselineFit(fit);
  joint.paragraphs.push_back(
      // clang-format off
      StringPrintf("One Ceres problem over the tilt test and the run tied to %s; covariance from ceres::Covariance. Cross-validation over 5 contiguous theta blocks: held-out mean squared whitened error %.4f (baseline), %.4f (extended).",
                   // clang-format on
                   d.tied_landmark.empty() ? "no landmark" : d.tied_landmark.c_str(),
                   d.cross_validation.baseline, d.cross_validation.extended));
  joint.paragraphs.push_back(JointShift(r, linear));
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

  ReportSection samples;
  samples.title = "5. How many calibration samples decide the landmark";
  samples.paragraphs.push_back(
      // clang-format off
      StringPrintf("Criterion: P(deciding a wrong landmark) <= %g, with the endpoint covariance J sigma^2 (A^T A)^-1 J^T (shrinks with N) plus the run's own noise (does not). The analytic curves are checked by Monte Carlo in build/bin/min_samples.",
                   // clang-format on
                   r.max_error));
  samples.table.push_back({"design", "N_min", "N for one landmark in the 3-sigma ellipse"});
  for (const DesignCurve& design : r.min_samples.designs) {
    std::string name = design.name;
    if (name == "optimal")
      name += StringPrintf(" (%.0f and %.0f deg)", design.theta_a * 180 / M_PI,
                           design.theta_b * 180 / M_PI);
    samples.table.push_back({name, SampleCountText(design.n_min, r.min_samples.full_samples),
                             SampleCountText(design.n_min_3sigma, r.min_samples.full_samples)});
  }
  samples.figure = "min_samples.png";
  samples.figure_caption = "P(wrong landmark) against the number of tilt-test samples, per design";
  doc.sections.push_back(samples);

  ReportSection comparison;
  comparison.title = "6. The reference report and this analysis";
  comparison.paragraphs.push_back(reference.recognition);
  if (!reference.rows.empty()) {
    comparison.table.push_back({"figure", "reference report", "this analysis", "verdict"});
    for (const ReferenceRow& row : reference.rows)
      comparison.table.push_back({row.figure, row.reference, row.accelcal, row.verdict});
  }
  doc.sections.push_back(comparison);
  doc.sections.push_back(ProvenanceSection(r.data_source, "7. Provenance"));

  if (!absent.empty()) {
    ReportSection missing;
    missing.title = "Figures not drawn";
    for (const auto& [figure, why] : absent)
      missing.paragraphs.push_back(figure + ": " + why + ".");
    doc.sections.push_back(missing);
  }
  return doc;
}

}  // namespace

nlohmann::json AnalyzeJson(const AnalyzeReport& r) {
  nlohmann::json json = {
      {"truth", r.truth},
      {"linear_ls", LinearLsJson(r.linear)},
      {"trajectory", TrajectoryJson(r.trajectory)},
      {"discover", DiscoveryJson(r.discovery, r.alpha)},
      {"min_samples", MinSamplesJson({r.min_samples, r.landmarks, r.max_error})}};
  AddProvenanceJson(r.data_source, &json);
  return json;
}

std::string FigureOutcomeLine(const FigureOutcome& figures) {
  auto list = [](const std::vector<std::string>& names) {
    std::string text;
    for (const std::string& name : names) text += (text.empty() ? "" : ", ") + name;
    return text;
  };
  if (figures.absent.empty()) return "all drawn (" + list(figures.drawn) + ")";
  std::vector<std::string> absent;
  std::vector<std::string> reasons;
  for (const auto& [figure, why] : figures.absent) {
    absent.push_back(figure);
    if (std::find(reasons.begin(), reasons.end(), why) == reasons.end()) reasons.push_back(why);
  }
  std::string line = figures.drawn.empty()
                         ? std::string("none drawn: ")
                         : list(figures.drawn) + " drawn; " + list(absent) + " not drawn: ";
  if (reasons.size() == 1) return line + reasons[0];
  for (size_t i = 0; i < absent.size(); ++i)
    line += (i == 0 ? "" : "; ") + absent[i] + ": " + figures.absent.at(absent[i]);
  return line;
}

Status WriteAnalyzeReport(const std::string& dir, const AnalyzeReport& r, const FigureTools& tools,
                          FigureOutcome* outcome) {
  const nlohmann::json results = AnalyzeJson(r);
  ACCELCAL_RETURN_IF_ERROR(WriteJsonAtomically(dir + "/results.json", results));
  ACCELCAL_RETURN_IF_ERROR(WriteJsonAtomically(dir + "/trajectory.json", results["trajectory"]));
  ACCELCAL_RETURN_IF_ERROR(WriteJsonAtomically(dir + "/discover.json", results["discover"]));
  ACCELCAL_RETURN_IF_ERROR(WriteJsonAtomically(dir + "/min_samples.json", results["min_samples"]));
  ACCELCAL_RETURN_IF_ERROR(
      WriteFileAtomically(dir + "/path.csv", TrajectoryPathCsv(r.trajectory.trajectory)));
  ACCELCAL_RETURN_IF_ERROR(WriteFileAtomically(dir + "/bins.csv", DiscoveryBinsCsv(r.discovery)));
  ACCELCAL_RETURN_IF_ERROR(
      WriteFileAtomically(dir + "/residuals.csv", DiscoveryResidualsCsv(r.discovery, r.test)));
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
    const std::string why = Plot(tools, script.first, arguments);
    if (!why.empty()) absent[figure] = why;
  }
  outcome->absent = absent;
  outcome->drawn.clear();
  // In the report's order, not the map's.
  for (const char* figure : {"trajectory.png", "discovery.png", "min_samples.png"})
    if (figures.count(figure) == 1 && absent.count(figure) == 0) outcome->drawn.push_back(figure);
  const ReportDocument document = Document(r, absent);
  ACCELCAL_RETURN_IF_ERROR(WriteFileAtomically(dir + "/report.md", RenderMarkdown(document)));
  return WriteFileAtomically(dir + "/report.html", RenderHtml(document, dir));
}

}  // namespace accelcal
