#include "reporting/apply_checks.h"

#include "common/format.h"

namespace accelcal {

bool MedianMagnitudePlausible(double median_mps2, double gravity_mps2) {
  return median_mps2 >= 0.5 * gravity_mps2 && median_mps2 <= 2.0 * gravity_mps2;
}

Status ImplausibleMedianMagnitude(const std::string& log, const std::string& calibration,
                                  double median_mps2, double gravity_mps2,
                                  const std::string& output_unit) {
  return Status::Error(StringPrintf(
      "%s: corrected by %s, the log's median |a| is %.4g m/s^2, not about g = %g: is the log "
      "in the calibration's output unit (%s) and from the same sensor?",
      log.c_str(), calibration.c_str(), median_mps2, gravity_mps2, output_unit.c_str()));
}

Status CheckMedianMagnitude(const std::string& log, const std::string& calibration,
                            double median_mps2, double gravity_mps2,
                            const std::string& output_unit) {
  if (MedianMagnitudePlausible(median_mps2, gravity_mps2)) return Status::Ok();
  return ImplausibleMedianMagnitude(log, calibration, median_mps2, gravity_mps2, output_unit);
}

}  // namespace accelcal
