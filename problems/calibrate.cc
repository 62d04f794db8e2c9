// calibrate: a tilt-table test alone in, a calibration file out: bias and scale per axis
// with their covariance, the noise variances it assumed and where they came from, the fit's
// verdict, and where the test came from (io/calibration_file.h, docs/calibration.md).
//
//   build/bin/calibrate --data_dir=../shared/data/tp2-2018 --calibration_out=cal.json
//   build/bin/calibrate --calibration_file=my_tilt.csv --noise_variance=0.25,0.64 \
//       --calibration_out=cal.json
//
// The noise variances come from --noise_variance, else from the folder's conditions file
// (datos.txt or scenario.json) or --conditions_file, else they are estimated from the fit's
// residuals (s_k^2 = RSS_k / (N - 2)), and the output says which: an estimated variance
// makes the covariance honest for white noise but leaves the chi-square nothing to check.

#include <gflags/gflags.h>
#include <unistd.h>

#include <algorithm>
#include <iostream>
#include <sstream>

#include "estimation/tilt_table/linear_ls.h"
#include "io/calibration_file.h"
#include "io/course_data.h"
#include "io/json_file.h"
#include "io/provenance.h"
#include "io/run_conditions.h"
#include "problem_support.h"
#include "reporting/calibration_report.h"

// clang-format off
DEFINE_string(data_dir, "", "Folder holding the tilt test: ensayo.mat (course layout) or calibration.csv; its datos.txt or scenario.json, when present, states the noise variances.");
DEFINE_string(calibration_file, "", "The tilt test as a single file, overriding --data_dir: .mat with tita (Nx1, rad) and datos (Nx2, m/s^2), or .csv with columns theta,ax,ay.");
DEFINE_string(conditions_file, "", "The stated noise variances: datos.txt or scenario.json, overriding the folder's.");
DEFINE_string(noise_variance, "", "The axes' white-noise variances VX,VY in (m/s^2)^2, overriding any file. Empty and no conditions file: estimated from the residuals.");
DEFINE_double(g, 9.8, "Gravity in m/s^2. Only (1 + scale) * g is observable, so an error here moves scale_x and scale_y. A 'gravity' in scenario.json is used unless this flag is given.");
DEFINE_string(calibration_out, "", "The calibration file to write (JSON, docs/calibration.md; written atomically). Required.");
ACCELCAL_DEFINE_THETA_UNIT_FLAG();
// clang-format on

ACCELCAL_FLAG_RANGE(g, 1.0, 100.0);

namespace accelcal {
namespace {

constexpr char kUsage[] =
    "Calibrates two accelerometers (x, y) from a tilt-table test alone and writes a calibration\n"
    "file: bias_k (m/s^2) and scale_k (dimensionless) per axis with their covariance, g (m/s^2),\n"
    "the noise variances ((m/s^2)^2) and where they came from, the fit's verdict and the input's\n"
    "SHA-256. apply uses it on new data; trajectory --calibration in place of a tilt test.\n"
    "Angles in radians (--theta_unit=deg for degrees).\n"
    "Exit status: 0 on success, 2 on bad input (one line on stderr; nothing is written).\n\n"
    "  calibrate --data_dir=../shared/data/tp2-2018 --calibration_out=cal.json\n"
    "  calibrate --calibration_file=tilt.csv [--noise_variance=0.25,0.64] "
    "--calibration_out=cal.json";

// What the fit assumes about the noise, and where it came from.
struct NoiseStatement {
  double variance_x = 0.0;
  double variance_y = 0.0;
  std::string from;  // "--noise_variance", a file, or "" (to be estimated)
  RunConditions conditions;
  bool has_conditions = false;
};

Status ParseNoiseVarianceFlag(NoiseStatement* noise) {
  std::istringstream stream(FLAGS_noise_variance);
  std::string x, y, extra;
  if (std::count(FLAGS_noise_variance.begin(), FLAGS_noise_variance.end(), ',') != 1 ||
      !std::getline(stream, x, ',') || !std::getline(stream, y, ',') ||
      std::getline(stream, extra, ',')) {
    return Status::Error("--noise_variance must be two numbers VX,VY in (m/s^2)^2, got '" +
                         FLAGS_noise_variance + "'");
  }
  RunConditions conditions;
  size_t used_x = 0, used_y = 0;
  try {
    conditions.noise_variance_x = std::stod(x, &used_x);
    conditions.noise_variance_y = std::stod(y, &used_y);
  } catch (const std::exception&) {
    used_x = 0;
  }
  if (used_x != x.size() || used_y != y.size() || x.empty() || y.empty()) {
    return Status::Error("--noise_variance must be two numbers VX,VY in (m/s^2)^2, got '" +
                         FLAGS_noise_variance + "'");
  }
  ACCELCAL_RETURN_IF_ERROR(CheckRunConditions(conditions).WithContext("--noise_variance"));
  noise->variance_x = conditions.noise_variance_x;
  noise->variance_y = conditions.noise_variance_y;
  noise->from = "--noise_variance";
  return Status::Ok();
}

// The tilt test's file and, when one is there or named, the conditions file.
Status ResolveInputs(DataFiles* files) {
  if (FLAGS_data_dir.empty() && FLAGS_calibration_file.empty()) {
    return Status::Error("give the tilt test: --data_dir=FOLDER or --calibration_file=FILE");
  }
  if (FLAGS_calibration_out.empty()) {
    return Status::Error("--calibration_out must name the calibration file to write");
  }
  DataFiles overrides;
  overrides.calibration = FLAGS_calibration_file;
  overrides.conditions = FLAGS_conditions_file;
  ACCELCAL_RETURN_IF_ERROR(ResolveDataFiles(FLAGS_data_dir, overrides, files));
  // A folder's conditions file is optional here; one named by flag is not.
  if (FLAGS_conditions_file.empty() && !files->conditions.empty() &&
      access(files->conditions.c_str(), F_OK) != 0) {
    files->conditions.clear();
  }
  files->run.clear();
  files->landmarks.clear();
  return Status::Ok();
}

Status LoadNoise(const DataFiles& files, NoiseStatement* noise) {
  if (!files.conditions.empty()) {
    ACCELCAL_RETURN_IF_ERROR(LoadRunConditions(files.conditions, &noise->conditions));
    noise->has_conditions = true;
  }
  if (!FLAGS_noise_variance.empty()) return ParseNoiseVarianceFlag(noise);
  if (noise->has_conditions) {
    noise->variance_x = noise->conditions.noise_variance_x;
    noise->variance_y = noise->conditions.noise_variance_y;
    noise->from = files.conditions;
  }
  return Status::Ok();
}

// The fit under the stated variances, or under variances estimated from its residuals.
Status Fit(const CalibrationTest& test, double gravity, NoiseStatement* noise, BaselineFit* fit) {
  LinearLsOptions options;
  options.gravity_mps2 = gravity;
  options.noise_variance_x = noise->variance_x;
  options.noise_variance_y = noise->variance_y;
  if (!noise->from.empty()) return EstimateLinearLs(test, options, fit);
  ACCELCAL_RETURN_IF_ERROR(EstimateLinearLsWithNoiseFromResiduals(test, &options, fit));
  noise->variance_x = options.noise_variance_x;
  noise->variance_y = options.noise_variance_y;
  noise->from = kNoiseEstimatedFromResiduals;
  return Status::Ok();
}

int Run(int argc, char** argv) {
  if (!InitProblem("calibrate", kUsage, "problems/calibrate", &argc, &argv)) return kExitBadInput;
  DataFiles files;
  Status status = ResolveInputs(&files);
  if (status.ok()) {
    status = CheckOutputPaths({{"--calibration_out", FLAGS_calibration_out}},
                              InputsOf(FLAGS_data_dir, files));
  }
  LoadOptions load_options;
  if (status.ok()) status = LoadOptionsFromFlags(FLAGS_theta_unit, &load_options);
  CalibrationTest test;
  std::vector<std::string> notes;
  if (status.ok()) status = LoadCalibrationTest(files.calibration, &test, load_options, &notes);
  NoiseStatement noise;
  if (status.ok()) status = LoadNoise(files, &noise);
  const double gravity = ChooseGravity(noise.conditions, FLAGS_g);
  BaselineFit fit;
  if (status.ok()) status = Fit(test, gravity, &noise, &fit).WithContext(files.calibration);
  DataSource source;
  if (status.ok()) status = DescribeMeasuredData(FLAGS_data_dir, FileRoles(files), &source);
  CalibrationRecord record;
  std::string json_text;
  if (status.ok()) {
    record = TwoAxisCalibrationRecord(fit, gravity, noise.variance_x, noise.variance_y, noise.from,
                                      source);
    status = JsonText(CalibrationJson(record), &json_text);
  }
  if (status.ok()) status = WriteOutputFiles({{FLAGS_calibration_out, json_text}});
  if (!status.ok()) return ExitWithError("calibrate", status);
  PrintInputNotes(notes);
  std::cout << WithDataLine(source, CalibrationTable(record, FLAGS_calibration_out)) << std::flush;
  return 0;
}

}  // namespace
}  // namespace accelcal

int main(int argc, char** argv) {
  return accelcal::GuardedMain("calibrate", accelcal::Run, argc, argv);
}
