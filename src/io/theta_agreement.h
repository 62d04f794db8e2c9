#ifndef ACCELCAL_IO_THETA_AGREEMENT_H_
#define ACCELCAL_IO_THETA_AGREEMENT_H_

// Whether a tilt test's angles say what they claim, checked by physics rather than by their
// range. In the tilt test (../shared/spec/error-model.md) the true specific force is
//
//   f_x = -g sin(theta),  f_y = -g cos(theta),
//
// so the direction of the measured output vector, phi = atan2(-m_x, -m_y), tracks theta:
// biases, scale errors, the table offset and the non-orthogonality move it by hundredths of
// a radian, noise by about sigma/g. The agreement of a reading of the angles is
//
//   R = mean over samples of cos(phi_i - theta_i)
//     = mean of (-m_y cos(theta_i) - m_x sin(theta_i)) / |m_i|
//
// (samples with |m_i| = 0 say nothing and are skipped). R is near 1 for the right reading
// and near 0 for a wrong one: degrees read as radians turn 57 times too fast, so over any
// span wider than a few degrees the cosine takes all signs; an inverted axis, swapped columns
// or a column that is not theta do the same.
//
// The thresholds were chosen by measurement (issue 15): a numpy simulation of the spec's model
// with biases ~0.1 m/s^2, scale errors ~0.03, a table offset ~0.01 rad and a
// non-orthogonality ~0.005 rad; spans uniform in 5..360 degrees starting anywhere in
// -360..360 degrees, uniform or random schedules, noise sigma uniform in 0..3 m/s^2 on each
// axis (the course's is 0.5 and 0.8); 4000 tests per sample count:
//
//   samples                          3     5    10    20    40   200  2000
//   right reading, min R           0.58  0.68  0.75  0.81  0.86  0.90  0.91
//   the course's noise, min R     0.981 0.985 0.988 0.993 0.993 0.994 0.995
//   radian data, max R_deg - R_rad 0.07  0.06  0.00  0.00  0.00  0.00  0.00
//   degree data, min R_deg - R_rad    (aliasing of sparse samples)    0.78  0.76
//
// and, with sigma = 3 m/s^2 on both axes in every test (200 000 tests per count), the right
// reading's R fell below 0.5 in 6.8e-4 of the 3-sample tests and 2.5e-5 of the 5-sample ones,
// never from 10 samples on (min 0.53 at 10, 0.85 at 40); the degree rule below fired on
// radian data 18 times in 200 000 3-sample tests, once in 5-sample ones, never from 10 on.
// tests/theta_agreement_test.cc repeats the check with the project's simulator. Hence:
//   kMinAgreement = 0.5: the course's noise keeps R >= 0.98, and only 3 to 5 samples with
//     noise of 30% of g come near it; a wrong reading stays below it over any span wider
//     than about 5 degrees read as radians (|R| <= 2 / span_rad once the samples are dense).
//   kDegreeMargin = 0.2, kMinDegreeAgreement = 0.8: for data in radians the degree reading
//     never agreed better by more than 0.08 from 10 samples on; for data in degrees with 200
//     samples or more it agreed better by at least 0.76.

#include <cstddef>
#include <vector>

#include "common/measurements.h"
#include "common/status.h"
#include "io/course_data.h"

namespace accelcal {

constexpr double kMinAgreement = 0.5;
constexpr double kDegreeMargin = 0.2;
constexpr double kMinDegreeAgreement = 0.8;

// Accumulates R over a test given in any number of pieces, in constant memory (a fixed block
// of scratch, whatever the test's length), for the reading `unit` applies and, under kAuto,
// also for the numbers read as degrees. The cost is one vectorized sin/cos per sample and
// reading (common/sincos.h).
class ThetaAgreement {
 public:
  explicit ThetaAgreement(AngleUnit unit);

  // Adds samples whose angles are in radians as `unit` reads them: converted from degrees
  // under kDegree, as written under kAuto and kRadian.
  void Add(const CalibrationTest& samples);

  long long samples() const { return samples_; }
  // Samples with a non-zero output, over which R is a mean.
  long long counted() const { return counted_; }
  // R of the reading in use, and (kAuto only) of the numbers read as degrees; 0 when no
  // sample has an output.
  double agreement() const;
  double agreement_as_degrees() const;

  // The refusals, or Ok. `theta_span_rad` is the span of the angles in the reading in use.
  // A test at one angle (span 0) is left to the fit, which refuses it with what to do
  // (rotate the table through a wider range).
  //   kAuto: the degree reading agrees better by more than kDegreeMargin and above
  //     kMinDegreeAgreement: "... looks like degrees; pass --theta_unit=deg".
  //   every unit: the reading's R is below kMinAgreement: check the unit, the column order
  //     and the axes' signs.
  Status Check(double theta_span_rad) const;

 private:
  static constexpr size_t kBlock = 512;

  const AngleUnit unit_;
  long long samples_ = 0;
  long long counted_ = 0;
  double sum_ = 0.0;
  double sum_as_degrees_ = 0.0;
  // kBlock each: sin, cos, the angles as degrees, the inverse norms.
  std::vector<double> sin_;
  std::vector<double> cos_;
  std::vector<double> as_degrees_;
  std::vector<double> inverse_norm_;
};

}  // namespace accelcal

#endif  // ACCELCAL_IO_THETA_AGREEMENT_H_
