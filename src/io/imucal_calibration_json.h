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

// The units and comment of imucal's file (its CalibrationInfo fields): acc_unit and gyr_unit, the
// calibrated data's; from_acc_unit and from_gyr_unit, the raw data's that imucal's calibrate()
// checks against the unit its caller states ("a.u." for raw counts, as imucal's example).
struct ImucalUnits {
  std::string acc_unit = "m/s^2";
  std::string gyr_unit = "deg/s";
  std::string from_acc_unit = "a.u.";
  std::string from_gyr_unit = "a.u.";
  std::string comment;  // free text; null in the file when empty
};

// imucal's calibration file for a FerrarisCalibrationInfo (cal_type "Ferraris", _format_version
// "2.0.0"), the keys in the order its to_json_file writes them and no others (its from_json_file
// passes every key to the dataclass, which refuses one it does not know); numbers at full
// precision. `calibration` must have its gyroscope: imucal's calibrate() needs all seven
// matrices.
std::string ImucalCalibrationJsonText(const ImucalCalibration& calibration,
                                      const ImucalUnits& units);

Status ParseImucalCalibrationJson(const std::string& text, ImucalCalibration* calibration);

// The file `path`; failures start with the file name.
Status ReadImucalCalibrationJson(const std::string& path, ImucalCalibration* calibration);

}  // namespace accelcal

#endif  // ACCELCAL_IO_IMUCAL_CALIBRATION_JSON_H_
