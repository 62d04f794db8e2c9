#include "estimation/tilt_table/discovery.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "common/format.h"
#include "estimation/discovery/selection.h"
#include "estimation/statistics/chi_square.h"
#include "estimation/tilt_table/joint_data.h"
#include "estimation/tilt_table/robust_covariance.h"
#include "estimation/tilt_table/score_test.h"

namespace accelcal {

const char* NoiseFindingName(NoiseFinding::Kind kind) {
  switch (kind) {
    case NoiseFinding::Kind::kCorrelation:
      return "noise_correlation";
    case NoiseFinding::Kind::kOutliers:
      return "outliers";
    case NoiseFinding::Kind::kHeavyTails:
      return "heavy_tailed_noise";
  }
  return "noise_correlation";
}

namespace {

double TotalChi2(const JointResult& result) {
  return result.chi2_x + result.chi2_y + result.chi2_endpoint;
}

// The landmark the current model points at, judged without tying the run to any: a
// landmark-free fit of the model, dead-reckoned, scored by Mahalanobis distance. An
// unmodelled effect can bias the baseline's endpoint toward the wrong landmark, so the
// tie is decided again each time the model grows.
Status MostProbableLandmark(const JointData& data, JointOptions options, double alpha,
                            std::string* name) {
  name->clear();
  const std::vector<Landmark>& landmarks = data.landmarks();
  if (landmarks.empty()) return Status::Ok();
  options.landmark_mode = JointOptions::Landmark::kNone;
  std::vector<Parameter> calibration_effects;
  for (const Parameter effect : options.effects) {
    if (!ActsOnlyInRun(effect)) calibration_effects.push_back(effect);
  }
  options.effects = calibration_effects;
  JointResult free_run;
  ACCELCAL_RETURN_IF_ERROR(SolveJoint(data, options, &free_run));
  TrajectoryOptions trajectory;
  trajectory.path_stride = data.run().size();
  DeadReckoningResult result;
  ACCELCAL_RETURN_IF_ERROR(
      DeadReckon(data.run(), data.conditions(), free_run.estimate, trajectory, &result));
  const LandmarkDecision decision =
      DecideLandmark(result.endpoint, result.covariance, landmarks, alpha);
  if (decision.best >= 0) *name = decision.scores[decision.best].landmark.name;
  return Status::Ok();
}

// Mean whitened squared error of held-out calibration rows when the model, linearised at
// its solution, is refitted on the other folds: exact for a linear model, and free of
// the drift coordinate's dependence on the sample's place in the whole test.
double CrossValidate(const Eigen::MatrixXd& jacobian, const Eigen::VectorXd& residual,
                     int calibration_rows, int folds) {
  double error = 0.0;
  const int p = static_cast<int>(jacobian.cols());
  const int samples = calibration_rows / 2;
  for (int fold = 0; fold < folds; ++fold) {
    // Contiguous blocks of samples (both axes of a sample stay together).
    const int begin = 2 * (static_cast<long long>(samples) * fold / folds);
    const int end = 2 * (static_cast<long long>(samples) * (fold + 1) / folds);
    Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(p, p);
    Eigen::VectorXd gradient = Eigen::VectorXd::Zero(p);
    for (int row = 0; row < jacobian.rows(); ++row) {
      if (row >= begin && row < end) continue;
      normal.noalias() += jacobian.row(row).transpose() * jacobian.row(row);
      gradient.noalias() += jacobian.row(row).transpose() * residual[row];
    }
    const Eigen::VectorXd step = normal.ldlt().solve(gradient);
    for (int row = begin; row < end; ++row)
      error += std::pow(residual[row] - jacobian.row(row).dot(step), 2);
  }
  return error / calibration_rows;
}

std::string Fixed(double value, double stddev, const char* unit) {
  return StringPrintf("%.3g +- %.2g %s", value, stddev, unit);
}

// An effect of the final model and its alternatives, in words (Ambiguity::text).
std::string AmbiguityText(const Ambiguity& ambiguity) {
  const char* name = Info(ambiguity.effect).name;
  const char* unit = Info(ambiguity.effect).unit;
  std::string text =
      std::string(name) + " = " + Fixed(ambiguity.effect_estimate, ambiguity.effect_stddev, unit);
  for (const Ambiguity::Alternative& alternative : ambiguity.alternatives) {
    const std::string other =
        alternative.Name() + " = " +
        Fixed(alternative.estimate, alternative.stddev, alternative.Unit().c_str());
    const std::string moved =
        Fixed(alternative.effect_estimate_with, alternative.effect_stddev_with, unit);
    if (alternative.beside) {
      text += StringPrintf(" alone, or %s = %s beside %s%s (delta chi2 %+.2g)", name, moved.c_str(),
                           other.c_str(),
                           alternative.note.empty() ? "" : (", " + alternative.note).c_str(),
                           alternative.delta_chi2);
    } else if (alternative.replaces) {
      const char* replaced = Info(*alternative.replaces).name;
      text += StringPrintf(" with %s, or %s = %s with %s in its place (delta chi2 %+.2g)", replaced,
                           name, moved.c_str(), other.c_str(), alternative.delta_chi2);
    } else {
      text += StringPrintf(" or %s (delta chi2 %+.2g)", other.c_str(), alternative.delta_chi2);
    }
  }
  return text;
}

// The tilt table (and the run tied to a landmark) as a geometry of the one discovery procedure
// (estimation/discovery/selection.h): the joint fit with a set of catalogue effects, candidates
// scored by the score test (chi-square(1)), and every change of the model followed by a new
// decision of the landmark tie. It changes `joint`, `current` and the result's landmark fields
// in place, and logs the landmark each change happened under.
class TiltTableGeometry : public DiscoveryGeometry {
 public:
  TiltTableGeometry(const JointData& data, double alpha, double family_alpha,
                    double ambiguity_delta_chi2, std::vector<Parameter> candidates,
                    JointOptions* joint, JointResult* current, DiscoveryResult* result)
      : data_(data),
        alpha_(alpha),
        family_alpha_(family_alpha),
        ambiguity_delta_chi2_(ambiguity_delta_chi2),
        candidates_(std::move(candidates)),
        joint_(joint),
        current_(current),
        result_(result) {
    for (const Parameter effect : joint_->effects) model_.push_back(IndexOf(effect));
  }

  const std::vector<Parameter>& candidates() const { return candidates_; }
  int IndexOf(Parameter parameter) const {
    return static_cast<int>(std::find(candidates_.begin(), candidates_.end(), parameter) -
                            candidates_.begin());
  }
  // The landmark the run was tied to when each change happened, in order.
  const std::vector<std::string>& landmark_at_change() const { return landmark_at_change_; }

  Status TestCandidates(const std::vector<int>& candidates,
                        std::vector<CandidateTest>* tests) override {
    std::vector<Parameter> parameters;
    for (const int c : candidates) parameters.push_back(candidates_[c]);
    std::vector<double> delta_chi2;
    ACCELCAL_RETURN_IF_ERROR(ScoreCandidates(data_, *joint_, *current_, parameters, &delta_chi2));
    tests->clear();
    for (const double delta : delta_chi2)
      tests->push_back({true, delta, ChiSquareSurvival(delta, 1.0), ""});
    return Status::Ok();
  }

  Status Add(int candidate, double* delta_chi2) override {
    JointOptions extended = *joint_;
    extended.effects.push_back(candidates_[candidate]);
    JointResult refit;
    ACCELCAL_RETURN_IF_ERROR(SolveJoint(data_, extended, &refit));
    *delta_chi2 = TotalChi2(*current_) - TotalChi2(refit);  // same tie before and after
    landmark_at_change_.push_back(joint_->landmark_name);
    *joint_ = extended;
    *current_ = refit;
    model_.push_back(candidate);
    // The grown model may point at another landmark; tie the run to it from now on.
    if (ActsOnlyInRun(candidates_[candidate])) return Status::Ok();
    return Retie(StringPrintf("with %s in the model", Info(candidates_[candidate]).name));
  }

  // The chi-square each effect of the model removes from it: the model without the effect,
  // refitted with the same tie, against the model itself. An effect the smaller model cannot
  // be solved without (it never happens for a model that was solved with it) counts as needed.
  Status TestEffects(std::vector<CandidateTest>* tests) override {
    tests->assign(joint_->effects.size(), {true, HUGE_VAL, 0.0, ""});
    for (size_t e = 0; e < joint_->effects.size(); ++e) {
      JointOptions smaller = *joint_;
      smaller.effects.erase(smaller.effects.begin() + e);
      JointResult without;
      if (SolveJoint(data_, smaller, &without).ok())
        (*tests)[e].delta_chi2 = std::max(0.0, TotalChi2(without) - TotalChi2(*current_));
      (*tests)[e].p_value = ChiSquareSurvival((*tests)[e].delta_chi2, 1.0);
    }
    return Status::Ok();
  }

  Status Drop(size_t effect) override {
    const Parameter gone = joint_->effects[effect];
    landmark_at_change_.push_back(joint_->landmark_name);
    joint_->effects.erase(joint_->effects.begin() + effect);
    model_.erase(model_.begin() + effect);
    ACCELCAL_RETURN_IF_ERROR(SolveJoint(data_, *joint_, current_));
    return Retie(StringPrintf("without %s in the model", Info(gone).name));
  }

  const std::vector<int>& Effects() const override { return model_; }

  bool Swap(size_t effect, int candidate, SwapFit* fit) override {
    JointOptions swapped = *joint_;
    swapped.effects[effect] = candidates_[candidate];
    JointResult alternative;
    if (!SolveJoint(data_, swapped, &alternative).ok()) return false;
    fit->worse = TotalChi2(alternative) - TotalChi2(*current_);
    fit->estimate = alternative.estimate.Value(candidates_[candidate]);
    fit->stddev = alternative.estimate.StandardDeviation(candidates_[candidate]);
    for (size_t e = 0; e < joint_->effects.size(); ++e) {
      const Parameter kept = joint_->effects[e];
      fit->current_estimates.push_back(current_->estimate.Value(kept));
      fit->current_stddevs.push_back(current_->estimate.StandardDeviation(kept));
      const JointResult& in = e == effect ? *current_ : alternative;
      fit->estimates.push_back(in.estimate.Value(kept));
      fit->stddevs.push_back(in.estimate.StandardDeviation(kept));
    }
    return true;
  }

  bool Beside(int candidate, BesideFit* fit) override {
    JointOptions grown = *joint_;
    grown.effects.push_back(candidates_[candidate]);
    // The tie re-decided for the grown model, as Add does: a candidate that moves the
    // endpoint to another landmark is judged with the run tied there.
    if (grown.landmark_mode == JointOptions::Landmark::kNamed) {
      std::string tie;
      if (!MostProbableLandmark(data_, grown, alpha_, &tie).ok()) tie.clear();
      if (!tie.empty()) grown.landmark_name = tie;
    }
    JointResult refit;
    if (!SolveJoint(data_, grown, &refit).ok()) return false;
    // And every other tie the grown model finds plausible and that fits about as well as the
    // current model (within ambiguity_delta_chi2): of those fits, the one that moves an effect
    // of the model most (a candidate whose signal the tie took can only show there).
    // (Only for a candidate that shares an effect's signal: its sigma grows by a fifth beside
    // it; another tie cannot move an effect through a candidate the effect does not feel.)
    bool shares = false;
    for (const Parameter effect : joint_->effects) {
      const double sigma = current_->estimate.StandardDeviation(effect);
      shares = shares || (sigma > 0.0 && refit.estimate.StandardDeviation(effect) >= 1.2 * sigma);
    }
    if (grown.landmark_mode == JointOptions::Landmark::kNamed && shares && TieContested()) {
      const auto largest_shift = [&](const JointResult& with) {
        double largest = 0.0;
        for (const Parameter effect : joint_->effects) {
          const double sigma = current_->estimate.StandardDeviation(effect);
          if (sigma > 0.0)
            largest = std::max(
                largest,
                std::abs(with.estimate.Value(effect) - current_->estimate.Value(effect)) / sigma);
        }
        return largest;
      };
      JointOptions every = grown;
      every.landmark_mode = JointOptions::Landmark::kAuto;
      JointResult all;
      if (SolveJoint(data_, every, &all).ok()) {
        double most = largest_shift(refit);
        for (const LandmarkHypothesis& hypothesis : all.hypotheses) {
          if (!hypothesis.solved || hypothesis.name == grown.landmark_name ||
              !(hypothesis.posterior >= kTiePosteriorReported))
            continue;
          JointOptions there = grown;
          there.landmark_name = hypothesis.name;
          JointResult other;
          if (!SolveJoint(data_, there, &other).ok() ||
              !(TotalChi2(other) - TotalChi2(*current_) < ambiguity_delta_chi2_))
            continue;
          const double shift = largest_shift(other);
          if (!(shift > most)) continue;
          most = shift;
          refit = other;
          grown.landmark_name = hypothesis.name;
        }
      }
    }
    fit->note = grown.landmark_mode == JointOptions::Landmark::kNamed &&
                        grown.landmark_name != joint_->landmark_name
                    ? "with the run tied to " + grown.landmark_name
                    : "";
    fit->gain = TotalChi2(*current_) - TotalChi2(refit);
    fit->current_estimates.clear();
    fit->current_stddevs.clear();
    fit->estimates.clear();
    fit->stddevs.clear();
    for (const Parameter effect : joint_->effects) {
      fit->current_estimates.push_back(current_->estimate.Value(effect));
      fit->current_stddevs.push_back(current_->estimate.StandardDeviation(effect));
      fit->estimates.push_back(refit.estimate.Value(effect));
      fit->stddevs.push_back(refit.estimate.StandardDeviation(effect));
    }
    fit->estimate = refit.estimate.Value(candidates_[candidate]);
    fit->stddev = refit.estimate.StandardDeviation(candidates_[candidate]);
    return true;
  }

  bool FitsAboutAsWell(const SwapFit& swap) const override {
    return swap.worse < ambiguity_delta_chi2_;
  }

  // Whether another landmark than the one the run is tied to is in question: the baseline's
  // decision had a second landmark with posterior kTiePosteriorReported or more, or the tie has
  // moved since (only then is a candidate beside the model fitted under the other ties too).
  bool TieContested() const {
    const LandmarkDecision& decision = result_->baseline_decision;
    if (data_.landmarks().size() < 2 || decision.best < 0) return false;
    if (decision.scores[decision.best].landmark.name != joint_->landmark_name) return true;
    for (size_t i = 0; i < decision.scores.size(); ++i) {
      if (static_cast<int>(i) != decision.best &&
          decision.scores[i].posterior >= kTiePosteriorReported)
        return true;
    }
    return false;
  }

  // It must explain, alone, what the effect explains (significantly), and about as well.
  bool LooksAlike(size_t, const SwapFit& swap, double effect_delta_chi2,
                  size_t alternatives) const override {
    const double explained = effect_delta_chi2 - swap.worse;
    return FitsAboutAsWell(swap) &&
           ChiSquareSurvival(explained, 1.0) <= family_alpha_ / alternatives;
  }

 private:
  // Re-decides the landmark tie for the model and refits when it moves.
  Status Retie(const std::string& because) {
    if (joint_->landmark_mode != JointOptions::Landmark::kNamed) return Status::Ok();
    std::string tie;
    ACCELCAL_RETURN_IF_ERROR(MostProbableLandmark(data_, *joint_, alpha_, &tie));
    if (!tie.empty() && tie != joint_->landmark_name) {
      result_->landmark_note +=
          StringPrintf("; %s, the run points at %s, not %s, and is tied to it", because.c_str(),
                       tie.c_str(), joint_->landmark_name.c_str());
      joint_->landmark_name = tie;
      result_->tied_landmark = tie;
      ACCELCAL_RETURN_IF_ERROR(SolveJoint(data_, *joint_, current_));
    }
    return Status::Ok();
  }

  const JointData& data_;
  const double alpha_;
  const double family_alpha_;
  const double ambiguity_delta_chi2_;
  const std::vector<Parameter> candidates_;
  JointOptions* joint_;
  JointResult* current_;
  DiscoveryResult* result_;
  std::vector<int> model_;
  std::vector<std::string> landmark_at_change_;
};

}  // namespace

Status Discover(const CalibrationTest& test, const VehicleRun& run, const RunConditions& conditions,
                const std::vector<Landmark>& landmarks, const DiscoveryOptions& options,
                DiscoveryResult* result) {
  *result = DiscoveryResult();
  // Every fit below starts from the baseline of its noise model; each is computed once.
  const JointData data(test, run, conditions, landmarks);
  // 1. The baseline and what it leaves.
  const JointOptions stated_noise = JointOptionsFor(conditions, options.gravity_mps2);
  const BaselineFit* baseline_fit = nullptr;
  ACCELCAL_RETURN_IF_ERROR(data.Baseline(stated_noise, &baseline_fit));
  result->baseline = *baseline_fit;
  const ParameterEstimate baseline = FromBaselineFit(result->baseline);
  std::array<std::vector<double>, 2> residuals;
  CalibrationResiduals(test, baseline.values, options.gravity_mps2, &residuals[0], &residuals[1]);
  const std::array<double, 2> stated = {conditions.noise_variance_x, conditions.noise_variance_y};
  for (int k = 0; k < 2; ++k) {
    AxisDiagnostics& axis = result->axes[k];
    axis.noise = TestNoiseLevel(residuals[k], stated[k]);
    axis.chi2 = (k == 0 ? result->baseline.chi2_x : result->baseline.chi2_y).chi2;
    axis.dof = (k == 0 ? result->baseline.chi2_x : result->baseline.chi2_y).dof;
    axis.whiteness = LjungBox(residuals[k], options.ljung_box_lags);
    axis.normality = JarqueBera(residuals[k]);
  }
  // 2. Noise first, as a model: per axis its outliers, tails, level and correlation, read
  // from local differences (estimation/statistics/noise_analysis.h). The procedure has three
  // families of tests, each with Holm inside its share of alpha (Bonferroni across them, so the
  // whole discovery keeps its family-wise error rate at alpha): the noise (alpha/4), the
  // effects (alpha/2) and the checks of what the final model leaves (alpha/4).
  const double noise_alpha = 0.25 * options.alpha;
  const double family_alpha = 0.5 * options.alpha;
  const double checks_alpha = 0.25 * options.alpha;
  NoiseAnalysisOptions analysis_options;
  analysis_options.outlier_alpha = noise_alpha / 8.0;
  std::array<NoiseAnalysis, 2> first;
  for (int k = 0; k < 2; ++k)
    first[k] = AnalyzeNoise(residuals[k], stated[k], {}, false, analysis_options);
  auto family = [](const std::array<NoiseAnalysis, 2>& a) {
    return std::vector<double>{a[0].outlier_p, a[0].kurtosis_p, a[0].level_p, a[0].correlation_p,
                               a[1].outlier_p, a[1].kurtosis_p, a[1].level_p, a[1].correlation_p};
  };
  std::vector<bool> flags = HolmRejections(family(first), noise_alpha);
  std::array<bool, 2> heavy{}, outlying{};
  std::array<NoiseAnalysis, 2>& analysis = result->noise_analysis;
  for (int k = 0; k < 2; ++k) {
    heavy[k] = flags[4 * k + 1];
    outlying[k] = flags[4 * k] && !heavy[k] && !first[k].outlier_candidates.empty();
    // Outliers can hide one another (two in one neighbourhood, or a scale they inflate): look
    // again without those found, until no more are.
    for (int pass = 0; outlying[k] && pass < 5; ++pass) {
      const NoiseAnalysis again = AnalyzeNoise(residuals[k], stated[k], first[k].outlier_candidates,
                                               false, analysis_options);
      if (again.outlier_candidates.empty()) break;
      std::vector<int>& found = first[k].outlier_candidates;
      found.insert(found.end(), again.outlier_candidates.begin(), again.outlier_candidates.end());
      std::sort(found.begin(), found.end());
    }
    // Level and correlation again without the outliers, or with the sample's own moments
    // under heavy tails (a variance test with Gaussian error bars would be wrong there).
    analysis[k] = (heavy[k] || outlying[k])
                      ? AnalyzeNoise(residuals[k], stated[k],
                                     outlying[k] ? first[k].outlier_candidates : std::vector<int>(),
                                     heavy[k], analysis_options)
                      : first[k];
    analysis[k].outlier_p = first[k].outlier_p;
    analysis[k].largest_score = first[k].largest_score;
    analysis[k].outlier_candidates = first[k].outlier_candidates;
    analysis[k].excess_kurtosis = first[k].excess_kurtosis;
    analysis[k].kurtosis_z = first[k].kurtosis_z;
    analysis[k].kurtosis_p = first[k].kurtosis_p;
  }
  flags = HolmRejections(family(analysis), noise_alpha);
  const char* axis_name[2] = {"x", "y"};
  for (int k = 0; k < 2; ++k) {
    AxisDiagnostics& axis = result->axes[k];
    AxisNoise& noise = result->noise_model[k];
    const NoiseAnalysis& a = analysis[k];
    axis.noise_flagged = flags[4 * k + 2];
    const bool correlated = flags[4 * k + 3];
    noise.variance = stated[k] * (axis.noise_flagged ? a.variance_ratio : 1.0);
    noise.correlation = correlated ? a.correlation : 0.0;
    if (outlying[k]) noise.outliers = a.outlier_candidates;
    result->noise_variance_used[k] = noise.variance;
    axis.bins = BinByTheta(test.theta_rad, residuals[k], options.theta_bins, noise.variance);
    if (axis.noise_flagged) {
      DiscoveredEffect effect;
      effect.effect = k == 0 ? Parameter::kNoiseVarianceX : Parameter::kNoiseVarianceY;
      effect.estimate = a.variance_ratio;
      effect.stddev = a.variance_ratio_stddev;
      effect.p_value = a.level_p;
      effect.delta_chi2 = a.level_z * a.level_z;
      result->effects.push_back(effect);
    }
    if (correlated) {
      NoiseFinding finding;
      finding.kind = NoiseFinding::Kind::kCorrelation;
      finding.axis = k;
      finding.estimate = a.correlation;
      finding.stddev = a.correlation_stddev;
      finding.p_value = a.correlation_p;
      finding.description = StringPrintf(
          "%s: time-correlated noise, AR(1) with lag-1 correlation %.3g +- %.2g (p = %.2g); "
          "marginal variance %.3g of the stated",
          axis_name[k], a.correlation, a.correlation_stddev, a.correlation_p, a.variance_ratio);
      result->noise_findings.push_back(finding);
    }
    if (outlying[k]) {
      NoiseFinding finding;
      finding.kind = NoiseFinding::Kind::kOutliers;
      finding.axis = k;
      finding.estimate = static_cast<double>(noise.outliers.size());
      finding.p_value = a.outlier_p;
      finding.samples = noise.outliers;
      std::string listed;
      for (size_t i = 0; i < noise.outliers.size() && i < 8; ++i)
        listed += (i ? ", " : "") + std::to_string(noise.outliers[i]);
      if (noise.outliers.size() > 8) listed += ", ...";
      finding.description = StringPrintf(
          "%s: outliers, %zu samples set aside (largest %.1f robust sigma, p = %.2g; samples %s)",
          axis_name[k], noise.outliers.size(), a.largest_score, a.outlier_p, listed.c_str());
      result->noise_findings.push_back(finding);
    }
    if (heavy[k]) {
      NoiseFinding finding;
      finding.kind = NoiseFinding::Kind::kHeavyTails;
      finding.axis = k;
      finding.estimate = a.excess_kurtosis;
      finding.p_value = a.kurtosis_p;
      finding.description = StringPrintf(
          "%s: heavy-tailed noise, excess kurtosis %.3g (p = %.2g; %zu samples beyond %.1f "
          "robust sigma); the level's spread is the sample's own",
          axis_name[k], a.excess_kurtosis, a.kurtosis_p, a.outlier_candidates.size(),
          TwoSidedNormalQuantile(analysis_options.outlier_alpha / std::max(1, a.samples)));
      result->noise_findings.push_back(finding);
    }
  }
  // The endpoint against the landmarks, with the noise the data show. With outliers or
  // correlated noise the baseline is refitted under that noise model first: least squares
  // over every sample would carry the outliers into the bias, and the run to a wrong
  // landmark, and would understate its covariance under correlation.
  ParameterEstimate noise_scaled = baseline;
  const bool structured =
      !result->noise_model[0].outliers.empty() || !result->noise_model[1].outliers.empty() ||
      result->noise_model[0].correlation != 0.0 || result->noise_model[1].correlation != 0.0;
  if (structured) {
    JointOptions refit;
    refit.gravity_mps2 = options.gravity_mps2;
    refit.noise_variance_x = result->noise_variance_used[0];
    refit.noise_variance_y = result->noise_variance_used[1];
    refit.noise_correlation = {result->noise_model[0].correlation,
                               result->noise_model[1].correlation};
    refit.outliers = {result->noise_model[0].outliers, result->noise_model[1].outliers};
    refit.num_threads = options.num_threads;
    JointResult fit;
    ACCELCAL_RETURN_IF_ERROR(SolveJoint(data, refit, &fit));
    noise_scaled = fit.estimate;
  }
  noise_scaled.values[Parameter::kNoiseVarianceX] = result->noise_variance_used[0] / stated[0];
  noise_scaled.values[Parameter::kNoiseVarianceY] = result->noise_variance_used[1] / stated[1];
  noise_scaled.noise_correlation = {result->noise_model[0].correlation,
                                    result->noise_model[1].correlation};
  TrajectoryOptions trajectory;
  trajectory.path_stride = run.size();
  ACCELCAL_RETURN_IF_ERROR(
      DeadReckon(run, conditions, noise_scaled, trajectory, &result->baseline_trajectory));
  result->baseline_decision =
      DecideLandmark(result->baseline_trajectory.endpoint, result->baseline_trajectory.covariance,
                     landmarks, options.alpha);
  const LandmarkDecision& decision = result->baseline_decision;
  if (decision.best >= 0) {
    result->tied_landmark = decision.scores[decision.best].landmark.name;
    std::vector<double> posteriors;
    for (const LandmarkScore& score : decision.scores) posteriors.push_back(score.posterior);
    std::sort(posteriors.rbegin(), posteriors.rend());
    const bool ambiguous = posteriors.size() > 1 && posteriors[1] > options.alpha;
    result->landmark_note =
        decision.consistent
            ? StringPrintf("the baseline endpoint is consistent with %s (p = %.3g)",
                           result->tied_landmark.c_str(), decision.scores[decision.best].p_value)
            : StringPrintf(
                  "no landmark is consistent with the baseline endpoint (the closest, %s, has p = "
                  "%.2g): "
                  "a run bias shift is tested against it",
                  result->tied_landmark.c_str(), decision.scores[decision.best].p_value);
    if (ambiguous) {
      result->landmark_note +=
          StringPrintf("; the choice is ambiguous (second posterior %.3g)", posteriors[1]);
    }
  }

  // 3. Forward selection over the catalogue.
  JointOptions joint;
  joint.gravity_mps2 = options.gravity_mps2;
  joint.noise_variance_x = result->noise_variance_used[0];
  joint.noise_variance_y = result->noise_variance_used[1];
  joint.noise_correlation = noise_scaled.noise_correlation;
  joint.outliers = {result->noise_model[0].outliers, result->noise_model[1].outliers};
  joint.num_threads = options.num_threads;
  joint.landmark_mode = result->tied_landmark.empty() ? JointOptions::Landmark::kNone
                                                      : JointOptions::Landmark::kNamed;
  joint.landmark_name = result->tied_landmark;
  ACCELCAL_RETURN_IF_ERROR(SolveJoint(data, joint, &result->baseline_joint));
  JointResult current = result->baseline_joint;
  const double log_n = std::log(2.0 * test.size() + (result->tied_landmark.empty() ? 0 : 2));
  std::vector<Parameter> catalogue;
  for (const ParameterInfo& info : ParameterCatalogue()) {
    if (info.baseline || IsNoiseRatio(info.parameter)) continue;
    if (ActsOnlyInRun(info.parameter) && result->tied_landmark.empty()) continue;
    catalogue.push_back(info.parameter);
  }
  TiltTableGeometry geometry(data, options.alpha, family_alpha, options.ambiguity_delta_chi2,
                             catalogue, &joint, &current, result);
  // The one procedure's forward selection and backward elimination
  // (estimation/discovery/selection.h), replayed into this result's records.
  SelectionOptions selection;
  selection.alpha = family_alpha;
  selection.max_effects = options.max_effects;
  SelectionRecord record;
  std::vector<int> candidates(catalogue.size());
  for (size_t c = 0; c < candidates.size(); ++c) candidates[c] = static_cast<int>(c);
  ACCELCAL_RETURN_IF_ERROR(SelectEffects(&geometry, candidates, selection, &record));
  for (const SelectionRecord::Score& score : record.scores) {
    result->candidates.push_back({score.step, catalogue[score.candidate], score.delta_chi2,
                                  score.p_value, score.significant});
  }
  for (size_t i = 0; i < record.history.size(); ++i) {
    const SelectionRecord::Change& change = record.history[i];
    const Parameter effect = catalogue[change.candidate];
    result->history.push_back(
        {change.added ? SelectionEvent::Kind::kAdded : SelectionEvent::Kind::kDropped, effect,
         change.delta_chi2, change.p_value, geometry.landmark_at_change()[i]});
    if (change.added) {
      DiscoveredEffect found;
      found.effect = effect;
      found.selection_step = change.step;
      found.selection_p_value = change.p_value;
      found.selection_delta_chi2 = change.delta_chi2;
      result->effects.push_back(found);
    } else {
      result->effects.erase(
          std::find_if(result->effects.begin(), result->effects.end(),
                       [&](const DiscoveredEffect& e) { return e.effect == effect; }));
    }
  }
  // Drops the least significant effect of the model that Holm (alpha/2 over the model's
  // effects) does not find needed once the shapes outside the catalogue are allowed for.
  auto drop_weakest_for_shape = [&](const std::vector<double>& delta_chi2,
                                    const std::vector<double>& p_values, bool* dropped) -> Status {
    const int weakest = WeakestNotNeeded(p_values, family_alpha);
    *dropped = weakest >= 0;
    if (!*dropped) return Status::Ok();
    const Parameter gone = joint.effects[weakest];
    result->history.push_back({SelectionEvent::Kind::kDroppedForShape, gone, delta_chi2[weakest],
                               p_values[weakest], joint.landmark_name});
    result->effects.erase(
        std::find_if(result->effects.begin(), result->effects.end(),
                     [&](const DiscoveredEffect& effect) { return effect.effect == gone; }));
    return geometry.Drop(weakest);
  };
  auto necessity = [&](std::vector<double>* delta_chi2) -> Status {
    std::vector<CandidateTest> tests;
    ACCELCAL_RETURN_IF_ERROR(geometry.TestEffects(&tests));
    delta_chi2->clear();
    for (const CandidateTest& test : tests) delta_chi2->push_back(test.delta_chi2);
    return Status::Ok();
  };
  // 5. What the final model leaves (estimation/tilt_table/residual_checks.h), Holm within the
  // checks' share of alpha. A shape they find is outside the catalogue; an effect named only
  // because it resembles that shape is not needed once the shape is allowed for, so each
  // effect is tested again with the shapes as nuisance columns and the weakest one not
  // needed is dropped, until every effect left is needed.
  ResidualChecksOptions check_options;
  check_options.max_harmonic = options.max_harmonic;
  check_options.ljung_box_lags = options.ljung_box_lags;
  check_options.gravity_mps2 = options.gravity_mps2;
  const AxisNoise final_noise[2] = {joint.Noise(0), joint.Noise(1)};
  Eigen::MatrixXd jacobian;
  Eigen::VectorXd linear_residual;
  auto run_checks = [&]() -> Status {
    ACCELCAL_RETURN_IF_ERROR(LinearizeJoint(data, joint, current, &jacobian, &linear_residual));
    result->checks =
        CheckResiduals(test, jacobian, linear_residual,
                       EvaluateFit(test, current.estimate.values, options.gravity_mps2),
                       current.landmark.empty() ? 0 : 2, final_noise, check_options);
    FlagByHolm(checks_alpha, &result->checks);
    return Status::Ok();
  };
  // A step can be mimicked by several catalogue effects at once (a run bias shift, a drift
  // and an angle offset together), after which the final model's checks see nothing. When
  // a single step on the baseline (its size and place: two parameters) explains at least as
  // much as all the named effects do, by BIC, the step is the simpler account: it joins the
  // nuisance shapes. A true effect explains more than any step resembling it, so it stays.
  std::vector<std::pair<int, std::vector<double>>> simpler_steps;
  if (!joint.effects.empty()) {
    JointOptions base = joint;
    base.effects.clear();
    Eigen::MatrixXd base_jacobian;
    Eigen::VectorXd base_residual;
    ACCELCAL_RETURN_IF_ERROR(
        LinearizeJoint(data, base, result->baseline_joint, &base_jacobian, &base_residual));
    const double effects_gain = TotalChi2(result->baseline_joint) - TotalChi2(current);
    const double effects_bic = effects_gain - joint.effects.size() * log_n;
    for (const ResidualCheck& check : CheckResiduals(
             test, base_jacobian, base_residual,
             EvaluateFit(test, result->baseline_joint.estimate.values, options.gravity_mps2),
             result->baseline_joint.landmark.empty() ? 0 : 2, final_noise, check_options)) {
      if (check.name.find("step") == std::string::npos) continue;
      if (check.statistic - 2.0 * log_n >= effects_bic && check.p_value <= checks_alpha)
        simpler_steps.push_back({check.axis, check.shape[0]});
    }
  }
  ACCELCAL_RETURN_IF_ERROR(run_checks());
  while (!joint.effects.empty()) {
    std::vector<Eigen::VectorXd> nuisance;
    for (const ResidualCheck& check : result->checks) {
      if (!check.flagged) continue;
      for (const std::vector<double>& shape : check.shape)
        nuisance.push_back(WhitenedShapeColumn(shape, check.axis, final_noise[check.axis],
                                               static_cast<int>(jacobian.rows())));
    }
    for (const auto& [axis, shape] : simpler_steps) {
      nuisance.push_back(
          WhitenedShapeColumn(shape, axis, final_noise[axis], static_cast<int>(jacobian.rows())));
    }
    if (nuisance.empty()) break;
    // Columns of the current free parameters, by name.
    const std::vector<Parameter>& free = current.estimate.free;
    std::vector<double> p_values;
    std::vector<double> delta_chi2;
    for (const Parameter effect : joint.effects) {
      Eigen::MatrixXd others(jacobian.rows(),
                             static_cast<Eigen::Index>(free.size() - 1 + nuisance.size()));
      Eigen::MatrixXd own(jacobian.rows(), 1);
      int column = 0;
      for (size_t c = 0; c < free.size(); ++c) {
        if (free[c] == effect) {
          own.col(0) = jacobian.col(c);
        } else {
          others.col(column++) = jacobian.col(c);
        }
      }
      for (const Eigen::VectorXd& shape : nuisance) others.col(column++) = shape;
      delta_chi2.push_back(ExtraChiSquare(others, own, linear_residual));
      p_values.push_back(ChiSquareSurvival(delta_chi2.back(), 1.0));
    }
    bool dropped = false;
    ACCELCAL_RETURN_IF_ERROR(drop_weakest_for_shape(delta_chi2, p_values, &dropped));
    if (!dropped) break;
    ACCELCAL_RETURN_IF_ERROR(run_checks());
  }
  // What remains, in words: the flagged shapes strongest first, each kept only if it still
  // stands once the shapes before it are allowed for (a 2-theta harmonic also shows as a
  // curved trend and a step; those are parts of the same shape, not more of them). Then the
  // flagged checks with no shape: a slow shape also makes the residuals correlated, so the
  // correlation checks are run again on what the model and the shapes kept leave, and stand
  // only if they still see it (the endpoint's check stands as it is). Each line is the check's
  // description and its advice (WhatRemains).
  {
    std::vector<int> flagged;
    for (size_t c = 0; c < result->checks.size(); ++c) {
      if (result->checks[c].flagged) flagged.push_back(static_cast<int>(c));
    }
    std::stable_sort(flagged.begin(), flagged.end(), [&](int a, int b) {
      return result->checks[a].p_value < result->checks[b].p_value;
    });
    const double stand_alpha = checks_alpha / std::max<size_t>(1, result->checks.size());
    const int rows = static_cast<int>(jacobian.rows());
    std::vector<Eigen::VectorXd> kept;
    std::string parts;
    const auto keep = [&](int index) {
      result->remaining.push_back(WhatRemains(result->checks[index]));
      result->remaining_checks.push_back(index);
    };
    for (const int index : flagged) {
      const ResidualCheck& check = result->checks[index];
      if (check.shape.empty()) continue;
      Eigen::MatrixXd extra(rows, check.shape.size());
      for (size_t c = 0; c < check.shape.size(); ++c)
        extra.col(c) =
            WhitenedShapeColumn(check.shape[c], check.axis, final_noise[check.axis], rows);
      Eigen::MatrixXd model(rows, jacobian.cols() + static_cast<int>(kept.size()));
      model.leftCols(jacobian.cols()) = jacobian;
      for (size_t c = 0; c < kept.size(); ++c) model.col(jacobian.cols() + c) = kept[c];
      int rank = 0;
      const double delta = ExtraChiSquare(model, extra, linear_residual, &rank);
      if (!kept.empty() && !(rank > 0 && ChiSquareSurvival(delta, rank) <= stand_alpha)) {
        parts += (parts.empty() ? "" : ", ") + check.name;
        continue;
      }
      keep(index);
      for (int c = 0; c < extra.cols(); ++c) kept.push_back(extra.col(c));
    }
    // What the model and the shapes kept leave.
    Eigen::VectorXd left = linear_residual;
    if (!kept.empty()) {
      Eigen::MatrixXd model(rows, jacobian.cols() + static_cast<int>(kept.size()));
      model.leftCols(jacobian.cols()) = jacobian;
      for (size_t c = 0; c < kept.size(); ++c) model.col(jacobian.cols() + c) = kept[c];
      left -= model * model.completeOrthogonalDecomposition().solve(linear_residual);
    }
    const int endpoint_rows = current.landmark.empty() ? 0 : 2;
    for (const int index : flagged) {
      const ResidualCheck& check = result->checks[index];
      if (!check.shape.empty()) continue;
      bool stands = kept.empty() || check.axis < 0;
      if (!stands) {
        const std::vector<double> white = AxisWhiteResiduals(
            left, check.axis, test.size(), endpoint_rows, final_noise[check.axis]);
        for (const ResidualCheck& again :
             CorrelationChecks(white, check.axis, check_options.ljung_box_lags)) {
          stands |= again.name == check.name && again.p_value <= stand_alpha;
        }
      }
      if (stands) {
        keep(index);
      } else {
        parts += (parts.empty() ? "" : ", ") + check.name;
      }
    }
    if (!parts.empty()) {
      result->remaining.push_back("also flagged, but parts of the shapes above: " + parts);
    }
  }

  // Every figure of the final model's effects against the final model itself.
  {
    std::vector<double> delta_chi2;
    ACCELCAL_RETURN_IF_ERROR(necessity(&delta_chi2));
    for (size_t e = 0; e < joint.effects.size(); ++e) {
      for (DiscoveredEffect& effect : result->effects) {
        if (effect.effect != joint.effects[e]) continue;
        effect.delta_chi2 = delta_chi2[e];
        effect.p_value = ChiSquareSurvival(delta_chi2[e], 1.0);
        effect.bic_change = -effect.delta_chi2 + log_n;
      }
    }
  }
  // Heavy tails: the final model again with a Huber loss (1.345 sigma: 95% of least squares'
  // efficiency under Gaussian noise, far better under heavy tails), and the sandwich
  // covariance, right whatever the tails.
  if (std::any_of(result->noise_findings.begin(), result->noise_findings.end(),
                  [](const NoiseFinding& finding) {
                    return finding.kind == NoiseFinding::Kind::kHeavyTails;
                  })) {
    JointOptions robust = joint;
    robust.loss = RobustLoss::kHuber;
    robust.loss_scale = 1.345;
    robust.compress_calibration = false;
    JointResult fit;
    ACCELCAL_RETURN_IF_ERROR(SolveJoint(data, robust, &fit));
    ACCELCAL_RETURN_IF_ERROR(HuberSandwichCovariance(data, robust, &fit));
    current = fit;
    result->robust_fit = true;
  }
  result->extended = current;
  for (DiscoveredEffect& effect : result->effects) {
    if (IsNoiseRatio(effect.effect)) continue;
    effect.estimate = current.estimate.Value(effect.effect);
    effect.stddev = current.estimate.StandardDeviation(effect.effect);
  }

  // 4. The gain.
  ACCELCAL_RETURN_IF_ERROR(
      DeadReckon(run, conditions, current.estimate, trajectory, &result->extended_trajectory));
  result->extended_decision =
      DecideLandmark(result->extended_trajectory.endpoint, result->extended_trajectory.covariance,
                     landmarks, options.alpha);
  std::array<std::vector<double>, 2> extended_residuals;
  CalibrationResiduals(test, current.estimate.values, options.gravity_mps2, &extended_residuals[0],
                       &extended_residuals[1]);
  for (int k = 0; k < 2; ++k) {
    std::vector<double> difference(test.size());
    for (int i = 0; i < test.size(); ++i)
      difference[i] = residuals[k][i] - extended_residuals[k][i];
    const std::vector<ResidualBin> signature =
        BinByTheta(test.theta_rad, difference, options.theta_bins, result->noise_variance_used[k]);
    for (const ResidualBin& bin : signature) result->axes[k].bin_signature.push_back(bin.mean);
  }
  if (options.cross_validation_folds > 1) {
    const int calibration_rows = 2 * test.size();
    Eigen::MatrixXd jacobian;
    Eigen::VectorXd residual;
    ACCELCAL_RETURN_IF_ERROR(LinearizeJoint(data, joint, current, &jacobian, &residual));
    // Only the parameters the tilt test sees are refitted per fold.
    std::vector<int> columns;
    for (size_t c = 0; c < current.estimate.free.size(); ++c) {
      if (!ActsOnlyInRun(current.estimate.free[c])) columns.push_back(static_cast<int>(c));
    }
    Eigen::MatrixXd calibration(calibration_rows, columns.size());
    for (size_t c = 0; c < columns.size(); ++c)
      calibration.col(c) = jacobian.col(columns[c]).head(calibration_rows);
    result->cross_validation.folds = options.cross_validation_folds;
    result->cross_validation.extended =
        CrossValidate(calibration, residual.head(calibration_rows), calibration_rows,
                      options.cross_validation_folds);
    const double rows =
        joint.Noise(0).InlierCount(test.size()) + joint.Noise(1).InlierCount(test.size());
    CrossValidation& cv = result->cross_validation;
    cv.null_mean = 1.0 + columns.size() / (rows * (1.0 - 1.0 / options.cross_validation_folds));
    cv.null_stddev = std::sqrt(2.0 / rows);
    // Held-out outlier rows are zero and count in the mean; compare like with like.
    cv.extended *= calibration_rows / rows;
    cv.z = (cv.extended - cv.null_mean) / cv.null_stddev;
    // The baseline's own linearisation at its own solution (no effect, same noise).
    JointOptions base = joint;
    base.effects.clear();
    ACCELCAL_RETURN_IF_ERROR(
        LinearizeJoint(data, base, result->baseline_joint, &jacobian, &residual));
    result->cross_validation.baseline =
        CrossValidate(jacobian.topLeftCorner(calibration_rows, 4), residual.head(calibration_rows),
                      calibration_rows, options.cross_validation_folds);
  }

  // 6. Effects another candidate would replace at about the same fit.
  {
    std::vector<double> necessary;
    ACCELCAL_RETURN_IF_ERROR(necessity(&necessary));
    // The catalogue's candidates in each effect's place (the one procedure's look-alikes).
    std::vector<int> all(geometry.candidates().size());
    for (size_t c = 0; c < all.size(); ++c) all[c] = static_cast<int>(c);
    const std::vector<SwappedModel> swaps = FitSwaps(&geometry, all);
    const std::vector<LookAlike> look_alikes = FindLookAlikes(geometry, all, swaps, necessary);
    // And those that move it, beside it or in another effect's place: correlated in this
    // design, not separable from the effect's estimate.
    const std::vector<Partner> partners =
        FindPartners(&geometry, all, swaps, necessary,
                     PartnerOptions{options.partner_alpha, options.partner_shift_sigma,
                                    options.partner_reach_sigma});
    const size_t candidate_count = all.size() - joint.effects.size();
    for (size_t e = 0; e < joint.effects.size(); ++e) {
      Ambiguity ambiguity;
      ambiguity.effect = joint.effects[e];
      ambiguity.effect_estimate = current.estimate.Value(ambiguity.effect);
      ambiguity.effect_stddev = current.estimate.StandardDeviation(ambiguity.effect);
      for (const LookAlike& look_alike : look_alikes) {
        if (look_alike.effect != e) continue;
        Ambiguity::Alternative instead;
        instead.effect = geometry.candidates()[look_alike.alternative];
        instead.estimate = look_alike.fit.estimate;
        instead.stddev = look_alike.fit.stddev;
        instead.delta_chi2 = look_alike.fit.worse;
        ambiguity.alternatives.push_back(instead);
      }
      for (const Partner& partner : partners) {
        if (partner.effect != e) continue;
        Ambiguity::Alternative with;
        with.effect = geometry.candidates()[partner.partner];
        with.estimate = partner.fit.estimate;
        with.stddev = partner.fit.stddev;
        with.delta_chi2 = partner.delta_chi2;
        with.beside = partner.replaces < 0;
        if (partner.replaces >= 0) with.replaces = joint.effects[partner.replaces];
        with.effect_estimate_with = partner.fit.estimates[e];
        with.effect_stddev_with = partner.fit.stddevs[e];
        with.p_value = partner.p_value;
        with.reach_sigma = partner.reach_sigma;
        with.note = partner.fit.note;
        ambiguity.alternatives.push_back(with);
      }
      // Shapes outside the catalogue in its place: a theta harmonic on either axis that fits
      // about as well, alone explains what the effect explains, and is not merely a
      // generalisation of it (over half a circle, a 3-theta harmonic on x and
      // scale_nonlinearity_x are nearly the same shape; over a full circle, a 2-theta
      // harmonic contains scale_nonlinearity_x and is not an alternative to it). Linearised
      // at the final solution: without the effect, the residual is r + J_e (neutral - value).
      const std::vector<Parameter>& free = current.estimate.free;
      const auto column = std::find(free.begin(), free.end(), ambiguity.effect);
      if (column != free.end() && jacobian.cols() == static_cast<Eigen::Index>(free.size())) {
        const int e_col = static_cast<int>(column - free.begin());
        const Eigen::VectorXd j_e = jacobian.col(e_col);
        Eigen::MatrixXd others(jacobian.rows(), jacobian.cols() - 1);
        for (int c = 0, o = 0; c < jacobian.cols(); ++c) {
          if (c != e_col) others.col(o++) = jacobian.col(c);
        }
        const Eigen::VectorXd without =
            linear_residual +
            j_e * (Info(ambiguity.effect).neutral - current.estimate.Value(ambiguity.effect));
        // The effect's signature in the test (a harmonic can only stand for that part).
        Eigen::VectorXd test_signature = j_e;
        test_signature.tail(jacobian.rows() - 2 * test.size()).setZero();
        Eigen::MatrixXd others_in_test = others;
        others_in_test.bottomRows(jacobian.rows() - 2 * test.size()).setZero();
        const double own = ExtraChiSquare(others_in_test, test_signature, test_signature);
        for (int axis = 0; axis < 2; ++axis) {
          for (int k = 1; k <= options.max_harmonic; ++k) {
            std::vector<double> cosine(test.size()), sine(test.size());
            for (int i = 0; i < test.size(); ++i) {
              cosine[i] = std::cos(k * test.theta_rad[i]);
              sine[i] = std::sin(k * test.theta_rad[i]);
            }
            Eigen::MatrixXd shape(jacobian.rows(), 2);
            shape.col(0) = WhitenedShapeColumn(cosine, axis, final_noise[axis],
                                               static_cast<int>(jacobian.rows()));
            shape.col(1) = WhitenedShapeColumn(sine, axis, final_noise[axis],
                                               static_cast<int>(jacobian.rows()));
            Eigen::MatrixXd swapped(jacobian.rows(), others.cols() + 2);
            swapped << others, shape;
            // The harmonic must not contain the effect's own signature.
            // (in the test's rows: the run's rows of the others would hide it there)
            Eigen::MatrixXd swapped_in_test = swapped;
            swapped_in_test.bottomRows(jacobian.rows() - 2 * test.size()).setZero();
            if (!(own > 0.0) ||
                ExtraChiSquare(swapped_in_test, test_signature, test_signature) < 0.01 * own)
              continue;
            int rank = 0;
            const double gain = ExtraChiSquare(others, shape, without, &rank);
            if (rank < 1) continue;
            const double worse = necessary[e] - gain;  // its chi-square over the final model's
            if (!(worse < options.ambiguity_delta_chi2)) continue;
            if (!(ChiSquareSurvival(gain, rank) <= family_alpha / candidate_count)) continue;
            // Its amplitude in that model.
            const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> fit(swapped);
            const Eigen::VectorXd beta = fit.solve(without);
            Ambiguity::Alternative alternative;
            alternative.shape = StringPrintf("%s: %d-theta harmonic", axis == 0 ? "x" : "y", k);
            alternative.estimate = std::hypot(beta[beta.size() - 2], beta[beta.size() - 1]);
            // Its spread: the harmonic's two coefficients' (whitened rows: unit noise).
            const Eigen::MatrixXd information = swapped.transpose() * swapped;
            const Eigen::MatrixXd covariance =
                information.completeOrthogonalDecomposition().pseudoInverse();
            const Eigen::Index last = covariance.rows() - 1;
            alternative.stddev = std::sqrt(
                0.5 * std::max(0.0, covariance(last, last) + covariance(last - 1, last - 1)));
            alternative.delta_chi2 = worse;
            ambiguity.alternatives.push_back(alternative);
          }
        }
      }
      if (ambiguity.alternatives.empty()) continue;
      // What would separate them: the run, where one acts in it and another does not; else
      // more samples (the chi-square between the two models grows with them), unless this
      // design cannot separate them at any size.
      std::string separation;
      for (const Ambiguity::Alternative& alternative : ambiguity.alternatives) {
        const bool run_effect = EffectOf(ambiguity.effect).acts_in != ActsIn::kCalibrationTest;
        if (alternative.beside && !alternative.note.empty()) {
          // Beside it under another tie: the landmark the run reached decides.
          const std::string line = StringPrintf(
              "%s beside %s, %s, fits %s (delta chi2 %+.1f) and moves %s by %.1f of "
              "its sigma as fitted: which landmark the run reached decides; the run's end "
              "position measured, or a landmark the endpoint's uncertainty cannot confuse with "
              "another, would separate them",
              Info(alternative.effect).name, Info(ambiguity.effect).name, alternative.note.c_str(),
              alternative.delta_chi2 < 0.0 ? "better" : "about as well", alternative.delta_chi2,
              Info(ambiguity.effect).name,
              std::abs(alternative.effect_estimate_with - ambiguity.effect_estimate) /
                  ambiguity.effect_stddev);
          separation += (separation.empty() ? "" : "; ") + line;
          continue;
        }
        if (alternative.beside) {
          // The partner gains too little to be named, enough to move the effect: more of the
          // same data names it or rules it out (its chi-square grows with them).
          const std::string line = StringPrintf(
              "%s and %s are correlated in this design: %s alone (as fitted) or both, with %s "
              "gaining delta chi2 %.1f (p = %.2g) and moving %s by %.1f of its sigma as fitted "
              "(one of its own sigmas further, by %.1f); about %.3g times "
              "more samples of this design would name %s or rule it out, or a design where "
              "their signatures differ",
              Info(ambiguity.effect).name, Info(alternative.effect).name,
              Info(ambiguity.effect).name, Info(alternative.effect).name, -alternative.delta_chi2,
              alternative.p_value, Info(ambiguity.effect).name,
              std::abs(alternative.effect_estimate_with - ambiguity.effect_estimate) /
                  ambiguity.effect_stddev,
              alternative.reach_sigma,
              std::max(1.0, 13.0 / std::max(-alternative.delta_chi2, 1e-3)),
              Info(alternative.effect).name);
          separation += (separation.empty() ? "" : "; ") + line;
          continue;
        }
        if (alternative.replaces) {
          // Two look-alikes of this design; which one is there moves the effect.
          const char* replaced = Info(*alternative.replaces).name;
          const std::string line = StringPrintf(
              "%s and %s look alike in this design, and %s depends on which is there: %s in "
              "%s's place fits within delta chi2 %.1f (explaining what it explained at p = %.2g) "
              "and moves %s by %.1f of its sigma as fitted; about %.3g times more samples of "
              "this design would tell them apart, or a design where their signatures differ",
              replaced, Info(alternative.effect).name, Info(ambiguity.effect).name,
              Info(alternative.effect).name, replaced, alternative.delta_chi2, alternative.p_value,
              Info(ambiguity.effect).name,
              std::abs(alternative.effect_estimate_with - ambiguity.effect_estimate) /
                  ambiguity.effect_stddev,
              std::max(1.0, 9.2 / std::max(std::abs(alternative.delta_chi2), 1e-3)));
          separation += (separation.empty() ? "" : "; ") + line;
          continue;
        }
        if (!alternative.shape.empty()) {
          // A shape acts only in the test (it was seen there); the run separates them when
          // the effect acts in it.
          const std::string line = StringPrintf(
              "%s%s, a shape outside the catalogue, fits as well as %s: this design cannot say "
              "which; a test over a full circle of theta or more positions, where their "
              "signatures differ, would",
              run_effect ? "the run, if tied to a well-known landmark, may separate them; " : "",
              alternative.shape.c_str(), Info(ambiguity.effect).name);
          separation += (separation.empty() ? "" : "; ") + line;
          continue;
        }
        const bool run_alternative =
            EffectOf(alternative.effect).acts_in != ActsIn::kCalibrationTest;
        std::string line;
        if (run_effect != run_alternative) {
          line = StringPrintf(
              "the run separates %s from %s (only %s acts in it): tie the run "
              "to a landmark whose position is known well",
              Info(ambiguity.effect).name, Info(alternative.effect).name,
              Info(run_effect ? ambiguity.effect : alternative.effect).name);
        }
        const double gap = std::abs(alternative.delta_chi2);
        const double factor = 9.2 / std::max(gap, 1e-3);
        const std::string more =
            factor > 1e4 ? StringPrintf(
                               "this test design cannot separate %s from %s at any "
                               "size: another range of theta or other positions",
                               Info(ambiguity.effect).name, Info(alternative.effect).name)
                         : StringPrintf(
                               "about %.3g times more samples of this design (their "
                               "chi-squares differ by %.2g; a likelihood ratio of 100 "
                               "needs 9.2), or a design where their signatures differ",
                               std::max(1.0, factor), gap);
        line += (line.empty() ? "" : "; or ") + more;
        separation += (separation.empty() ? "" : "; ") + line;
      }
      ambiguity.separation = separation;
      ambiguity.text = AmbiguityText(ambiguity);
      result->ambiguities.push_back(std::move(ambiguity));
    }
  }
  // 7. What the effects owe to the landmark tie: the final model with the run tied to each
  // landmark (TieDependence in discovery.h).
  TieDependence& dependence = result->tie_dependence;
  std::vector<Parameter> run_effects;
  for (const Parameter effect : joint.effects) {
    if (ActsOnlyInRun(effect)) run_effects.push_back(effect);
  }
  if (!joint.effects.empty() && landmarks.size() > 1 &&
      joint.landmark_mode == JointOptions::Landmark::kNamed) {
    JointOptions every = joint;
    every.landmark_mode = JointOptions::Landmark::kAuto;
    JointResult all;
    ACCELCAL_RETURN_IF_ERROR(SolveJoint(data, every, &all));
    JointOptions without = joint;
    without.effects.erase(std::remove_if(without.effects.begin(), without.effects.end(),
                                         [](Parameter e) { return ActsOnlyInRun(e); }),
                          without.effects.end());
    // Every plausible tie, with every effect's estimate under it (joint.effects order).
    std::vector<TieAlternative> ties;
    for (const LandmarkHypothesis& hypothesis : all.hypotheses) {
      TieAlternative tie;
      tie.landmark = hypothesis.name;
      tie.posterior = hypothesis.posterior;
      tie.tied = hypothesis.name == joint.landmark_name;
      if (!hypothesis.solved || (!tie.tied && !(tie.posterior >= kTiePosteriorReported))) continue;
      JointOptions with_tie = joint, without_tie = without;
      with_tie.landmark_name = without_tie.landmark_name = hypothesis.name;
      JointResult with_fit, without_fit;
      // A tie the solver refuses (an effect not separable there) is no alternative to report.
      if (!SolveJoint(data, with_tie, &with_fit).ok()) continue;
      if (!run_effects.empty()) {
        if (!SolveJoint(data, without_tie, &without_fit).ok()) continue;
        tie.delta_chi2 = std::max(0.0, TotalChi2(without_fit) - TotalChi2(with_fit));
        tie.p_value = ChiSquareSurvival(tie.delta_chi2, run_effects.size());
        tie.needed = tie.p_value <= family_alpha;
      }
      for (const Parameter effect : joint.effects) {
        tie.estimates.push_back(with_fit.estimate.Value(effect));
        tie.stddevs.push_back(with_fit.estimate.StandardDeviation(effect));
      }
      ties.push_back(tie);
    }
    std::stable_sort(ties.begin(), ties.end(),
                     [](const TieAlternative& a, const TieAlternative& b) {
                       return a.tied != b.tied ? a.tied : a.posterior > b.posterior;
                     });
    // The effects the tie moves: every run effect, and any other whose estimate under a
    // plausible tie is kTieShiftSigma or more of its sigma from the tied one's (a calibration
    // effect that pays for a tie through the bias and scale the run shares).
    std::vector<size_t> moved;
    if (!ties.empty() && ties.front().tied) {
      const TieAlternative& tied = ties.front();
      for (size_t e = 0; e < joint.effects.size(); ++e) {
        bool depends = ActsOnlyInRun(joint.effects[e]);
        for (const TieAlternative& tie : ties) {
          depends =
              depends || (tied.stddevs[e] > 0.0 && std::abs(tie.estimates[e] - tied.estimates[e]) >=
                                                       kTieShiftSigma * tied.stddevs[e]);
        }
        if (depends) moved.push_back(e);
      }
    }
    if (!moved.empty() && ties.size() > 1) {
      for (const size_t e : moved) dependence.effects.push_back(joint.effects[e]);
      for (TieAlternative& tie : ties) {
        std::vector<double> estimates, stddevs;
        for (const size_t e : moved) {
          estimates.push_back(tie.estimates[e]);
          stddevs.push_back(tie.stddevs[e]);
        }
        tie.estimates = estimates;
        tie.stddevs = stddevs;
      }
      dependence.ties = ties;
    }
  }

  for (int k = 0; k < 2; ++k) result->final_residuals[k] = extended_residuals[k];
  result->noise_model = {joint.Noise(0), joint.Noise(1)};

  // The verdict, first line of every report.
  std::string missing;
  for (const DiscoveredEffect& effect : result->effects) {
    const ParameterInfo& info = Info(effect.effect);
    missing += (missing.empty() ? "" : "; ") + std::string(info.name) + " = " +
               Fixed(effect.estimate, effect.stddev, info.unit) +
               StringPrintf(" (delta chi2 = %.1f, p = %.2g)", effect.delta_chi2, effect.p_value);
  }
  // The effects under every plausible landmark tie, when more than one is.
  std::string ties;
  bool only_run_effects = true;
  for (const Parameter effect : dependence.effects)
    only_run_effects = only_run_effects && ActsOnlyInRun(effect);
  if (dependence.Depends()) {
    for (const TieAlternative& tie : dependence.ties) {
      std::string effects;
      for (size_t e = 0; e < dependence.effects.size(); ++e) {
        const ParameterInfo& info = Info(dependence.effects[e]);
        if (ActsOnlyInRun(dependence.effects[e]) && !tie.needed) continue;
        effects += (effects.empty() ? "" : ", ") + std::string(info.name) + " = " +
                   Fixed(tie.estimates[e], tie.stddevs[e], info.unit);
      }
      if (dependence.HasRunEffects()) {
        effects = tie.needed
                      ? effects + StringPrintf(" (delta chi2 = %.1f)", tie.delta_chi2)
                      : effects + (effects.empty() ? "" : "; ") +
                            StringPrintf("no run effect needed (delta chi2 = %.2g, p = %.2g)",
                                         tie.delta_chi2, tie.p_value);
      }
      ties += StringPrintf("%s%s %s (posterior %.2g): %s", ties.empty() ? "" : "; ",
                           tie.tied ? "tied to" : "if it ended at", tie.landmark.c_str(),
                           tie.posterior, effects.c_str());
    }
  }
  if (dependence.Depends() && !dependence.Undecided()) {
    missing += std::string(only_run_effects ? "; the run effects" : "; the estimates") +
               " depend on the landmark the run reached: " + ties;
  }
  for (const NoiseFinding& finding : result->noise_findings)
    missing += (missing.empty() ? "" : "; ") + finding.description;
  std::string left;
  for (const std::string& line : result->remaining) left += (left.empty() ? "" : "; ") + line;
  result->verdict_code = DecideVerdict(
      !left.empty(), !result->ambiguities.empty() || dependence.Undecided(), !missing.empty());
  switch (result->verdict_code) {
    case Verdict::kUnexplained:
      result->verdict = (missing.empty() ? std::string("unexplained: structure remains")
                                         : "missing: " + missing + ", but structure remains") +
                        " that no effect of the catalogue explains: " + left;
      break;
    case Verdict::kCannotTellApart: {
      std::string sets;
      for (const Ambiguity& ambiguity : result->ambiguities) {
        sets += (sets.empty() ? "" : "; ") + ambiguity.text +
                "; what would separate them: " + ambiguity.separation;
      }
      if (dependence.Undecided()) {
        sets +=
            (sets.empty() ? "" : "; ") +
            std::string("whether the run has a run effect depends on the landmark it reached: ") +
            ties +
            "; what would separate them: the run's end position measured, or a landmark "
            "whose position the endpoint's uncertainty cannot confuse with another";
      }
      result->verdict = "cannot tell apart: " + sets + " (the model as fitted: " + missing + ")";
      break;
    }
    case Verdict::kMissing:
      result->verdict = "missing: " + missing + " (and the extended model explains the data)";
      break;
    case Verdict::kExplained:
      result->verdict =
          "the baseline explains the data: no effect of the catalogue is significant at alpha = " +
          StringPrintf("%g", options.alpha) + ", and nothing remains that the checks can see";
      break;
  }
  return Status::Ok();
}

}  // namespace accelcal
