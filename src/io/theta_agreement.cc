#include "io/theta_agreement.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/format.h"
#include "common/sincos.h"

namespace accelcal {

ThetaAgreement::ThetaAgreement(AngleUnit unit)
    : unit_(unit), sin_(kBlock), cos_(kBlock), as_degrees_(kBlock), inverse_norm_(kBlock) {}

void ThetaAgreement::Add(const CalibrationTest& samples) {
  const size_t size = samples.theta_rad.size();
  for (size_t first = 0; first < size; first += kBlock) {
    const size_t count = std::min(kBlock, size - first);
    const double* theta = samples.theta_rad.data() + first;
    const double* measured_x = samples.measured_x.data() + first;
    const double* measured_y = samples.measured_y.data() + first;
    for (size_t i = 0; i < count; ++i) {
      // sqrt of the sum of squares (vectorized), std::hypot only where that overflows.
      const double squares = measured_x[i] * measured_x[i] + measured_y[i] * measured_y[i];
      const double norm = squares <= std::numeric_limits<double>::max()
                              ? std::sqrt(squares)
                              : std::hypot(measured_x[i], measured_y[i]);
      inverse_norm_[i] = norm > 0.0 ? 1.0 / norm : 0.0;
      counted_ += norm > 0.0 ? 1 : 0;
    }
    SinCos(theta, count, sin_.data(), cos_.data());
    double block_sum = 0.0;
    for (size_t i = 0; i < count; ++i) {
      block_sum += (-measured_y[i] * cos_[i] - measured_x[i] * sin_[i]) * inverse_norm_[i];
    }
    sum_ += block_sum;
    if (unit_ == AngleUnit::kAuto) {
      // The same expression as the conversion of --theta_unit=deg.
      for (size_t i = 0; i < count; ++i) as_degrees_[i] = theta[i] * (M_PI / 180.0);
      SinCos(as_degrees_.data(), count, sin_.data(), cos_.data());
      double block_sum_as_degrees = 0.0;
      for (size_t i = 0; i < count; ++i) {
        block_sum_as_degrees +=
            (-measured_y[i] * cos_[i] - measured_x[i] * sin_[i]) * inverse_norm_[i];
      }
      sum_as_degrees_ += block_sum_as_degrees;
    }
    samples_ += static_cast<long long>(count);
  }
}

double ThetaAgreement::agreement() const {
  return counted_ > 0 ? sum_ / static_cast<double>(counted_) : 0.0;
}

double ThetaAgreement::agreement_as_degrees() const {
  return counted_ > 0 ? sum_as_degrees_ / static_cast<double>(counted_) : 0.0;
}

Status ThetaAgreement::Check(double theta_span_rad) const {
  if (samples_ == 0 || !(theta_span_rad > 0.0)) return Status::Ok();
  if (counted_ == 0) {
    return Status::Error(
        "ax and ay are 0 in every sample, so the outputs say nothing about theta; check that "
        "the columns hold the accelerometers' outputs (theta, ax, ay; m/s^2)");
  }
  const double agreement = this->agreement();
  const bool automatic = unit_ == AngleUnit::kAuto;
  if (automatic) {
    const double as_degrees = agreement_as_degrees();
    if (as_degrees - agreement > kDegreeMargin && as_degrees > kMinDegreeAgreement) {
      return Status::Error(StringPrintf(
          "read as radians, theta does not follow the direction of the outputs (agreement R = "
          "%.2f) but read as degrees it does (R = %.2f; R = mean cos(atan2(-ax, -ay) - theta), "
          "1 when f_x = -g sin(theta), f_y = -g cos(theta)): theta looks like degrees; pass "
          "--theta_unit=deg",
          agreement, as_degrees));
    }
  }
  if (agreement < kMinAgreement) {
    const std::string as_degrees =
        automatic ? StringPrintf(" (%.2f read as degrees)", agreement_as_degrees()) : "";
    return Status::Error(StringPrintf(
        "theta read as %s does not follow the direction of the outputs: agreement R = %.2f%s "
        "over %lld samples, where R = mean cos(atan2(-ax, -ay) - theta) is 1 for a tilt test "
        "and 0 for unrelated angles (at least %.1f expected); check the angle unit "
        "(--theta_unit), the column order (theta, ax, ay) and the axes' signs (f_x = -g "
        "sin(theta), f_y = -g cos(theta))",
        unit_ == AngleUnit::kDegree ? "degrees" : "radians", agreement, as_degrees.c_str(),
        counted_, kMinAgreement));
  }
  return Status::Ok();
}

}  // namespace accelcal
