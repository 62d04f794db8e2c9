#include "io/course_data.h"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <new>
#include <set>

#include "common/format.h"
#include "common/landmark_checks.h"
#include "io/atomic_file.h"
#include "io/calibration_stream.h"
#include "io/csv_reader.h"
#include "io/input_text.h"
#include "io/mat_file.h"
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

std::string Shape(const MatMatrix& matrix) {
  return std::to_string(matrix.rows) + "x" + std::to_string(matrix.cols);
}

// A column vector (Nx1) or a row vector (1xN), as MATLAB users write either.
Status ReadVector(MatFileReader* reader, const std::string& name, const std::string& meaning,
                  std::vector<double>* values) {
  MatMatrix matrix;
  ACCELCAL_RETURN_IF_ERROR(reader->ReadMatrix(name, &matrix));
  if (matrix.rows != 1 && matrix.cols != 1) {
    return Status::Error("variable '" + name + "' is " + Shape(matrix) + "; expected Nx1 " +
                         meaning);
  }
  *values = matrix.values;
  for (size_t i = 0; i < values->size(); ++i) {
    if (!std::isfinite((*values)[i])) {
      return Status::Error(name + "(" + std::to_string(i + 1) + ") is " +
                           StringPrintf("%.6g", (*values)[i]) + "; remove or repair the sample");
    }
  }
  return Status::Ok();
}

// An Nx2 matrix (x then y) whose row count must equal `expected_rows`.
// A 2xN matrix (MATLAB users often save [ax; ay]) is read as its transpose and said in
// `notes`; it cannot be confused with Nx2 unless N is 2.
Status ReadTwoColumns(MatFileReader* reader, const std::string& name, int expected_rows,
                      const std::string& row_variable, std::vector<double>* x,
                      std::vector<double>* y, std::vector<std::string>* notes) {
  MatMatrix matrix;
  ACCELCAL_RETURN_IF_ERROR(reader->ReadMatrix(name, &matrix));
  if (matrix.rows == 2 && matrix.cols == expected_rows && expected_rows != 2) {
    MatMatrix transpose{matrix.cols, 2, std::vector<double>(matrix.values.size())};
    for (int row = 0; row < matrix.cols; ++row) {
      transpose.values[row] = matrix(0, row);
      transpose.values[matrix.cols + row] = matrix(1, row);
    }
    notes->push_back("variable '" + name + "' is " + Shape(matrix) + "; read as its transpose (" +
                     Shape(transpose) + ", x then y)");
    matrix = std::move(transpose);
  }
  if (matrix.cols != 2) {
    return Status::Error("variable '" + name + "' is " + Shape(matrix) + "; expected " +
                         std::to_string(expected_rows) + "x2 (x then y, m/s^2)");
  }
  if (matrix.rows != expected_rows) {
    return Status::Error("variable '" + name + "' has " + std::to_string(matrix.rows) +
                         " rows but '" + row_variable + "' has " + std::to_string(expected_rows) +
                         "; they must match sample for sample");
  }
  for (int col = 0; col < 2; ++col) {
    for (int row = 0; row < matrix.rows; ++row) {
      if (!std::isfinite(matrix(row, col))) {
        return Status::Error(name + "(" + std::to_string(row + 1) + "," + std::to_string(col + 1) +
                             ") is " + StringPrintf("%.6g", matrix(row, col)) +
                             "; remove or repair the sample");
      }
    }
  }
  x->assign(matrix.values.begin(), matrix.values.begin() + matrix.rows);
  y->assign(matrix.values.begin() + matrix.rows, matrix.values.end());
  return Status::Ok();
}

// A landmark's name is shown whole in tables, JSON and messages: it must be a printable
// line of at most kMaxLandmarkNameBytes (a MAT file's names are identifiers of at most 63).
constexpr size_t kMaxLandmarkNameBytes = 100;

Status CheckLandmarkName(const std::string& name, int row) {
  if (IsPrintableUtf8(name) && name.size() <= kMaxLandmarkNameBytes) return Status::Ok();
  return Status::Error("landmark " + std::to_string(row) + "'s name '" + EchoInput(name) + "' (" +
                       std::to_string(name.size()) + " bytes) is not a name: use at most " +
                       std::to_string(kMaxLandmarkNameBytes) +
                       " printable characters, in UTF-8 (save the file as UTF-8, not Latin-1)");
}

const std::vector<CsvColumn> kRunColumns = {{"t"}, {"ax"}, {"ay"}};
const std::vector<CsvColumn> kLandmarkColumns = {{"name", false}, {"x"}, {"y"}};

Status LoadCalibrationMat(const std::string& path, CalibrationTest* test,
                          std::vector<std::string>* notes) {
  MatFileReader reader;
  ACCELCAL_RETURN_IF_ERROR(reader.Open(path));
  ACCELCAL_RETURN_IF_ERROR(ReadVector(&reader, "tita", "angles (rad)", &test->theta_rad));
  return ReadTwoColumns(&reader, "datos", test->size(), "tita", &test->measured_x,
                        &test->measured_y, notes);
}

Status LoadRunMat(const std::string& path, VehicleRun* run, std::vector<std::string>* notes) {
  MatFileReader reader;
  ACCELCAL_RETURN_IF_ERROR(reader.Open(path));
  ACCELCAL_RETURN_IF_ERROR(ReadVector(&reader, "t", "times (s)", &run->timestamp_s));
  // The assignment calls the matrix `acel`; the course's file names it `Aerr`.
  std::vector<std::string> names;
  ACCELCAL_RETURN_IF_ERROR(reader.ListVariables(&names));
  const bool has_aerr = std::find(names.begin(), names.end(), "Aerr") != names.end();
  const bool has_acel = std::find(names.begin(), names.end(), "acel") != names.end();
  if (has_aerr && has_acel) {
    return Status::Error(
        "the file holds both 'Aerr' (the course's name) and 'acel' (the assignment's) for the "
        "run's accelerations; keep the one that is the run");
  }
  const std::string name = (!has_aerr && has_acel) ? "acel" : "Aerr";
  ACCELCAL_RETURN_IF_ERROR(
      ReadTwoColumns(&reader, name, run->size(), "t", &run->measured_x, &run->measured_y, notes));
  return CheckUniformTime(run->timestamp_s, "t");
}

Status LoadLandmarksMat(const std::string& path, std::vector<Landmark>* landmarks) {
  MatFileReader reader;
  ACCELCAL_RETURN_IF_ERROR(reader.Open(path));
  std::vector<std::string> names;
  ACCELCAL_RETURN_IF_ERROR(reader.ListVariables(&names));
  for (const std::string& name : names) {
    // Every variable of puntos.mat is a landmark, so a variable MATLAB saves without being
    // asked (the last unnamed result `ans`, or a hidden one starting with '_') would become a
    // landmark nobody placed. Such a file is refused rather than read with a stray landmark.
    if (name == "ans" || name.empty() || name.front() == '_') {
      return Status::Error(
          "variable '" + name + "' is " +
          (name == "ans" ? "MATLAB's last unnamed result" : "a variable MATLAB hides") +
          ", not a landmark: save the file with the landmarks only, e.g. save "
          "puntos.mat A B C D");
    }
  }
  // All at once: one pass over the file however many landmarks it holds.
  std::vector<std::pair<std::string, MatMatrix>> matrices;
  ACCELCAL_RETURN_IF_ERROR(
      reader.ReadAllMatrices(2, "every landmark must be a 1x2 [x y] in metres", &matrices));
  for (const auto& [name, matrix] : matrices) {
    if (matrix.values.size() != 2) {
      return Status::Error("variable '" + name + "' is " + Shape(matrix) +
                           "; every landmark must be a 1x2 [x y] in metres");
    }
    if (!std::isfinite(matrix.values[0]) || !std::isfinite(matrix.values[1])) {
      return Status::Error("landmark '" + name + "' is not finite");
    }
    landmarks->push_back({name, matrix.values[0], matrix.values[1]});
  }
  return Status::Ok();
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
Status CheckUniformTime(const std::vector<double>& timestamp_s, const std::string& name) {
  if (timestamp_s.size() < 2) {
    return Status::Error("the run has " + std::to_string(timestamp_s.size()) +
                         " sample(s); at least 2 are needed to integrate");
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
  std::vector<double> sorted = steps;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double dt = sorted[sorted.size() / 2];
  // An accelerometer run is sampled between 1 Hz and 100 kHz; a step outside that is a time
  // axis in another unit (milliseconds read as seconds integrate to 10^8 m), not a run.
  if (dt > kMaxRunStepS || dt < kMinRunStepS) {
    return Status::Error(StringPrintf(
        "%s steps by %.6g s, outside the [%g, %g] s of an accelerometer log: is %s in %s? "
        "store it in seconds",
        name.c_str(), dt, kMinRunStepS, kMaxRunStepS, name.c_str(),
        dt > kMaxRunStepS ? "milliseconds (or another unit)" : "minutes or hours"));
  }
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
    return Status::Error(data_dir +
                         ": no such directory; --data_dir must name a folder "
                         "holding ensayo.mat (course layout) or calibration.csv");
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

Status LoadVehicleRun(const std::string& path, VehicleRun* run, std::vector<std::string>* notes) {
  *run = VehicleRun();
  std::vector<std::string> file_notes;
  Status status;
  if (IsCsvPath(path)) {
    CsvTable table;
    status = ReadCsvFile(path, kRunColumns, &table);
    if (status.ok()) {
      run->timestamp_s = std::move(table.numbers[0]);
      run->measured_x = std::move(table.numbers[1]);
      run->measured_y = std::move(table.numbers[2]);
      status = CheckUniformTime(run->timestamp_s, "t");
    }
  } else {
    try {
      status = LoadRunMat(path, run, &file_notes);
    } catch (const std::bad_alloc&) {
      *run = VehicleRun();
      status = OutOfMemory("the run's samples");
    }
  }
  if (!status.ok()) *run = VehicleRun();
  AddNotes(path, file_notes, notes);
  return status.WithContext(path);
}

Status LoadLandmarks(const std::string& path, std::vector<Landmark>* landmarks) {
  landmarks->clear();
  Status status;
  if (IsCsvPath(path)) {
    CsvTable table;
    status = ReadCsvFile(path, kLandmarkColumns, &table);
    for (int i = 0; status.ok() && i < table.row_count; ++i) {
      // Names are quoted whole in the outputs and in CheckLandmarks' messages.
      status = CheckLandmarkName(table.texts[0][i], i + 1);
      if (status.ok()) {
        landmarks->push_back({table.texts[0][i], table.numbers[1][i], table.numbers[2][i]});
      }
    }
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
  ACCELCAL_RETURN_IF_ERROR(
      LoadCalibrationTest(files.calibration, &data->test, options, &data->notes));
  ACCELCAL_RETURN_IF_ERROR(LoadVehicleRun(files.run, &data->run, &data->notes));
  ACCELCAL_RETURN_IF_ERROR(LoadLandmarks(files.landmarks, &data->landmarks));
  return LoadRunConditions(files.conditions, &data->conditions);
}

Status WriteCalibrationCsv(const std::string& path, const CalibrationTest& test) {
  std::string text = "theta,ax,ay\n";
  text.reserve(text.size() + 72 * test.theta_rad.size());
  char line[128];
  for (int i = 0; i < test.size(); ++i) {
    std::snprintf(line, sizeof(line), "%.17g,%.17g,%.17g\n", test.theta_rad[i], test.measured_x[i],
                  test.measured_y[i]);
    text += line;
  }
  return WriteFileAtomically(path, text);
}

namespace {

Status WriteThreeColumnCsv(const std::string& path, const char* header,
                           const std::vector<double>& first, const std::vector<double>& second,
                           const std::vector<double>& third) {
  std::string text = std::string(header) + "\n";
  text.reserve(text.size() + 72 * first.size());
  for (size_t i = 0; i < first.size(); ++i) {
    text += StringPrintf("%.17g,%.17g,%.17g\n", first[i], second[i], third[i]);
  }
  return WriteFileAtomically(path, text);
}

bool IsMatlabIdentifier(const std::string& name) {
  if (name.empty() || name.size() > 63 || !std::isalpha(static_cast<unsigned char>(name[0])))
    return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  });
}

MatMatrix Columns(const std::vector<const std::vector<double>*>& columns) {
  MatMatrix matrix;
  matrix.rows = static_cast<int>(columns[0]->size());
  matrix.cols = static_cast<int>(columns.size());
  for (const std::vector<double>* column : columns) {
    matrix.values.insert(matrix.values.end(), column->begin(), column->end());
  }
  return matrix;
}

}  // namespace

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
    ACCELCAL_RETURN_IF_ERROR(WriteThreeColumnCsv(path("trajectory.csv"), "t,ax,ay", run.timestamp_s,
                                                 run.measured_x, run.measured_y));
    std::string text = "name,x,y\n";
    for (const Landmark& landmark : landmarks) {
      text += StringPrintf("%s,%.17g,%.17g\n", landmark.name.c_str(), landmark.x_m, landmark.y_m);
    }
    ACCELCAL_RETURN_IF_ERROR(WriteFileAtomically(path("landmarks.csv"), text));
    return WriteFileAtomically(path("scenario.json"), ScenarioJson(conditions));
  }
  ACCELCAL_RETURN_IF_ERROR(
      WriteMatFile(path("ensayo.mat"), {{"tita", Columns({&test.theta_rad})},
                                        {"datos", Columns({&test.measured_x, &test.measured_y})}}));
  ACCELCAL_RETURN_IF_ERROR(WriteMatFile(
      path("acel.mat"),
      {{"t", Columns({&run.timestamp_s})}, {"Aerr", Columns({&run.measured_x, &run.measured_y})}}));
  std::vector<std::pair<std::string, MatMatrix>> points;
  for (const Landmark& landmark : landmarks) {
    if (!IsMatlabIdentifier(landmark.name)) {
      return Status::Error("landmark '" + landmark.name +
                           "' cannot be a MATLAB variable name; use the CSV layout or rename it");
    }
    points.push_back({landmark.name, MatMatrix{1, 2, {landmark.x_m, landmark.y_m}}});
  }
  ACCELCAL_RETURN_IF_ERROR(WriteMatFile(path("puntos.mat"), points));
  auto pair = [](double first, double second) {
    return "[" + RoundTripDouble(first) + " " + RoundTripDouble(second) + "]";
  };
  const std::string datos =
      "Posici\xC3\xB3n inicial = " +
      pair(conditions.initial_position_x_m, conditions.initial_position_y_m) +
      "\nVelocidad inicial = " +
      pair(conditions.initial_velocity_x_mps, conditions.initial_velocity_y_mps) +
      "\nvarianza del ruido de los aceler\xC3\xB3metros = " +
      pair(conditions.noise_variance_x, conditions.noise_variance_y) + "\n";
  return WriteFileAtomically(path("datos.txt"), datos);
}

}  // namespace accelcal
