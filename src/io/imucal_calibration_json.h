#ifndef ACCELCAL_IO_IMUCAL_CALIBRATION_JSON_H_
#define ACCELCAL_IO_IMUCAL_CALIBRATION_JSON_H_

// Reader of imucal's calibration file (its CalibrationInfo.to_json_file; example_cal.json in
// ../shared/data/imucal-ferraris): an object with K_a, R_a (3x3 arrays of rows), b_a (3 numbers)
// and, for a Ferraris calibration, K_g, R_g, K_ga, b_g. Other keys (units, comment,
// cal_type, _format_version) are not needed and not checked. Refused with the file name and
// the key: a missing accelerometer key, a gyroscope given in part, a value that is not an
// array of the right shape of finite numbers, a key given twice (io/json_file.h).

#include <string>

#include "common/status.h"
#include "models/imucal_convention.h"

namespace accelcal {

Status ParseImucalCalibrationJson(const std::string& text, ImucalCalibration* calibration);

// The file `path`; failures start with the file name.
Status ReadImucalCalibrationJson(const std::string& path, ImucalCalibration* calibration);

}  // namespace accelcal

#endif  // ACCELCAL_IO_IMUCAL_CALIBRATION_JSON_H_
