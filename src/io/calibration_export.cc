#include "io/calibration_export.h"

#include <Eigen/Dense>
#include <cmath>

#include "common/format.h"
#include "io/imu_tk_calib_file.h"
#include "io/imucal_calibration_json.h"
#include "io/kalibr_imu_yaml.h"
#include "models/gyroscope.h"
#include "models/imucal_convention.h"
#include "models/triad.h"

namespace accelcal {
namespace {

constexpr double kDegreesPerRadian = 180.0 / M_PI;

std::string JoinedLines(const std::vector<std::string>& lines, const char* separator) {
  std::string text;
  for (size_t i = 0; i < lines.size(); ++i) text += (i ? separator : "") + lines[i];
  return text;
}

Status NeedTriad(const CalibrationRecord& record, const std::string& path, const char* format) {
  if (record.geometry == "triad") return Status::Ok();
  return Status::Error(path + ": " + format +
                       " describes a three-axis IMU, and this calibration's geometry is " +
                       record.geometry +
                       " (no z axis): export a triad's calibration, calibrate_imu --mode=ml "
                       "--calibration_out");
}

Status NeedGyroscope(const CalibrationRecord& record, const std::string& path, const char* format,
                     const char* why) {
  if (record.has_gyroscope) return Status::Ok();
  return Status::Error(path + ": no gyroscope section, and " + format + " " + why +
                       ": calibrate with the gyroscope (its columns in the log, or --gyro_log) "
                       "and calibrate_imu --mode=ml --calibration_out");
}

// The gyroscope's matrix T_g K_g, (rad/s) per unit of its output.
Eigen::Matrix3d GyroscopeMatrix(const GyroscopeParameters& parameters) {
  Eigen::Matrix<double, 3, 3, Eigen::RowMajor> misalignment;
  GyroscopeMisalignmentMatrix(parameters.data(), misalignment.data());
  const Eigen::Vector3d gains(parameters[kGyroscopeGainX], parameters[kGyroscopeGainY],
                              parameters[kGyroscopeGainZ]);
  return misalignment * gains.asDiagonal();
}

// imucal's name of a raw unit: "a.u." for counts (its example's), else the unit itself.
std::string ImucalRawUnit(const std::string& unit) { return unit == "count" ? "a.u." : unit; }

Status ExportKalibr(const CalibrationRecord& record, const std::string& path,
                    const TriadParameters& triad, const GyroscopeParameters& gyroscope,
                    const std::string& gyroscope_unit, const ExportOptions& options,
                    std::vector<ExportedFile>* files, std::vector<std::string>* notes) {
  // The same log fit twice (the accelerometer's Allan JSON given for the gyroscope too) would
  // pass every unit check when both are in counts: refused by the logs' checksums.
  const nlohmann::json::json_pointer log_sha256("/input_files/log/sha256");
  if (options.allan.is_object() && options.gyro_allan.is_object() &&
      options.allan.contains(log_sha256) && options.gyro_allan.contains(log_sha256) &&
      options.allan.at(log_sha256) == options.gyro_allan.at(log_sha256)) {
    return Status::Error(options.allan_path + " and " + options.gyro_allan_path +
                         " are Allan fits of the same log (" + options.allan.at(log_sha256).dump() +
                         "): give --allan the accelerometer's and --gyro_allan the gyroscope's");
  }
  // Each Allan fit of one of the calibration's own logs must be of its sensor's: the
  // accelerometer's fit of the gyroscope's log (the two swapped) would give noise densities off by
  // the ratio of the two sensors' noise, in the same unit, and pass every other check.
  const auto of_log = [&](const nlohmann::json& allan) -> std::string {
    return allan.is_object() && allan.contains(log_sha256) && allan.at(log_sha256).is_string()
               ? allan.at(log_sha256).get<std::string>()
               : "";
  };
  const auto recorded = [&](const char* role) -> std::string {
    const auto it = record.input_sha256.find(role);
    return it == record.input_sha256.end() ? "" : it->second;
  };
  const std::string accelerometer_log = recorded("log");
  const std::string gyroscope_log = recorded("log_gyroscope");
  if (!gyroscope_log.empty() && gyroscope_log != accelerometer_log) {
    const bool allan_of_gyroscope = of_log(options.allan) == gyroscope_log;
    const bool gyro_allan_of_accelerometer = of_log(options.gyro_allan) == accelerometer_log;
    if (allan_of_gyroscope || gyro_allan_of_accelerometer) {
      return Status::Error(
          std::string(allan_of_gyroscope
                          ? options.allan_path + " (--allan) is an Allan fit of " + path +
                                "'s gyroscope log"
                          : options.gyro_allan_path + " (--gyro_allan) is an Allan fit of " + path +
                                "'s accelerometer log") +
          " (by their SHA-256): give --allan the accelerometer's and --gyro_allan the "
          "gyroscope's (swapped?)");
    }
  }
  KalibrImuConfig config;
  config.rostopic = options.rostopic;
  ACCELCAL_RETURN_IF_ERROR(KalibrNoiseFromAllan(options.allan, options.allan_path,
                                                record.output_unit, TriadMatrix(triad),
                                                "accelerometer", &config.accelerometer));
  ACCELCAL_RETURN_IF_ERROR(KalibrNoiseFromAllan(options.gyro_allan, options.gyro_allan_path,
                                                gyroscope_unit, GyroscopeMatrix(gyroscope),
                                                "gyroscope", &config.gyroscope));
  const double accelerometer_rate = config.accelerometer.update_rate_hz;
  const double gyroscope_rate = config.gyroscope.update_rate_hz;
  if (std::fabs(accelerometer_rate - gyroscope_rate) > 0.01 * accelerometer_rate) {
    return Status::Error(StringPrintf(
        "%s and %s: the accelerometer's log is sampled at %.6g Hz and the gyroscope's at %.6g "
        "Hz; Kalibr's update_rate is one IMU's: give the Allan fits of one IMU's logs",
        options.allan_path.c_str(), options.gyro_allan_path.c_str(), accelerometer_rate,
        gyroscope_rate));
  }
  config.update_rate_hz =
      options.update_rate_hz > 0.0 ? options.update_rate_hz : accelerometer_rate;
  std::vector<std::string> header = options.provenance;
  header.push_back(
      "Kalibr's IMU noise (kalibr_calibrate_imu_camera --imu): noise only; Kalibr reads no "
      "intrinsics from this file, so its messages must be the corrected ones (accelcal's apply "
      "output, m/s^2 and rad/s); terms of the corrected axes, docs/calibration.md, Exports");
  header.push_back("accelerometer from " + options.allan_path + ", gyroscope from " +
                   options.gyro_allan_path + " (allan --json)");
  files->push_back({options.out, KalibrImuYamlText(config, header), "Kalibr's imu.yaml"});
  for (const KalibrSensorNoise* sensor : {&config.accelerometer, &config.gyroscope})
    for (const std::string& note : sensor->notes) notes->push_back(note);
  notes->push_back(
      "Kalibr's imu.yaml holds no intrinsics: record the corrected data (apply) in the bag");
  (void)path;
  return Status::Ok();
}

}  // namespace

Status ParseExportFormat(const std::string& name, ExportFormat* format) {
  if (name == "kalibr") {
    *format = ExportFormat::kKalibr;
  } else if (name == "imu_tk") {
    *format = ExportFormat::kImuTk;
  } else if (name == "imucal") {
    *format = ExportFormat::kImucal;
  } else {
    return Status::Error("--format is '" + name + "'; it must be kalibr, imu_tk or imucal");
  }
  return Status::Ok();
}

std::vector<std::string> ExportPaths(const ExportOptions& options, bool has_gyroscope) {
  if (options.format != ExportFormat::kImuTk) return {options.out};
  std::vector<std::string> paths = {options.out + "_acc.calib"};
  if (has_gyroscope) paths.push_back(options.out + "_gyro.calib");
  return paths;
}

namespace {

// A list of effect terms in a note: all of up to three, else the first and last and how many.
std::string TermsInBrief(const std::vector<std::string>& terms) {
  if (terms.size() <= 3) return JoinStrings(terms);
  return terms.front() + " .. " + terms.back() + ", " + std::to_string(terms.size()) + " terms";
}

}  // namespace

Status ExportCalibration(const CalibrationRecord& record, const std::string& calibration_path,
                         const ExportOptions& options, std::vector<ExportedFile>* files,
                         std::vector<std::string>* notes) {
  files->clear();
  const char* format_name = options.format == ExportFormat::kKalibr  ? "Kalibr's imu.yaml"
                            : options.format == ExportFormat::kImuTk ? "imu_tk's .calib"
                                                                     : "imucal's calibration";
  ACCELCAL_RETURN_IF_ERROR(NeedTriad(record, calibration_path, format_name));
  TriadParameters triad;
  Eigen::MatrixXd covariance;
  TriadOutputUnit unit;
  // The peers' formats hold the 9 (and the gyroscope's 12): a model with effect terms is
  // written as its baseline, the same session's fit without them, and the notes say so.
  bool from_baseline = false;
  ACCELCAL_RETURN_IF_ERROR(TriadBaselineCalibration(record, calibration_path, &triad, &covariance,
                                                    &unit, &from_baseline));
  if (from_baseline) {
    notes->push_back("the accelerometer's effect terms (" + TermsInBrief(EffectTermNames(record)) +
                     ") do not fit " + format_name +
                     ": its 9 parameters are the baseline's, the same session's fit without them "
                     "(docs/calibration.md, Exports)");
  }
  GyroscopeParameters gyroscope{};
  GyroscopeOffset gyroscope_offset{};
  GyroscopeOutputUnit gyroscope_unit = GyroscopeOutputUnit::kCount;
  if (record.has_gyroscope) {
    Eigen::MatrixXd gyroscope_covariance;
    bool gyroscope_from_baseline = false;
    ACCELCAL_RETURN_IF_ERROR(GyroscopeBaselineCalibration(record.gyroscope, &gyroscope,
                                                          &gyroscope_offset, &gyroscope_covariance,
                                                          &gyroscope_unit, &gyroscope_from_baseline)
                                 .WithContext(calibration_path));
    if (gyroscope_from_baseline) {
      notes->push_back("the gyroscope's effect terms (" +
                       TermsInBrief(EffectTermNames(record.gyroscope)) + ") do not fit " +
                       format_name +
                       ": its 12 parameters are the baseline's, the same session's fit without "
                       "them (docs/calibration.md, Exports)");
    }
  }
  switch (options.format) {
    case ExportFormat::kKalibr:
      ACCELCAL_RETURN_IF_ERROR(NeedGyroscope(record, calibration_path, format_name,
                                             "needs the gyroscope's noise in rad/s"));
      return ExportKalibr(record, calibration_path, triad, gyroscope,
                          GyroscopeOutputUnitName(gyroscope_unit), options, files, notes);
    case ExportFormat::kImuTk: {
      const std::vector<std::string> paths = ExportPaths(options, record.has_gyroscope);
      std::vector<std::string> comments = options.provenance;
      comments.push_back(
          "imu_tk CalibratedTriad_::load reads the 21 numbers above and stops; a = T K (u - b), "
          "u in " +
          record.output_unit + ", a in m/s^2 (docs/calibration.md, Exports)");
      files->push_back({paths[0],
                        ImuTkCalibTextFullPrecision(ImuTkAccelerometerTriad(triad), comments),
                        "imu_tk's accelerometer calibration"});
      if (record.has_gyroscope) {
        comments.back() = std::string(
                              "imu_tk CalibratedTriad_::load reads the 21 numbers above and "
                              "stops; w = T K (u - b), u in ") +
                          GyroscopeOutputUnitName(gyroscope_unit) +
                          ", w in rad/s in the accelerometer's frame (docs/calibration.md, "
                          "Exports)";
        files->push_back({paths[1],
                          ImuTkCalibTextFullPrecision(
                              ImuTkGyroscopeTriad(gyroscope, gyroscope_offset), comments),
                          "imu_tk's gyroscope calibration"});
      } else {
        notes->push_back("no gyroscope section: " + options.out +
                         "_gyro.calib not written (the accelerometer's only)");
      }
      return Status::Ok();
    }
    case ExportFormat::kImucal: {
      ACCELCAL_RETURN_IF_ERROR(NeedGyroscope(
          record, calibration_path, format_name,
          "has no place for an accelerometer alone (its calibrate() needs all seven matrices)"));
      double output_per_radps = 0.0;
      if (options.imucal_gyr_unit == "deg/s") {
        output_per_radps = kDegreesPerRadian;
      } else if (options.imucal_gyr_unit == "rad/s") {
        output_per_radps = 1.0;
      } else {
        return Status::Error("--imucal_gyr_unit is '" + options.imucal_gyr_unit +
                             "'; it must be deg/s (imucal's) or rad/s");
      }
      ImucalCalibration imucal;
      imucal.accelerometer = TriadToImucal(triad, Eigen::Matrix3d::Identity());
      imucal.gyroscope = GyroscopeToImucal(gyroscope, gyroscope_offset, output_per_radps);
      imucal.has_gyroscope = true;
      ImucalUnits units;
      units.acc_unit = "m/s^2";
      units.gyr_unit = options.imucal_gyr_unit;
      units.from_acc_unit = ImucalRawUnit(record.output_unit);
      units.from_gyr_unit = ImucalRawUnit(GyroscopeOutputUnitName(gyroscope_unit));
      std::vector<std::string> comment = options.provenance;
      comment.push_back(
          "accelcal's a = T K (u - b) and w = T_g K_g (u_g - b_g) as imucal's Ferraris model: "
          "K_a R_a = (T K)^-1, K_g R_g = (c T_g K_g)^-1, K_ga = 0 (the calibration file's "
          "gyroscope model has no g-sensitivity term); both in accelcal's frame (the calibration "
          "file's model.conventions) "
          "(docs/calibration.md, Exports)");
      units.comment = JoinedLines(comment, "; ");
      files->push_back({options.out, ImucalCalibrationJsonText(imucal, units),
                        "imucal's calibration (FerrarisCalibrationInfo)"});
      return Status::Ok();
    }
  }
  return Status::Error("unknown export format");
}

}  // namespace accelcal
