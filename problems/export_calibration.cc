// export_calibration: a triad's calibration file (docs/calibration.md) written in the format
// another stack reads (docs/calibration.md, "Exports"; the formats in io/calibration_export.h):
//
//   kalibr  Kalibr's imu.yaml: noise densities and bias random walks, no intrinsics. Each term is
//           the Allan fit's (allan --json of the sensor's static log, in the calibration's output
//           unit) carried into the corrected output, x = M u: density_i = sqrt(sum_k M_ik^2 N_k^2),
//           the largest axis's; the random walk likewise from K (or, unresolved, from the
//           curve's bound min_tau sqrt(3/tau) adev_high(tau)).
//   imu_tk  imu_tk's pair PREFIX_acc.calib, PREFIX_gyro.calib: T, K, b of a = T K (u - b), the
//           layout of CalibratedTriad_::save at full precision.
//   imucal  imucal's calibration JSON (FerrarisCalibrationInfo): K_a R_a = (T K)^-1, b_a = b,
//           K_g R_g = (c T_g K_g)^-1, K_ga = 0, b_g = b_g (c = 180/pi for its deg/s).
//
// Input: the calibration file (and, for kalibr, the two Allan fits). Output: the file(s),
// written atomically, all or none; what was written and how on stdout.
//
//   build/bin/export_calibration --calibration=cal.json --format=imucal --out=imucal_cal.json

#include <gflags/gflags.h>

#include <iostream>

#include "io/calibration_export.h"
#include "io/calibration_file.h"
#include "io/input_file.h"
#include "io/json_file.h"
#include "io/output_paths.h"
#include "io/provenance.h"
#include "problem_support.h"

// clang-format off
DEFINE_string(calibration, "", "The calibration file of a triad (calibrate_imu --mode=ml --calibration_out; docs/calibration.md). Required.");
DEFINE_string(format, "", "kalibr (Kalibr's imu.yaml: noise only, m/s^2/sqrt(Hz), m/s^3/sqrt(Hz), rad/s/sqrt(Hz), rad/s^2/sqrt(Hz); needs --allan and --gyro_allan), imu_tk (imu_tk's .calib pair: T, K, b; raw input in the calibration's output unit, output m/s^2 and rad/s) or imucal (imucal's calibration JSON, a FerrarisCalibrationInfo: raw input in from_acc_unit/from_gyr_unit, output m/s^2 and --imucal_gyr_unit). Required.");
DEFINE_string(out, "", "kalibr, imucal: the file to write. imu_tk: a prefix PREFIX, giving PREFIX_acc.calib and PREFIX_gyro.calib (the latter when the calibration has a gyroscope section). Written atomically, all or none. Required.");
DEFINE_string(allan, "", "--format=kalibr: allan's JSON (allan --json) of the accelerometer's static log, in the calibration's output unit.");
DEFINE_string(gyro_allan, "", "--format=kalibr: allan's JSON of the gyroscope's static log, in the output unit of the calibration's gyroscope section (allan --log=GYRO_LOG --unit=count for counts).");
DEFINE_string(rostopic, "/imu0", "--format=kalibr: the topic of the IMU's sensor_msgs/Imu messages in the bag.");
DEFINE_double(update_rate_hz, 0.0, "--format=kalibr: the IMU's message rate in Hz; 0: the Allan logs' sampling rate.");
DEFINE_string(imucal_gyr_unit, "deg/s", "--format=imucal: the calibrated gyroscope's unit, deg/s (imucal's, what its Ferraris calibration gives) or rad/s.");
// clang-format on
ACCELCAL_FLAG_RANGE(update_rate_hz, 0.0, 1e6);

namespace accelcal {
namespace {

constexpr char kUsage[] =
    "Writes a triad's calibration file in the format another stack reads (docs/calibration.md,\n"
    "Exports). Units: the raw input each format's reader takes is in the calibration's output\n"
    "unit (count, m/s^2 or g; the gyroscope's count, rad/s or deg/s); corrected values are in\n"
    "m/s^2 and rad/s (imucal: deg/s by default). Kalibr's imu.yaml holds noise only (Kalibr\n"
    "reads no intrinsics from it): its terms come from allan's fits of the two static logs,\n"
    "carried through the calibration into the corrected unit. What a format cannot hold (a\n"
    "two-axis calibration; Kalibr or imucal without a gyroscope section) is refused.\n"
    "Exit status: 0 on success, 2 on bad input (one line on stderr; nothing is written).\n\n"
    "  export_calibration --calibration=cal.json --format=imu_tk --out=xsens\n"
    "  export_calibration --calibration=cal.json --format=imucal --out=imucal_cal.json\n"
    "  export_calibration --calibration=cal.json --format=kalibr --allan=acc_allan.json\n"
    "                     --gyro_allan=gyro_allan.json [--rostopic=/imu0] --out=imu.yaml";

Status CheckFlags(ExportOptions* options) {
  if (FLAGS_calibration.empty())
    return Status::Error("--calibration must name a triad's calibration file");
  if (FLAGS_format.empty()) return Status::Error("--format must be kalibr, imu_tk or imucal");
  ACCELCAL_RETURN_IF_ERROR(ParseExportFormat(FLAGS_format, &options->format));
  if (FLAGS_out.empty()) {
    return Status::Error(options->format == ExportFormat::kImuTk
                             ? "--out must name the prefix of the .calib pair"
                             : "--out must name the file to write");
  }
  if (options->format == ExportFormat::kImuTk && FLAGS_out.back() == '/') {
    return Status::Error("--out='" + FLAGS_out + "' names a folder; give a prefix, e.g. --out=" +
                         FLAGS_out + "imu (writing imu_acc.calib and imu_gyro.calib)");
  }
  const bool kalibr = options->format == ExportFormat::kKalibr;
  if (kalibr && (FLAGS_allan.empty() || FLAGS_gyro_allan.empty())) {
    return Status::Error(
        "--format=kalibr needs --allan and --gyro_allan: allan's JSON of the accelerometer's and "
        "of the gyroscope's static logs (Kalibr's noise terms come from them)");
  }
  if (!kalibr && (!FLAGS_allan.empty() || !FLAGS_gyro_allan.empty())) {
    return Status::Error("--allan and --gyro_allan are for --format=kalibr only");
  }
  if (options->format != ExportFormat::kImucal && FLAGS_imucal_gyr_unit != "deg/s")
    return Status::Error("--imucal_gyr_unit is for --format=imucal only");
  options->out = FLAGS_out;
  options->allan_path = FLAGS_allan;
  options->gyro_allan_path = FLAGS_gyro_allan;
  options->rostopic = FLAGS_rostopic;
  options->update_rate_hz = FLAGS_update_rate_hz;
  options->imucal_gyr_unit = FLAGS_imucal_gyr_unit;
  if (FLAGS_rostopic.empty() ||
      FLAGS_rostopic.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                       "0123456789_/~") != std::string::npos) {
    return Status::Error("--rostopic '" + FLAGS_rostopic +
                         "' is not a ROS topic name (letters, digits, _, / and ~)");
  }
  return Status::Ok();
}

Status ReadAllan(const std::string& path, nlohmann::json* json) {
  std::string text;
  ACCELCAL_RETURN_IF_ERROR(
      ReadInputText(path, 64ull << 20, "allan's JSON", &text).WithContext(path));
  return ParseJsonStrict(text, json).WithContext(path);
}

int Run(int argc, char** argv) {
  if (!InitProblem("export_calibration", kUsage, "problems/export_calibration", &argc, &argv))
    return kExitBadInput;
  ExportOptions options;
  Status status = CheckFlags(&options);
  CalibrationRecord record;
  if (status.ok()) status = ReadCalibrationFile(FLAGS_calibration, &record);
  if (status.ok()) {
    // Every output checked against the inputs and special files before anything is made.
    RunInputs inputs;
    inputs.files = {FLAGS_calibration};
    if (!FLAGS_allan.empty()) inputs.files.push_back(FLAGS_allan);
    if (!FLAGS_gyro_allan.empty()) inputs.files.push_back(FLAGS_gyro_allan);
    std::vector<OutputPath> outputs;
    for (const std::string& path : ExportPaths(options, record.has_gyroscope))
      outputs.push_back({"--out", path});
    status = CheckOutputPaths(outputs, inputs);
  }
  if (status.ok() && options.format == ExportFormat::kKalibr) {
    status = ReadAllan(FLAGS_allan, &options.allan);
    if (status.ok()) status = ReadAllan(FLAGS_gyro_allan, &options.gyro_allan);
  }
  InputFile calibration_file;
  if (status.ok()) status = HashInputFile(FLAGS_calibration, &calibration_file);
  if (!status.ok()) return ExitWithError("export_calibration", status);

  options.provenance = {
      std::string("accelcal export_calibration ") + AccelcalVersion() + ", " +
          UtcNow("%Y-%m-%dT%H:%M:%SZ"),
      "calibration: " + calibration_file.path + " (sha256 " + calibration_file.sha256 + ")",
      "command: " + CommandLine()};
  std::vector<ExportedFile> files;
  std::vector<std::string> notes;
  status = ExportCalibration(record, FLAGS_calibration, options, &files, &notes);
  std::vector<std::pair<std::string, std::string>> contents;
  for (const ExportedFile& file : files) contents.emplace_back(file.path, file.contents);
  if (status.ok()) status = WriteFilesAtomically(contents);
  if (!status.ok()) return ExitWithError("export_calibration", status);
  std::cout << "calibration: " << FLAGS_calibration << " (" << record.geometry << ", output in "
            << record.output_unit
            << (record.has_gyroscope ? "; gyroscope in " + record.gyroscope.output_unit : "")
            << ")\n";
  for (const ExportedFile& file : files)
    std::cout << "wrote " << file.path << ": " << file.what << "\n";
  for (const std::string& note : notes) std::cout << "note: " << note << "\n";
  return 0;
}

}  // namespace
}  // namespace accelcal

int main(int argc, char** argv) {
  return accelcal::GuardedMain("export_calibration", accelcal::Run, argc, argv);
}
