#include "io/course_data.h"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <new>
#include <set>

#include "common/format.h"
#include "common/landmark_checks.h"
#include "common/statistics.h"
#include "io/atomic_file.h"
#include "io/calibration_stream.h"
#include "io/course_csv.h"
#include "io/course_mat.h"
#include "io/datos_txt.h"
#include "io/input_text.h"
#include "io/run_conditions.h"
#include "io/theta_agreement.h"

namespace accelcal {
namespace {

bool IsRegularFile(const std::string& path) {
  struct stat info;
  return stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode);
}

bool IsDirectory(const std::string& path) {
  struct stat info;
  return stat(path.c_str(), &info) == 0 && S_ISDIR(info.st_mode);
}

// Whether `path` ends in `extension` (lower case), in any case: data copied from Windows
// or a camera card often ends in ".CSV".
bool HasExtension(const std::string& path, const std::string& extension) {
  if (path.size() < extension.size()) return false;
  return std::equal(extension.begin(), extension.end(), path.end() - extension.size(),
                    [](char expected, char actual) {
                      return expected == std::tolower(static_cast<unsigned char>(actual));
                    });
}

// A std::bad_alloc while a file's samples are copied or transposed, as one line.
Status OutOfMemory(const std::string& what) {
  return Status::Error("not enough memory to hold " + what +
                       "; free memory, raise the limit (ulimit -v) or use less data");
}

void AddNotes(const std::string& path, const std::vector<std::string>& file_notes,
              std::vector<std::string>* notes) {
  if (notes == nullptr) return;
  for (const std::string& note : file_notes) notes->push_back(path + ": " + note);
}

// Applies `unit` to the angles (CheckThetaSpan), then checks that they follow the outputs'
// direction (ThetaAgreement). The streaming reader converts degrees with the same
// expression and checks the same way.
Status ApplyThetaUnit(AngleUnit unit, CalibrationTest* test) {
  if (test->theta_rad.empty()) return Status::Ok();
  if (unit == AngleUnit::kDegree) {
    for (double& theta : test->theta_rad) theta *= M_PI / 180.0;
  }
  const auto [low, high] = std::minmax_element(test->theta_rad.begin(), test->theta_rad.end());
  ACCELCAL_RETURN_IF_ERROR(CheckThetaSpan(unit, *low, *high, test->size()));
  ThetaAgreement agreement(unit);
  agreement.Add(*test);
  return agreement.Check(*high - *low);
}

}  // namespace

bool IsCsvPath(const std::string& path) { return HasExtension(path, ".csv"); }

// Time must increase strictly and uniformly (the integration uses one dt). The step
// every sample is held to is the median step, so that one glitch is reported where it
// is rather than shifting the reference for all the others.
Status CheckLogTime(const std::vector<double>& timestamp_s, const std::string& name,
                    double* median_step_s) {
  if (timestamp_s.size() < 2) {
    return Status::Error("the log has " + std::to_string(timestamp_s.size()) +
                         " sample(s); at least 2 are needed to know its time step");
  }
  std::vector<double> steps(timestamp_s.size() - 1);
  for (size_t j = 1; j < timestamp_s.size(); ++j) {
    steps[j - 1] = timestamp_s[j] - timestamp_s[j - 1];
    if (!(steps[j - 1] > 0.0)) {
      return Status::Error(name + " is not strictly increasing: " + name + "(" +
                           std::to_string(j + 1) + ") = " + StringPrintf("%.6g", timestamp_s[j]) +
                           " s after " + StringPrintf("%.6g", timestamp_s[j - 1]) + " s");
    }
  }
  const double dt = UpperMedian(steps);
  // An accelerometer run is sampled between 1 Hz and 100 kHz; a step outside that is a time
  // axis in another unit (milliseconds read as seconds integrate to 10^8 m), not a run.
  if (dt > kMaxRunStepS || dt < kMinRunStepS) {
    return Status::Error(StringPrintf(
        "%s steps by %.6g s, outside the [%g, %g] s of an accelerometer log: is %s in %s? "
        "store it in seconds",
        name.c_str(), dt, kMinRunStepS, kMaxRunStepS, name.c_str(),
        dt > kMaxRunStepS ? "milliseconds (or another unit)" : "minutes or hours"));
  }
  *median_step_s = dt;
  return Status::Ok();
}

Status CheckUniformTime(const std::vector<double>& timestamp_s, const std::string& name) {
  if (timestamp_s.size() < 2) {
    return Status::Error("the run has " + std::to_string(timestamp_s.size()) +
                         " sample(s); at least 2 are needed to integrate");
  }
  double dt = 0.0;
  ACCELCAL_RETURN_IF_ERROR(CheckLogTime(timestamp_s, name, &dt));
  std::vector<double> steps(timestamp_s.size() - 1);
  for (size_t j = 1; j < timestamp_s.size(); ++j)
    steps[j - 1] = timestamp_s[j] - timestamp_s[j - 1];
  // Each timestamp is the double nearest its true value, within half an ulp of it, so a
  // step of an exact clock is off by up to an ulp of |t|; 4 ulp leave room for a clock
  // accumulated in doubles. Time increases, so the largest |t| is at one end.
  const double largest = std::max(std::abs(timestamp_s.front()), std::abs(timestamp_s.back()));
  const double resolution =
      std::nextafter(largest, std::numeric_limits<double>::infinity()) - largest;
  if (4.0 * resolution >= 0.5 * dt) {
    return Status::Error(StringPrintf(
        "%s near %.10g s is resolved to %.3g s only, too coarse for its step dt = %.3g s; "
        "store the time since the start of the run",
        name.c_str(), largest, resolution, dt));
  }
  const double tolerance = 1e-6 * dt + 4.0 * resolution;
  // Steps to the decimals the tolerance resolves, trailing zeros dropped: 0.0099999905 s, a
  // 100 Hz step near 1.7e9 s, reads 0.01 s.
  const int decimals = std::clamp(static_cast<int>(std::ceil(-std::log10(tolerance))), 0, 17);
  auto seconds = [decimals](double value) {
    std::string text = StringPrintf("%.*f", decimals, value);
    if (text.find('.') != std::string::npos) {
      text.erase(text.find_last_not_of('0') + 1);
      if (text.back() == '.') text.pop_back();
    }
    return text;
  };
  for (size_t j = 0; j < steps.size(); ++j) {
    if (std::abs(steps[j] - dt) > tolerance) {
      return Status::Error(name + " is not uniformly spaced: " + name + "(" +
                           std::to_string(j + 2) + ") - " + name + "(" + std::to_string(j + 1) +
                           ") = " + seconds(steps[j]) + " s, expected dt = " + seconds(dt) +
                           " s; resample the run");
    }
  }
  return Status::Ok();
}

// A tilt test never needs more than two turns, while any test wider than 12.6 degrees spans
// more than 4*pi when its degrees are read as radians, so kAuto refuses such a span instead
// of fitting a wrong model silently.
Status CheckThetaSpan(AngleUnit unit, double theta_min, double theta_max, long long sample_count) {
  const double span = theta_max - theta_min;
  if (unit == AngleUnit::kAuto && span > 4.0 * M_PI) {
    return Status::Error(StringPrintf(
        "theta spans %.6g (from %.6g to %.6g) over %lld samples, more than two turns if it were "
        "radians: it looks like degrees; pass --theta_unit=deg (or --theta_unit=rad if the "
        "table really turned that far)",
        span, theta_min, theta_max, sample_count));
  }
  return Status::Ok();
}

Status ParseAngleUnit(const std::string& text, AngleUnit* unit) {
  if (text == "auto") {
    *unit = AngleUnit::kAuto;
  } else if (text == "rad") {
    *unit = AngleUnit::kRadian;
  } else if (text == "deg") {
    *unit = AngleUnit::kDegree;
  } else {
    return Status::Error("--theta_unit='" + EchoInput(text) + "' is not one of auto, rad, deg");
  }
  return Status::Ok();
}

Status ResolveDataFiles(const std::string& data_dir, DataFiles* files) {
  if (!IsDirectory(data_dir)) {
    // Say what is there instead: a file given as --data_dir is the common slip.
    struct stat info;
    const std::string what = stat(data_dir.c_str(), &info) != 0 ? ": no such directory"
                             : S_ISREG(info.st_mode)            ? ": is a file, not a folder"
                                                                : ": is not a folder";
    return Status::Error(data_dir + what +
                         "; --data_dir must name a folder holding ensayo.mat (course layout) "
                         "or calibration.csv");
  }
  const std::string dir = data_dir.back() == '/' ? data_dir : data_dir + "/";
  if (IsRegularFile(dir + "ensayo.mat") && IsRegularFile(dir + "calibration.csv")) {
    return Status::Error(data_dir +
                         ": holds both layouts (ensayo.mat and calibration.csv), so which data "
                         "to read is not clear; keep one, or name the files with "
                         "--calibration_file and the other --*_file flags");
  }
  if (IsRegularFile(dir + "ensayo.mat")) {
    *files = {DataLayout::kCourseMat, dir + "ensayo.mat", dir + "acel.mat", dir + "puntos.mat",
              dir + "datos.txt"};
    return Status::Ok();
  }
  if (IsRegularFile(dir + "calibration.csv")) {
    *files = {DataLayout::kCsv, dir + "calibration.csv", dir + "trajectory.csv",
              dir + "landmarks.csv", dir + "scenario.json"};
    return Status::Ok();
  }
  return Status::Error(data_dir +
                       ": no course data here: expected ensayo.mat (course layout) "
                       "or calibration.csv (CSV layout)");
}

Status ResolveDataFiles(const std::string& data_dir, const DataFiles& overrides, DataFiles* files) {
  DataFiles resolved;
  if (!data_dir.empty()) ACCELCAL_RETURN_IF_ERROR(ResolveDataFiles(data_dir, &resolved));
  for (const auto member :
       {&DataFiles::calibration, &DataFiles::run, &DataFiles::landmarks, &DataFiles::conditions}) {
    if (!(overrides.*member).empty()) resolved.*member = overrides.*member;
  }
  *files = resolved;
  return Status::Ok();
}

Status LoadCalibrationTest(const std::string& path, CalibrationTest* test,
                           const LoadOptions& options, std::vector<std::string>* notes) {
  *test = CalibrationTest();
  std::vector<std::string> file_notes;
  Status status;
  if (IsCsvPath(path)) {
    // The streaming reader, so that a CSV test is read by one code path whether it is kept
    // or only accumulated; it checks the path, applies the angle unit and names the file
    // itself.
    CalibrationStreamOptions stream_options;
    stream_options.theta_unit = options.theta_unit;
    try {
      status = StreamCalibrationCsv(
          path, stream_options, [test](const CalibrationTest& batch) { test->Append(batch); },
          nullptr);
    } catch (const std::bad_alloc&) {
      const int held = test->size();
      *test = CalibrationTest();
      status = OutOfMemory("more than " + std::to_string(held) + " samples of the tilt test")
                   .WithContext(path);
    }
    if (!status.ok()) *test = CalibrationTest();
    return status;
  }
  try {
    status = LoadCalibrationMat(path, test, &file_notes);
  } catch (const std::bad_alloc&) {
    *test = CalibrationTest();
    status = OutOfMemory("the tilt test's samples");
  }
  if (status.ok()) status = ApplyThetaUnit(options.theta_unit, test);
  if (!status.ok()) *test = CalibrationTest();
  AddNotes(path, file_notes, notes);
  return status.WithContext(path);
}

namespace {

Status LoadTimedLog(const std::string& path, bool uniform_time, VehicleRun* run,
                    std::vector<std::string>* notes) {
  *run = VehicleRun();
  std::vector<std::string> file_notes;
  Status status;
  try {
    status = IsCsvPath(path) ? LoadRunCsv(path, run) : LoadRunMat(path, run, &file_notes);
  } catch (const std::bad_alloc&) {
    *run = VehicleRun();
    status = OutOfMemory("the log's samples");
  }
  if (status.ok()) {
    double dt = 0.0;
    status = uniform_time ? CheckUniformTime(run->timestamp_s, "t")
                          : CheckLogTime(run->timestamp_s, "t", &dt);
  }
  if (!status.ok()) *run = VehicleRun();
  AddNotes(path, file_notes, notes);
  return status.WithContext(path);
}

}  // namespace

Status LoadVehicleRun(const std::string& path, VehicleRun* run, std::vector<std::string>* notes) {
  return LoadTimedLog(path, /*uniform_time=*/true, run, notes);
}

Status LoadMeasuredLog(const std::string& path, VehicleRun* run, std::vector<std::string>* notes) {
  return LoadTimedLog(path, /*uniform_time=*/false, run, notes);
}

Status LoadLandmarks(const std::string& path, std::vector<Landmark>* landmarks) {
  landmarks->clear();
  Status status;
  if (IsCsvPath(path)) {
    status = LoadLandmarksCsv(path, landmarks);
  } else {
    status = LoadLandmarksMat(path, landmarks);
  }
  if (status.ok()) status = CheckLandmarks(*landmarks);
  if (!status.ok()) landmarks->clear();
  return status.WithContext(path);
}

std::map<std::string, std::string> FileRoles(const DataFiles& files) {
  return {{"calibration", files.calibration},
          {"run", files.run},
          {"landmarks", files.landmarks},
          {"conditions", files.conditions}};
}

Status LoadDataFiles(const DataFiles& files, CourseData* data, const LoadOptions& options) {
  data->notes.clear();
  if (!files.calibration.empty()) {
    ACCELCAL_RETURN_IF_ERROR(
        LoadCalibrationTest(files.calibration, &data->test, options, &data->notes));
  }
  ACCELCAL_RETURN_IF_ERROR(LoadVehicleRun(files.run, &data->run, &data->notes));
  ACCELCAL_RETURN_IF_ERROR(LoadLandmarks(files.landmarks, &data->landmarks));
  return LoadRunConditions(files.conditions, &data->conditions);
}

Status WriteDataDirectory(const std::string& dir, DataLayout layout, const CalibrationTest& test,
                          const VehicleRun& run, const std::vector<Landmark>& landmarks,
                          const RunConditions& conditions, std::vector<std::string>* written) {
  written->clear();
  auto path = [&](const char* name) {
    written->push_back(dir + "/" + name);
    return written->back();
  };
  if (layout == DataLayout::kCsv) {
    ACCELCAL_RETURN_IF_ERROR(WriteCalibrationCsv(path("calibration.csv"), test));
    ACCELCAL_RETURN_IF_ERROR(WriteRunCsv(path("trajectory.csv"), run));
    ACCELCAL_RETURN_IF_ERROR(WriteLandmarksCsv(path("landmarks.csv"), landmarks));
    return WriteFileAtomically(path("scenario.json"), ScenarioJson(conditions));
  }
  ACCELCAL_RETURN_IF_ERROR(WriteCalibrationMat(path("ensayo.mat"), test));
  ACCELCAL_RETURN_IF_ERROR(WriteRunMat(path("acel.mat"), run));
  ACCELCAL_RETURN_IF_ERROR(WriteLandmarksMat(path("puntos.mat"), landmarks));
  return WriteFileAtomically(path("datos.txt"), DatosTxt(conditions));
}

}  // namespace accelcal
