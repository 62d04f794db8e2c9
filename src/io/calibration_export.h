#ifndef ACCELCAL_IO_CALIBRATION_EXPORT_H_
#define ACCELCAL_IO_CALIBRATION_EXPORT_H_

// A triad's calibration file (io/calibration_file.h) in the formats other stacks read
// (docs/calibration.md, "Exports"), each format's text in its own file of io/:
//   kalibr: Kalibr's imu.yaml, the noise only (io/kalibr_imu_yaml.h), from the Allan fits of the
//           accelerometer's and the gyroscope's logs through the calibration's matrices;
//   imu_tk: imu_tk's .calib pair, PREFIX_acc.calib and PREFIX_gyro.calib (io/imu_tk_calib_file.h):
//           T, K, b as they are, full precision;
//   imucal: imucal's calibration JSON, a FerrarisCalibrationInfo (io/imucal_calibration_json.h):
//           K_a R_a = (T K)^-1, b_a = b; K_g R_g = (c T_g K_g)^-1, K_ga = 0, b_g = b_g.
// What a format cannot hold is refused, never approximated: a two-axis calibration (every format
// is a triad's), a calibration without a gyroscope for Kalibr and imucal (their files need one),
// Allan fits of logs in another unit than the calibration's.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/status.h"
#include "io/calibration_file.h"

namespace accelcal {

enum class ExportFormat { kKalibr, kImuTk, kImucal };

// "kalibr", "imu_tk" or "imucal".
Status ParseExportFormat(const std::string& name, ExportFormat* format);

struct ExportOptions {
  ExportFormat format = ExportFormat::kImuTk;
  // kalibr: the output file; imu_tk: the prefix of PREFIX_acc.calib and PREFIX_gyro.calib;
  // imucal: the output file.
  std::string out;
  // kalibr: allan's JSON of the accelerometer's and of the gyroscope's static logs (parsed),
  // their paths for messages; the topic; the rate (0: the Allan logs' own).
  nlohmann::json allan;
  std::string allan_path;
  nlohmann::json gyro_allan;
  std::string gyro_allan_path;
  std::string rostopic = "/imu0";
  double update_rate_hz = 0.0;
  // imucal: the calibrated gyroscope's unit, "deg/s" (imucal's own) or "rad/s".
  std::string imucal_gyr_unit = "deg/s";
  // Where the export came from, one line each (the calibration file and its SHA-256, the
  // command, the version and time): '#' lines in YAML and .calib, imucal's "comment".
  std::vector<std::string> provenance;
};

struct ExportedFile {
  std::string path;
  std::string contents;
  std::string what;  // e.g. "imu_tk's accelerometer calibration"
};

// The files of `options.format` for `record` (read from `calibration_path`, named in messages),
// and notes for stdout (what was chosen, what was left out). Nothing is written here.
Status ExportCalibration(const CalibrationRecord& record, const std::string& calibration_path,
                         const ExportOptions& options, std::vector<ExportedFile>* files,
                         std::vector<std::string>* notes);

// The paths `options` writes to (for checking them before any work): one, or imu_tk's two.
std::vector<std::string> ExportPaths(const ExportOptions& options, bool has_gyroscope);

}  // namespace accelcal

#endif  // ACCELCAL_IO_CALIBRATION_EXPORT_H_
