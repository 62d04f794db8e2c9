#include "estimation/triad/triad_pose_noise.h"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>

#include "common/format.h"
#include "common/statistics.h"
#include "estimation/statistics/chi_square.h"
#include "estimation/triad/noise_floor_detector.h"
#include "estimation/triad/triad_contrasts.h"
#include "estimation/triad/triad_ml_calibration.h"
#include "residuals/triad_pose_residual.h"

namespace accelcal {

Status TriadPoseNoiseFromLog(const TriadLog& log, const std::vector<StaticInterval>& intervals,
                             const std::vector<TriadPoseMean>& poses, TriadPoseNoise* noise) {
  *noise = TriadPoseNoise();
  if (intervals.size() != poses.size() || poses.empty())
    return Status::Error("the coloured noise model needs one interval per pose");
  if (log.size() < 2) return Status::Error("the log is too short for an Allan variance");
  const double sample_period_s =
      (log.timestamp_s.back() - log.timestamp_s.front()) / static_cast<double>(log.size() - 1);
  std::vector<double> durations;
  for (const TriadPoseMean& pose : poses) durations.push_back(pose.duration_s);
  const double median_duration_s = UpperMedian(durations);
  const std::array<double, 3> white = PooledWithinPoseVariance(poses);

  double smallest_p = 1.0;
  for (int k = 0; k < 3; ++k) {
    std::vector<std::vector<double>> segments;
    for (const StaticInterval& interval : intervals) {
      std::vector<double> samples;
      for (int i = interval.start; i <= interval.end; ++i) samples.push_back(log.output[i][k]);
      segments.push_back(std::move(samples));
    }
    AllanOptions options;
    AllanCurve curve;
    ACCELCAL_RETURN_IF_ERROR(ComputeAllanVariance(segments, sample_period_s, options, &curve)
                                 .WithContext(StringPrintf("axis %c's poses", "xyz"[k])));
    // The test point before the fit: the fit fills each point's edf by the noise it finds.
    int test = -1;
    for (size_t i = 0; i < curve.points.size(); ++i)
      if (curve.points[i].tau_s <= 0.5 * median_duration_s) test = static_cast<int>(i);
    if (test < 0) {
      return Status::Error(StringPrintf(
          "the poses (median %.3g s) are too short for the Allan variance of their noise",
          median_duration_s));
    }
    const AllanPoint point = curve.points[test];
    // The segments the point averages, and only those: a short pose does not enter a long
    // tau's point, and counting it would make the test overconfident.
    const double edf = AllanCurveDof(AllanNoiseKind::kWhite, curve, point.cluster_samples);
    const double expected = white[k] / static_cast<double>(point.cluster_samples);
    noise->test_tau_s = point.tau_s;
    noise->avar_ratio[k] = point.avar / expected;
    noise->white_p_value[k] = ChiSquareSurvival(edf * noise->avar_ratio[k], edf);
    smallest_p = std::min(smallest_p, noise->white_p_value[k]);

    AllanNoiseFit fit;
    ACCELCAL_RETURN_IF_ERROR(FitAllanNoise(options, &curve, &fit)
                                 .WithContext(StringPrintf("axis %c's poses", "xyz"[k])));
    noise->terms[k] = FittedNoiseTerms(fit);
  }
  TriadNoiseCandidate& candidate = noise->candidate;
  candidate.white_p_value = std::min(1.0, 3.0 * smallest_p);
  for (const TriadPoseMean& pose : poses) {
    std::array<double, 3> variance;
    for (int k = 0; k < 3; ++k) {
      variance[k] =
          AllanPoseMeanVariance(noise->terms[k], std::max(pose.duration_s, sample_period_s));
      // Never below what white noise of the pose's own samples gives.
      variance[k] = std::max(variance[k], white[k] / pose.sample_count);
    }
    candidate.pose_mean_variance.push_back(variance);
  }
  candidate.correlation = TriadPoseCorrelationFromTerms(noise->terms, poses, white);
  candidate.description = StringPrintf(
      "Allan variance of the poses' samples (terms N, B, K fitted per axis; a pose mean of T s "
      "has variance sigma^2(T)); at tau = %.3g s it is (%.3g, %.3g, %.3g) times white noise's",
      noise->test_tau_s, noise->avar_ratio[0], noise->avar_ratio[1], noise->avar_ratio[2]);
  const TriadPoseCorrelation& correlation = candidate.correlation;
  if (!correlation.empty()) {
    candidate.description += StringPrintf(
        "; the pose means are judged correlated across poses by the bias instability (B = "
        "%.3g, %.3g, %.3g) as flicker noise, %zu Gauss-Markov processes at %.3g to %.3g s",
        noise->terms[0].bias_instability, noise->terms[1].bias_instability,
        noise->terms[2].bias_instability, correlation.correlation_s.size(),
        correlation.correlation_s.front(), correlation.correlation_s.back());
  }
  return Status::Ok();
}

namespace {

constexpr double kFlickerAllanFloor = 0.441;  // 2 ln 2 / pi: flicker's Allan variance over B^2
constexpr double kBankSpacing = 4.0;

// One Gauss-Markov process's Allan variance at tau over its variance (correlation time T).
double MarkovAllanVariance(double tau_s, double correlation_s) {
  const double x = tau_s / correlation_s;
  if (x < 1e-4) return 2.0 * x / 3.0 - 0.5 * x * x;
  return (2.0 * x - 3.0 + 4.0 * std::exp(-x) - std::exp(-2.0 * x)) / (x * x);
}

}  // namespace

TriadPoseCorrelation TriadPoseCorrelationFromTerms(const std::array<AllanNoiseTerms, 3>& terms,
                                                   const std::vector<TriadPoseMean>& poses,
                                                   const std::array<double, 3>& sample_variance) {
  TriadPoseCorrelation model;
  bool any = false;
  for (const AllanNoiseTerms& axis : terms) any = any || axis.bias_instability > 0.0;
  if (!any || poses.size() < 2) return model;
  std::vector<double> durations;
  double first_s = poses.front().time_s;
  double last_s = first_s;
  for (const TriadPoseMean& pose : poses) {
    durations.push_back(pose.duration_s);
    first_s = std::min(first_s, pose.time_s);
    last_s = std::max(last_s, pose.time_s);
  }
  const double shortest_s = std::max(0.25 * UpperMedian(durations), 1e-3);
  const double span_s = std::max(last_s - first_s, shortest_s);
  for (double t = shortest_s;; t *= kBankSpacing) {
    model.correlation_s.push_back(t);
    if (t >= span_s && model.correlation_s.size() >= 2) break;
  }
  const double reference_s = std::sqrt(model.correlation_s.front() * model.correlation_s.back());
  double unit_allan = 0.0;
  for (const double t : model.correlation_s) unit_allan += MarkovAllanVariance(reference_s, t);
  for (int k = 0; k < 3; ++k) {
    const double b = terms[k].bias_instability;
    model.process_variance[k] = kFlickerAllanFloor * b * b / unit_allan;
    model.white_density[k] = terms[k].white_density;
    model.random_walk[k] = terms[k].random_walk;
    model.sample_variance[k] = sample_variance[k];
  }
  return model;
}

Status TriadCorrelatedChi2(const std::vector<TriadPoseMean>& poses, const TriadMlResult& fit,
                           const TriadPoseCorrelation& correlation,
                           const std::array<double, 3>& added_variance, double gravity_mps2,
                           double* chi2, std::vector<double>* innovations) {
  if (correlation.empty()) return Status::Error("no correlation model of the pose means");
  TriadContrasts contrasts;
  ACCELCAL_RETURN_IF_ERROR(TriadPoseContrasts(poses, fit, gravity_mps2, &contrasts));
  const TriadContrastWhitener whitener(poses, fit, contrasts, correlation, added_variance);
  Eigen::MatrixXd whitened;
  ACCELCAL_RETURN_IF_ERROR(whitener.Whiten(contrasts.rows, &whitened));
  // One Gauss-Newton step of the estimated parameters: the whitened contrasts' least squares.
  const Eigen::VectorXd z = whitened.col(0);
  const Eigen::MatrixXd x = whitened.rightCols(whitened.cols() - 1);
  const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> solver(x);
  const Eigen::VectorXd step = solver.solve(-z);
  const Eigen::VectorXd left = z + x * step;
  *chi2 = left.squaredNorm();
  if (innovations != nullptr) innovations->assign(left.data(), left.data() + left.size());
  return Status::Ok();
}

double QuantisationBiasVariance(double noise_variance, double step) {
  if (!(step > 0.0)) return 0.0;
  const double ratio = std::max(noise_variance, 0.0) / (step * step);
  if (ratio == 0.0) return step * step / 12.0;
  // Terms fall as exp(-4 pi^2 j^2 ratio) / j^2: one or two for sigma >= q / 3, up to 1e5 (a
  // tail below 1e-5 of the sum) as sigma -> 0.
  double sum = 0.0;
  for (int j = 1; j <= 100000; ++j) {
    const double term = std::exp(-4.0 * M_PI * M_PI * j * j * ratio) / (double(j) * j);
    sum += term;
    if (term < 1e-17 * sum) break;
  }
  return step * step / (2.0 * M_PI * M_PI) * sum;
}

double UnroundedNoiseVariance(double rounded_variance, double step) {
  if (!(step > 0.0) || !(rounded_variance > 0.0)) return std::max(rounded_variance, 0.0);
  // s^2(sigma^2) = sigma^2 + q^2/12 - B rises from 0 at sigma = 0 and exceeds sigma^2, so the
  // root lies in [0, s^2].
  double low = 0.0;
  double high = rounded_variance;
  for (int i = 0; i < 60; ++i) {
    const double middle = 0.5 * (low + high);
    const double rounded = middle + step * step / 12.0 - QuantisationBiasVariance(middle, step);
    (rounded < rounded_variance ? low : high) = middle;
  }
  return 0.5 * (low + high);
}

namespace {

// The quantisation term of the header for the poses of `log`.
void QuantisationOfPoseMeans(const TriadLog& log, const std::vector<TriadPoseMean>& poses,
                             TriadPoseNoise* noise) {
  if (poses.empty()) return;
  const std::array<double, 3> white = PooledWithinPoseVariance(poses);
  std::vector<double> counts;
  for (const TriadPoseMean& pose : poses) counts.push_back(pose.sample_count);
  const double median_count = UpperMedian(counts);
  noise->output_step = OutputSteps(log);
  for (int k = 0; k < 3; ++k) {
    const double step = noise->output_step[k];
    const double unrounded = UnroundedNoiseVariance(white[k], step);
    noise->unrounded_stddev[k] = std::sqrt(unrounded);
    noise->quantisation_variance[k] = QuantisationBiasVariance(unrounded, step);
    if (noise->quantisation_variance[k] >= 0.01 * white[k] / median_count)
      noise->quantisation_material = true;
  }
}

}  // namespace

Status ParseTriadNoiseChoice(const std::string& text, TriadNoiseChoice* choice) {
  if (text == "auto") {
    *choice = TriadNoiseChoice::kAuto;
  } else if (text == "white") {
    *choice = TriadNoiseChoice::kWhite;
  } else if (text == "allan") {
    *choice = TriadNoiseChoice::kAllan;
  } else {
    return Status::Error("'" + text + "' is not a noise model; use auto, white or allan");
  }
  return Status::Ok();
}

Status SelectTriadPoseNoise(const TriadLog& log, const std::vector<StaticInterval>& intervals,
                            const std::vector<TriadPoseMean>& poses, TriadNoiseChoice choice,
                            double alpha, TriadPoseNoise* noise, bool* use_allan) {
  const Status allan = TriadPoseNoiseFromLog(log, intervals, poses, noise);
  *use_allan = false;
  if (!allan.ok()) *noise = TriadPoseNoise();
  QuantisationOfPoseMeans(log, poses, noise);
  // Where rounding dominates (sigma below about q/2), the samples take two or three values and
  // their variance changes from pose to pose with where the mean falls on the grid: the white
  // test's chi-square degrees of freedom do not hold (it rejected white noise in 11 of 60
  // simulated sessions at sigma = 0.1 q, tests/triad_pose_noise_test.cc), so no Allan model is
  // offered unless asked for.
  if (allan.ok() && noise->quantisation_material && choice != TriadNoiseChoice::kAllan)
    noise->candidate = TriadNoiseCandidate();
  if (!allan.ok()) {
    return choice == TriadNoiseChoice::kAllan ? allan.WithContext("--noise=allan") : Status::Ok();
  }
  *use_allan = choice == TriadNoiseChoice::kAllan ||
               (choice == TriadNoiseChoice::kAuto && noise->candidate.white_p_value < alpha / 4.0);
  return Status::Ok();
}

}  // namespace accelcal
