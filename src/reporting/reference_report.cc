#include "reporting/reference_report.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>

#include "common/format.h"
#include "estimation/tilt_table/baseline_parameters.h"
#include "models/tilt_table.h"

namespace accelcal {
namespace {

// ---------------------------------------------------------------------------------------
// What the reference report printed (../shared/reference/seed-report.md). These are the
// document's figures, not results: they never change with the data.

// Table 1 (section 3): b_x, s_x, b_y, s_y, in kBaselineParameters' order (m/s^2, 1).
constexpr std::array<PrintedFigure, 4> kTable1 = {
    {{7.667e-2, 4}, {-3.014e-2, 4}, {-1.751e-2, 4}, {1.004e-2, 4}}};
// Equation (4) (section 3): the diagonal of the estimates' covariance, same order.
constexpr std::array<PrintedFigure, 4> kVariances = {
    {{1.245e-5, 4}, {2.603e-7, 4}, {3.200e-5, 4}, {6.663e-7, 4}}};
// Equation (4): its two nonzero off-diagonal entries, cov(b_x, s_x) and cov(b_y, s_y).
constexpr PrintedFigure kCovarianceBiasScaleX = {-8.915e-19, 4};
constexpr PrintedFigure kCovarianceBiasScaleY = {3.265e-10, 4};
// Section 5: the smallest coordinate gaps between the landmarks (m), and the sample counts
// its per-axis bound gives.
constexpr PrintedFigure kMinGapX = {1.620, 4};
constexpr PrintedFigure kMinGapY = {13.26, 4};
constexpr int kReportNx = 2222;
constexpr int kReportNy = 185466;
// Section 4: the corrected run reaches none of the landmarks, though its path passes A.
constexpr char kReportPassedLandmark[] = "A";
// Section 6: uncorrected, the run would have been taken to end at B.
constexpr char kReportRawLandmark[] = "B";
// ---------------------------------------------------------------------------------------

constexpr const char* kNames[4] = {"b_x", "s_x", "b_y", "s_y"};
constexpr const char* kUnits[4] = {" (m/s^2)", "", " (m/s^2)", ""};

// One unit of the printed figure's last digit.
double LastDigitUnit(const PrintedFigure& printed) {
  const double magnitude = std::floor(std::log10(std::abs(printed.value)));
  return std::pow(10.0, magnitude - printed.significant_digits + 1);
}

// `value` to `digits` significant digits: fixed from 1 up, else "7.667e-2" (no exponent padding).
std::string Digits(double value, int digits) {
  if (value == 0.0) return "0";
  const int magnitude = static_cast<int>(std::floor(std::log10(std::abs(value))));
  if (magnitude >= 0 && magnitude < 6)
    return StringPrintf("%.*f", std::max(0, digits - 1 - magnitude), value);
  std::string text = StringPrintf("%.*e", digits - 1, value);
  const size_t e = text.find('e');
  const bool negative = text[e + 1] == '-';
  size_t first = e + 2;
  while (first + 1 < text.size() && text[first] == '0') ++first;
  return text.substr(0, e) + (negative ? "e-" : "e") + text.substr(first);
}

std::string Printed(const PrintedFigure& printed) {
  return Digits(printed.value, printed.significant_digits);
}
// This run's value with one digit more than the report printed.
std::string Computed(const PrintedFigure& printed, double value) {
  return Digits(value, printed.significant_digits + 1);
}

std::string AgreementText(const PrintedFigure& printed, double computed) {
  switch (CompareToPrinted(printed, computed)) {
    case Agreement::kAgrees:
      return "agrees to the printed digits";
    case Agreement::kLastDigit:
      return "off by one in the last printed digit (" + Printed(printed) + " where " +
             Digits(computed, printed.significant_digits) + " is right): a rounding slip";
    case Agreement::kDiffers:
      break;
  }
  return StringPrintf("differs by %.1f units of the last printed digit",
                      std::abs(UnitsOfLastDigit(printed, computed)));
}

// A row comparing a printed number; `why` is added to the verdict when the two do not agree.
// `rounding_units` is how far (in units of the last printed digit) the figure moves with the
// order its sums are taken in; a difference within it is agreement.
void AddNumericRow(const std::string& figure, const PrintedFigure& printed, double computed,
                   const std::string& why, ReferenceComparison* comparison,
                   double rounding_units = 0.0, const std::string& rounding_why = "") {
  Agreement agreement = CompareToPrinted(printed, computed);
  std::string verdict = AgreementText(printed, computed);
  if (agreement != Agreement::kAgrees &&
      std::abs(UnitsOfLastDigit(printed, computed)) <= 0.5 + rounding_units) {
    agreement = Agreement::kAgrees;
    verdict = "agrees within the rounding of its sums: " + rounding_why;
  } else if (agreement != Agreement::kAgrees && !why.empty()) {
    verdict += "; " + why;
  }
  comparison->rows.push_back(
      {figure, Printed(printed), Computed(printed, computed), verdict, agreement});
  ++comparison->numeric_rows;
  comparison->agreeing_rows += agreement == Agreement::kAgrees ? 1 : 0;
}

// The sum of `values` in double, forward (as a simple loop or Octave's sum may take it), and
// compensated (Neumaier), which is exact to a few units of the last bit.
struct TwoSums {
  double forward = 0.0;
  double compensated = 0.0;
  // The relative difference: how much the order of summation moves the sum.
  double Spread() const {
    return compensated == 0.0 ? 0.0 : std::abs(forward - compensated) / std::abs(compensated);
  }
};
TwoSums SumBothWays(const std::vector<double>& values) {
  TwoSums sums;
  double correction = 0.0;
  for (double value : values) {
    sums.forward += value;
    const double t = sums.compensated + value;
    correction += std::abs(sums.compensated) >= std::abs(value) ? (sums.compensated - t) + value
                                                                : (value - t) + sums.compensated;
    sums.compensated = t;
  }
  sums.compensated += correction;
  return sums;
}

// The fit the report's equation (2) describes, m = a + b + s m: (m - f) regressed on [1, m],
// per axis; returns (b_x, s_x, b_y, s_y).
Eigen::Vector4d EquationTwoFit(const CalibrationTest& test, double gravity_mps2) {
  Eigen::Vector4d fit = Eigen::Vector4d::Zero();
  for (int axis = 0; axis < 2; ++axis) {
    Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
    Eigen::Vector2d right = Eigen::Vector2d::Zero();
    for (int i = 0; i < test.size(); ++i) {
      double force_x = 0.0;
      double force_y = 0.0;
      TiltTableSpecificForce(test.theta_rad[i], gravity_mps2, &force_x, &force_y);
      const double measured = axis == 0 ? test.measured_x[i] : test.measured_y[i];
      const Eigen::Vector2d row(1.0, measured);
      normal += row * row.transpose();
      right += row * (measured - (axis == 0 ? force_x : force_y));
    }
    fit.segment<2>(2 * axis) = normal.ldlt().solve(right);
  }
  return fit;
}

// The smallest |difference| of one coordinate over every pair of landmarks, and the pair.
double MinimumGap(const std::vector<Landmark>& landmarks, int axis, std::string* pair) {
  double gap = HUGE_VAL;
  for (size_t i = 0; i < landmarks.size(); ++i) {
    for (size_t j = i + 1; j < landmarks.size(); ++j) {
      const double d =
          axis == 0 ? landmarks[i].x_m - landmarks[j].x_m : landmarks[i].y_m - landmarks[j].y_m;
      if (std::abs(d) < gap) {
        gap = std::abs(d);
        *pair = landmarks[i].name + "-" + landmarks[j].name;
      }
    }
  }
  return gap;
}

const LandmarkScore* ScoreOf(const LandmarkDecision& decision, const std::string& name) {
  for (const LandmarkScore& score : decision.scores)
    if (score.landmark.name == name) return &score;
  return nullptr;
}

// Table 1 reproduced within one unit of every last printed digit; `how` says by how much, or
// which estimates differ.
bool RecogniseCourseData(const BaselineFit& fit, std::string* how) {
  bool all = true;
  double largest_units = 0.0;
  double largest_sigmas = 0.0;
  double chance = 1.0;
  std::string differing;
  for (int i = 0; i < 4; ++i) {
    const Parameter parameter = kBaselineParameters[i];
    const double value = fit.Value(parameter);
    const double sigma = fit.StandardDeviation(parameter);
    const double units = std::abs(UnitsOfLastDigit(kTable1[i], value));
    largest_units = std::max(largest_units, units);
    largest_sigmas = std::max(largest_sigmas, std::abs(value - kTable1[i].value) / sigma);
    // P(|estimate - printed| <= 1.5 units) for an estimate ~ N(printed, sigma^2).
    chance *= std::min(1.0, 3.0 * LastDigitUnit(kTable1[i]) / (sigma * std::sqrt(2.0 * M_PI)));
    if (CompareToPrinted(kTable1[i], value) == Agreement::kDiffers) {
      all = false;
      differing += StringPrintf("%s%s = %s where the report has %s, %.1f sigma apart",
                                differing.empty() ? "" : "; ", kNames[i],
                                Computed(kTable1[i], value).c_str(), Printed(kTable1[i]).c_str(),
                                std::abs(value - kTable1[i].value) / sigma);
    }
  }
  if (all) {
    *how = StringPrintf(
        // clang-format off
        "These are the course data the reference report analysed (2018, seed-report.md): its Table 1 is reproduced to within one unit of each estimate's last printed digit (at most %.1f units, %.3f sigma). The data are recognised by what they give, not by a file name or a checksum, so the same data in another layout are recognised too; a simulation of the same setting whose truth is Table 1 lands this close by chance with probability about %.0e. Each figure the report printed is set beside this run's, and each verdict is computed from the two.",
        // clang-format on
        largest_units, largest_sigmas, chance);
  } else {
    *how =
        // clang-format off
        "These are not the course data the reference report analysed (2018, seed-report.md): its Table 1 is not reproduced: " + differing + ". Its figures describe those data, so they are not set beside this run's.";
    // clang-format on
  }
  return all;
}

}  // namespace

double UnitsOfLastDigit(const PrintedFigure& printed, double computed) {
  return (computed - printed.value) / LastDigitUnit(printed);
}

Agreement CompareToPrinted(const PrintedFigure& printed, double computed) {
  // Half a unit (with room for the binary representation of both numbers) rounds to the
  // printed figure; one and a half is the neighbouring last digit.
  constexpr double kSlack = 1e-9;
  const double units = std::abs(UnitsOfLastDigit(printed, computed));
  if (units <= 0.5 + kSlack) return Agreement::kAgrees;
  if (units <= 1.5 + kSlack) return Agreement::kLastDigit;
  return Agreement::kDiffers;
}

ReferenceComparison CompareWithReferenceReport(const AnalyzeReport& r) {
  ReferenceComparison c;
  const BaselineFit& fit = r.linear.closed_form;
  c.course_data = RecogniseCourseData(fit, &c.recognition);
  if (!c.course_data) return c;

  // Table 1.
  double sum_sin = 0.0;
  double sum_x = 0.0;
  for (int i = 0; i < r.test.size(); ++i) {
    sum_sin += std::sin(r.test.theta_rad[i]);
    sum_x += r.test.measured_x[i];
  }
  const int n = r.test.size();
  for (int i = 0; i < 4; ++i) {
    std::string why;
    if (i == 0 && std::abs(sum_sin) < 1e-6) {
      why = StringPrintf(
          "b_x is the mean of the x outputs here (%s), since the sum of sin theta_i is %.1e",
          Computed(kTable1[0], sum_x / n).c_str(), sum_sin);
    }
    AddNumericRow(std::string(kNames[i]) + kUnits[i], kTable1[i], fit.Value(kBaselineParameters[i]),
                  why, &c);
  }

  // Equation (4). The covariance depends only on the stated noise and the angles, never on
  // the outputs: a printed entry these data do not give was miscopied.
  const std::array<double, 2> noise = {r.linear.noise_variance_x, r.linear.noise_variance_y};
  for (int i = 0; i < 4; ++i) {
    const Parameter parameter = kBaselineParameters[i];
    const bool bias = i % 2 == 0;
    std::string why =
        "the covariance depends only on the stated noise and the angles, not on the outputs";
    if (bias) {
      why += StringPrintf(": sigma^2/N = %g/%d = %.5e here", noise[i / 2], n, noise[i / 2] / n);
    }
    why += "; a transcription error";
    AddNumericRow(std::string("var ") + kNames[i] + (bias ? " ((m/s^2)^2)" : ""), kVariances[i],
                  fit.Covariance(parameter, parameter), why, &c);
  }
  // cov(b_k, s_k) is proportional to the sum of f_k over the test, sin theta_i for x: a
  // cancellation of N terms (-7e-9 on the course data) whose trailing digits depend on the
  // order of summation, so the printed digits are compared within that spread.
  {
    std::vector<double> sines(n);
    std::vector<double> cosines(n);
    for (int i = 0; i < n; ++i) {
      sines[i] = std::sin(r.test.theta_rad[i]);
      cosines[i] = std::cos(r.test.theta_rad[i]);
    }
    const std::array<TwoSums, 2> sums = {SumBothWays(sines), SumBothWays(cosines)};
    const std::array<PrintedFigure, 2> printed = {kCovarianceBiasScaleX, kCovarianceBiasScaleY};
    for (int axis = 0; axis < 2; ++axis) {
      const double value = fit.Covariance(BiasOf(axis), ScaleOf(axis));
      const double spread_units =
          sums[axis].Spread() * std::abs(value) / LastDigitUnit(printed[axis]);
      AddNumericRow(
          StringPrintf("cov(b_%c, s_%c) (m/s^2)", "xy"[axis], "xy"[axis]), printed[axis], value, "",
          &c, spread_units,
          StringPrintf(
              // clang-format off
              "it is proportional to the sum of %s theta_i, %.4e summed exactly and %.4e summed forward, which moves it by %.1f units of the last printed digit",
              // clang-format on
              axis == 0 ? "sin" : "cos", sums[axis].compensated, sums[axis].forward, spread_units));
    }
  }

  // The model of equation (2) against the spec's, which Table 1 follows.
  {
    const Eigen::Vector4d two = EquationTwoFit(r.test, r.linear.gravity_mps2);
    double spec_sigmas = 0.0;
    double two_sigmas = 0.0;
    for (int i = 0; i < 4; ++i) {
      const double sigma = fit.StandardDeviation(kBaselineParameters[i]);
      spec_sigmas = std::max(spec_sigmas, std::abs(fit.parameters[i] - kTable1[i].value) / sigma);
      two_sigmas = std::max(two_sigmas, std::abs(two[i] - kTable1[i].value) / sigma);
    }
    c.rows.push_back(
        {"the model (section 1)", "eq. (2): a_measured = a_real + b + s a_measured",
         std::string("the spec's: a_measured = (1 + s) a_real + b; eq. (2) would give ") +
             "b_x = " + Digits(two[0], 3) + ", s_x = " + Digits(two[1], 3) +
             ", b_y = " + Digits(two[2], 3) + ", s_y = " + Digits(two[3], 3),
         spec_sigmas < two_sigmas
             ? StringPrintf(
                   // clang-format off
                   "Table 1 follows the spec's model (within %.3f sigma), not eq. (2) (up to %.1f sigma away): eq. (2) is a slip in the text, not in the numbers",
                   // clang-format on
                   spec_sigmas, two_sigmas)
             : StringPrintf(
                   "Table 1 is nearer eq. (2)'s fit (%.1f sigma) than the spec's (%.1f sigma)",
                   two_sigmas, spec_sigmas)});
  }

  // Section 4: the bound, and the landmark.
  {
    std::string report_bound;
    std::string correct;
    std::string verdict;
    for (int axis = 0; axis < 2; ++axis) {
      const AxisErrorBudget& b = r.trajectory.budget[axis];
      report_bound +=
          StringPrintf("%s%.2f m (%s)", axis == 0 ? "" : ", ", b.report_bound_m, b.axis);
      correct += StringPrintf("%s%.2f m (%s)", axis == 0 ? "" : ", ", b.three_sigma_m, b.axis);
      const double noise_factor = b.noise.three_sigma_m / b.noise.report_m;
      const double scale_factor = b.scale.report_m / b.scale.three_sigma_m;
      verdict += StringPrintf(
          // clang-format off
          "%s%s: the bound is %s; its noise term 3 sigma_eta = %.2f m is %.1f times %s than the double integral's %.2f m, its scale term %.1f times %s than the correct %.2f m",
          // clang-format on
          axis == 0 ? "" : "; ", b.axis,
          b.report_bound_m < b.three_sigma_m ? "too small" : "large enough", b.noise.report_m,
          noise_factor >= 1.0 ? noise_factor : 1.0 / noise_factor,
          noise_factor >= 1.0 ? "smaller" : "larger", b.noise.three_sigma_m,
          scale_factor >= 1.0 ? scale_factor : 1.0 / scale_factor,
          scale_factor >= 1.0 ? "larger" : "smaller", b.scale.three_sigma_m);
    }
    c.rows.push_back({"endpoint error bound (section 4)",
                      "t_f^2/2 (3 sigma_b + 3 |a_max| sigma_s) + 3 sigma_eta: " + report_bound +
                          " on these data",
                      "3 sigma of the endpoint (parameters and the run's own noise): " + correct,
                      verdict});
  }
  const LandmarkDecision& decision = r.trajectory.decision;
  {
    std::string ours;
    std::string verdict;
    if (decision.reached.empty()) {
      ours = "no landmark is consistent with the endpoint";
      verdict = "agrees";
    } else {
      const LandmarkScore& best = decision.scores[decision.best];
      ours = StringPrintf("reached %s, %.2f sigma away (p = %.3g)", decision.reached.c_str(),
                          std::sqrt(best.mahalanobis2), best.p_value);
      verdict = StringPrintf(
          // clang-format off
          "differs: with the run's own noise counted, the endpoint is consistent with %s; the report's uncertainty region was too small (its noise term)",
          // clang-format on
          decision.reached.c_str());
    }
    c.rows.push_back({"landmark reached (section 4)", "none", ours, verdict});
  }
  // Where the corrected path comes nearest the landmark the report says it passes, in sigma of
  // the path's total covariance there.
  if (const LandmarkScore* passed = ScoreOf(decision, kReportPassedLandmark)) {
    const Eigen::Vector2d at(passed->landmark.x_m, passed->landmark.y_m);
    double nearest = HUGE_VAL;
    const PathPoint* nearest_point = nullptr;
    for (const PathPoint& point : r.trajectory.trajectory.path) {
      const Eigen::Matrix2d covariance = point.parameter_covariance + point.noise_covariance;
      if (covariance.determinant() <= 0.0) continue;
      const Eigen::Vector2d d = point.position - at;
      const double sigmas = std::sqrt(d.dot(covariance.ldlt().solve(d)));
      if (sigmas < nearest) {
        nearest = sigmas;
        nearest_point = &point;
      }
    }
    if (nearest_point != nullptr) {
      c.rows.push_back(
          {"the path passes " + std::string(kReportPassedLandmark) + " (section 4)",
           std::string("the corrected path passes ") + kReportPassedLandmark,
           StringPrintf("nearest at t = %.1f s: %.1f m away, %.2f sigma",
                        nearest_point->timestamp_s, (nearest_point->position - at).norm(), nearest),
           nearest <= 3.0 ? "agrees: the path passes within 3 sigma of it, then goes on"
                          : "differs: the path never comes within 3 sigma of it"});
    }
  }
  {
    // The landmark nearest the uncorrected endpoint.
    const Eigen::Vector2d raw = r.trajectory.trajectory.raw_endpoint;
    const Landmark* nearest = nullptr;
    for (const Landmark& landmark : r.landmarks) {
      if (nearest == nullptr || (Eigen::Vector2d(landmark.x_m, landmark.y_m) - raw).norm() <
                                    (Eigen::Vector2d(nearest->x_m, nearest->y_m) - raw).norm())
        nearest = &landmark;
    }
    if (nearest != nullptr) {
      const double distance = (Eigen::Vector2d(nearest->x_m, nearest->y_m) - raw).norm();
      c.rows.push_back({"without the correction, the run seems to end at (section 6)",
                        kReportRawLandmark,
                        StringPrintf("%s: the raw endpoint (%.1f, %.1f) m is %.1f m from it",
                                     nearest->name.c_str(), raw.x(), raw.y(), distance),
                        nearest->name == kReportRawLandmark ? "agrees" : "differs"});
    }
  }

  // Section 5.
  std::array<std::string, 2> pairs;
  const std::array<double, 2> gaps = {MinimumGap(r.landmarks, 0, &pairs[0]),
                                      MinimumGap(r.landmarks, 1, &pairs[1])};
  AddNumericRow("d_min,x (m), smallest x gap (" + pairs[0] + ")", kMinGapX, gaps[0], "", &c);
  AddNumericRow("d_min,y (m), smallest y gap (" + pairs[1] + ")", kMinGapY, gaps[1], "", &c);
  {
    const Eigen::Matrix2d& noise_part = r.min_samples.model.noise_part;
    const std::array<double, 2> noise_sigma = {std::sqrt(noise_part(0, 0)),
                                               std::sqrt(noise_part(1, 1))};
    bool unattainable = true;
    for (int axis = 0; axis < 2; ++axis) unattainable &= 3.0 * noise_sigma[axis] > gaps[axis] / 2;
    const std::string ours =
        r.min_samples.designs.empty()
            ? std::string("not computed (no landmark decided)")
            : StringPrintf(
                  "N = %d: P(wrong landmark) <= %g, judged in the plane with the honest covariance",
                  r.min_samples.uniform_n_min, r.max_error);
    c.rows.push_back({"samples needed (section 5)",
                      StringPrintf("N_x = %d, N_y = %d (per-axis bounds)", kReportNx, kReportNy),
                      ours,
                      StringPrintf(
                          // clang-format off
             "a different criterion: each axis alone to resolve its smallest gap, 3 sigma below %.2f m (x) and %.2f m (y); the run's own noise alone gives sigma %.2f m (x) and %.2f m (y) at any N, so %s",
                          // clang-format on
                          gaps[0] / 2, gaps[1] / 2, noise_sigma[0], noise_sigma[1],
                          unattainable ? "no N meets it" : "a large enough N meets it")});
  }

  // The summary line.
  std::string off;
  for (const ReferenceRow& row : c.rows) {
    if (!row.agreement.has_value() || *row.agreement == Agreement::kAgrees) continue;
    off +=
        (off.empty() ? "" : ", ") + row.figure.substr(0, row.figure.find(" (")) +
        (*row.agreement == Agreement::kLastDigit ? " is off by one in its last digit" : " differs");
  }
  c.summary =
      StringPrintf(
          "The reference report (2018): %d of the %d figures it printed agree to their printed "
          "digits",
          c.agreeing_rows, c.numeric_rows) +
      (off.empty() ? std::string("") : " (" + off + ")") +
      (decision.reached.empty()
           ? std::string("; like it, this analysis finds no landmark consistent")
           : "; its conclusion that the run reaches no landmark does not hold: it reaches " +
                 decision.reached) +
      ".";
  return c;
}

}  // namespace accelcal
