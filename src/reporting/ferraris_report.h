#ifndef ACCELCAL_REPORTING_FERRARIS_REPORT_H_
#define ACCELCAL_REPORTING_FERRARIS_REPORT_H_

// What the ferraris mode prints and writes (docs/imucal.md): the holds; imucal's closed form in
// imucal's convention (beside a reference calibration such as imucal's example_cal.json, when
// given) and in accelcal's; the least-squares fits with sigma and their differences from the
// closed form in those sigma; the fit statistic of Ferraris's assumption; what six holds can
// and cannot determine. The text and the JSON come from the same numbers. Formatting only.

#include <nlohmann/json.hpp>
#include <string>

#include "common/ferraris_session.h"
#include "estimation/triad/ferraris_calibration.h"
#include "estimation/triad/ferraris_least_squares.h"
#include "models/imucal_convention.h"

namespace accelcal {

struct FerrarisReport {
  std::string session_path;
  FerrarisSession session;
  FerrarisOptions options;
  FerrarisAnalysis analysis;
  // A calibration to show beside the closed form (imucal's example_cal.json), when given.
  bool has_reference = false;
  std::string reference_path;
  ImucalCalibration reference;
};

// The largest |ours - reference| / |reference| over the elements of K_a, R_a, b_a (and of the
// gyroscope's matrices when both have them); an element the reference gives as exactly 0
// counts as |ours|.
double FerrarisMaxRelativeDifference(const ImucalCalibration& ours,
                                     const ImucalCalibration& reference);

std::string FerrarisTable(const FerrarisReport& report);
nlohmann::json FerrarisJson(const FerrarisReport& report);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_FERRARIS_REPORT_H_
