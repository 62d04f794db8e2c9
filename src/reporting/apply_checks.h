#ifndef ACCELCAL_REPORTING_APPLY_CHECKS_H_
#define ACCELCAL_REPORTING_APPLY_CHECKS_H_

// apply's check that a triad's log is in the calibration's output unit, shared by the binary
// (problems/apply.cc) and the Python module's accelcal.apply (docs/python.md): corrected by the
// calibration, an accelerometer held still or moved by hand reads about 1 g, so the median |a|
// of the corrected samples must lie in [g/2, 2 g]. Outside it the log is in another unit than
// the calibration's (m/s^2 given to a calibration in counts corrects to about -79 m/s^2 per
// axis), or from another sensor, and its correction would be a silent wrong answer.

#include <string>

#include "common/status.h"

namespace accelcal {

// Whether `median_mps2`, the median |a| of a log's corrected samples, is about g.
bool MedianMagnitudePlausible(double median_mps2, double gravity_mps2);

// The refusal when it is not, in apply's words: `log` and `calibration` name what was corrected
// and by what (apply's --in and --calibration), `output_unit` is the calibration's.
Status ImplausibleMedianMagnitude(const std::string& log, const std::string& calibration,
                                  double median_mps2, double gravity_mps2,
                                  const std::string& output_unit);

// Both: OK when plausible, else the refusal.
Status CheckMedianMagnitude(const std::string& log, const std::string& calibration,
                            double median_mps2, double gravity_mps2,
                            const std::string& output_unit);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_APPLY_CHECKS_H_
