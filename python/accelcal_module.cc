// The Python module `accelcal` (docs/python.md): reading an IMU log, calibrating a triad by
// maximum likelihood (calibrate_imu --mode=ml) and applying a calibration to numpy arrays
// (apply's triad correction). Conversion only: every step is a library call the binaries make
// (io/imu_log.h, reporting/calibrate_imu_run.h, io/calibration_file.h,
// estimation/tilt_table/calibration_correction.h), so that the module and the binaries give
// the same numbers and the same one-line messages. A refused input raises accelcal.Error, a
// subclass of ValueError, with the binary's message; the C++ calls run without the GIL, so
// threads (Dask's threaded workers) calibrate in parallel. Every file or folder the module writes
// goes through the binaries' output-path guard (io/output_paths.h) and atomic writers
// (io/atomic_file.h): an input, a special file or a folder accelcal did not write is never
// replaced, and nothing partial is ever left.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "common/build_info.h"
#include "common/format.h"
#include "common/sha256.h"
#include "common/status.h"
#include "common/triad_log.h"
#include "estimation/discovery/verdict.h"
#include "estimation/tilt_table/calibration_correction.h"
#include "io/atomic_file.h"
#include "io/calibration_file.h"
#include "io/csv_reader.h"
#include "io/imu_log.h"
#include "io/json_file.h"
#include "io/output_paths.h"
#include "io/provenance.h"
#include "models/gyroscope_units.h"
#include "models/triad.h"
#include "models/triad_units.h"
#include "reporting/apply_checks.h"
#include "reporting/calibrate_imu_options.h"
#include "reporting/calibrate_imu_report.h"
#include "reporting/calibrate_imu_run.h"

namespace py = pybind11;

namespace accelcal {
namespace {

// A refused input: raised in Python as accelcal.Error (a ValueError).
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

void ThrowIfError(const Status& status) {
  if (!status.ok()) throw InputError(status.message());
}

// A path (str or os.PathLike); anything else (a numpy array, a DataFrame) is refused as
// accelcal.Error with what to give instead, not with os.fspath's TypeError.
std::string PathOf(const py::object& path) {
  if (!py::isinstance<py::str>(path) && !py::isinstance<py::bytes>(path) &&
      !py::hasattr(path, "__fspath__")) {
    throw InputError(
        "expected a log's path (str or os.PathLike) or an accelcal.Log, not a " +
        std::string(py::str(path.get_type().attr("__name__"))) +
        "; arrays: accelcal.Log(time_s, acc, gyro=None) (N, and N x 3 in the log's unit)");
  }
  return py::str(py::module_::import("os").attr("fspath")(path));
}

// A path, or an iterable of paths, as strings (a single str or path-like is one path).
std::vector<std::string> PathsOf(const py::object& paths) {
  std::vector<std::string> strings;
  if (paths.is_none()) return strings;
  if (py::isinstance<py::str>(paths) || py::hasattr(paths, "__fspath__")) {
    strings.push_back(PathOf(paths));
    return strings;
  }
  for (const py::handle path : paths)
    strings.push_back(PathOf(py::reinterpret_borrow<py::object>(path)));
  return strings;
}

// The binaries' check of an output (io/output_paths.h), before anything is written: `path`
// may not be an input (by path or identity), hold one or lie inside an input folder, nor be a
// link or a special file, nor exist as another kind; a folder that exists and is not empty is
// replaced only with `overwrite` and only when accelcal wrote it (its marker). `flag` names the
// path in the message.
void CheckOutput(const std::string& path, OutputPath::Kind kind, const RunInputs& inputs,
                 bool overwrite, const std::string& flag) {
  if (path.empty()) throw InputError(flag + " is empty: name the output to write");
  ThrowIfError(CheckOutputPaths({{flag, path, kind}}, inputs));
  if (kind == OutputPath::Kind::kFolder) ThrowIfError(CheckFolderReplaceable(path, overwrite));
}

OutputPath::Kind OutputKind(const std::string& kind) {
  if (kind == "file") return OutputPath::Kind::kFile;
  if (kind == "folder") return OutputPath::Kind::kFolder;
  throw InputError("kind='" + kind + "' is not an output's kind; use kind='file' or 'folder'");
}

void CheckOutputPython(const py::object& path, const std::string& kind, const py::object& inputs,
                       const py::object& input_folders, bool overwrite, const std::string& flag) {
  CheckOutput(PathOf(path), OutputKind(kind), RunInputs{PathsOf(inputs), PathsOf(input_folders)},
              overwrite, flag);
}

// A folder of files (name -> text) written as the binaries write theirs: checked as above, then
// filled as a new folder beside `path` (with the marker) that replaces it once every file is
// written (WriteDirectoryAtomically); on any failure, a name that is not a plain file name among
// them, the new folder is removed and `path` left as it was.
void WriteFolder(const py::object& path_object, const std::map<std::string, std::string>& files,
                 const py::object& inputs, const py::object& input_folders, bool overwrite,
                 const std::string& flag) {
  const std::string path = PathOf(path_object);
  CheckOutput(path, OutputPath::Kind::kFolder, RunInputs{PathsOf(inputs), PathsOf(input_folders)},
              overwrite, flag);
  Status status;
  {
    py::gil_scoped_release release;
    status = WriteDirectoryAtomically(path, overwrite, [&](const std::string& folder) {
      for (const auto& [name, text] : files) {
        if (name.empty() || name == "." || name == ".." || name == kOutputFolderMarker ||
            name.find('/') != std::string::npos || name.find('\0') != std::string::npos) {
          return Status::Error(flag + "=" + path + ": '" + name +
                               "' is not a file name of its own inside the folder; nothing was "
                               "written");
        }
        ACCELCAL_RETURN_IF_ERROR(WriteFileAtomically(folder + "/" + name, text));
      }
      return Status::Ok();
    });
  }
  ThrowIfError(status);
}

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

Array Columns(const std::vector<std::array<double, 3>>& rows) {
  Array array({static_cast<py::ssize_t>(rows.size()), static_cast<py::ssize_t>(3)});
  auto view = array.mutable_unchecked<2>();
  for (size_t i = 0; i < rows.size(); ++i)
    for (int k = 0; k < 3; ++k) view(i, k) = rows[i][k];
  return array;
}

Array Vector(const double* values, size_t count) {
  Array array(static_cast<py::ssize_t>(count));
  std::copy(values, values + count, array.mutable_data());
  return array;
}

Array Matrix(const Eigen::MatrixXd& matrix) {
  Array array({static_cast<py::ssize_t>(matrix.rows()), static_cast<py::ssize_t>(matrix.cols())});
  auto view = array.mutable_unchecked<2>();
  for (Eigen::Index i = 0; i < matrix.rows(); ++i)
    for (Eigen::Index j = 0; j < matrix.cols(); ++j) view(i, j) = matrix(i, j);
  return array;
}

// An N x 3 array's rows; refuses another shape, naming `what`.
std::vector<std::array<double, 3>> Rows(const Array& array, const char* what) {
  if (array.ndim() != 2 || array.shape(1) != 3) {
    throw InputError(std::string(what) + ": expected an array of shape (N, 3), got " +
                     std::to_string(array.ndim()) + " dimensions");
  }
  std::vector<std::array<double, 3>> rows(array.shape(0));
  auto view = array.unchecked<2>();
  for (size_t i = 0; i < rows.size(); ++i)
    for (int k = 0; k < 3; ++k) rows[i][k] = view(i, k);
  return rows;
}

// A log read from its file (io/imu_log.h), with what the reader said and the files' checksums.
struct Log {
  TriadLog samples;
  ImuLogSource source;
  DataSource data;  // the log's file (and the gyroscope's), with their SHA-256
  std::string path;
  std::string gyro_log;
  bool from_files = false;  // read from its file(s), not made from arrays
};

std::shared_ptr<Log> ReadLog(const py::object& path_object, const std::string& columns,
                             double rate_hz, const std::string& time_unit,
                             const py::object& gyro_log_object, bool even) {
  auto log = std::make_shared<Log>();
  log->path = PathOf(path_object);
  log->from_files = true;
  if (!gyro_log_object.is_none()) log->gyro_log = PathOf(gyro_log_object);
  ImuLogReadOptions options;
  std::vector<ImuColumnChoice> choices;
  ThrowIfError(ParseImuColumnChoices(columns, &choices));
  options.columns = columns;
  options.rate_hz = rate_hz;
  options.time_unit = time_unit;
  options.gyroscope_path = log->gyro_log;
  Status status;
  {
    py::gil_scoped_release release;
    status = ReadImuLog(log->path, options, &log->samples,
                        even ? ImuLogSpacing::kEven : ImuLogSpacing::kAny, &log->source);
    if (status.ok()) {
      std::map<std::string, std::string> files = {{"log", log->path}};
      if (!log->gyro_log.empty()) files["log_gyroscope"] = log->gyro_log;
      status = DescribeMeasuredData("", files, &log->data);
    }
  }
  ThrowIfError(status);
  return log;
}

// A log from numpy arrays: written as the CSV text t_s,ax,ay,az[,gx,gy,gz] at full precision and
// parsed by the readers' own parser (io/imu_log.h's ParseImuLog), so that arrays pass exactly the
// checks a file does (finite values, increasing and even time, ...). `name` starts the messages;
// the SHA-256 is the text's, recorded as the input file `name`.
std::shared_ptr<Log> LogFromArrays(const Array& time_s, const Array& acc, const py::object& gyro,
                                   const std::string& name) {
  const std::vector<std::array<double, 3>> acc_rows = Rows(acc, "acc");
  std::vector<std::array<double, 3>> gyro_rows;
  if (!gyro.is_none()) gyro_rows = Rows(gyro.cast<Array>(), "gyro");
  if (time_s.ndim() != 1 || static_cast<size_t>(time_s.shape(0)) != acc_rows.size() ||
      (!gyro.is_none() && gyro_rows.size() != acc_rows.size())) {
    throw InputError(name +
                     ": time_s must be an array of shape (N,) and acc (and gyro) of shape "
                     "(N, 3), the same N");
  }
  auto log = std::make_shared<Log>();
  log->path = name;
  auto time = time_s.unchecked<1>();
  Status status;
  {
    py::gil_scoped_release release;
    std::string text = gyro_rows.empty() ? "t_s,ax,ay,az\n" : "t_s,ax,ay,az,gx,gy,gz\n";
    for (size_t j = 0; j < acc_rows.size(); ++j) {
      text += StringPrintf("%.17g,%.17g,%.17g,%.17g", time(j), acc_rows[j][0], acc_rows[j][1],
                           acc_rows[j][2]);
      if (!gyro_rows.empty()) {
        text +=
            StringPrintf(",%.17g,%.17g,%.17g", gyro_rows[j][0], gyro_rows[j][1], gyro_rows[j][2]);
      }
      text += "\n";
    }
    status =
        ParseImuLog(text, ImuLogReadOptions(), &log->samples, ImuLogSpacing::kEven, &log->source)
            .WithContext(name);
    log->data.files["log"] = InputFile{name, text.size(), Sha256Hex(text)};
  }
  ThrowIfError(status);
  return log;
}

// The unit a log's columns' names state stands for the one not given, and must agree with
// the one given (problems/problem_support.h's TakeStatedUnitOf, the binaries' rule).
std::string UnitFor(const py::object& given, const std::string& stated,
                    const std::vector<std::string>& known, const char* flag, const char* outputs,
                    const char* sensor, const std::string& fallback,
                    std::vector<std::string>* notes) {
  const bool is_stated = std::find(known.begin(), known.end(), stated) != known.end();
  const std::string columns = std::string("the ") + sensor + " columns' names say ";
  if (given.is_none()) {
    if (!is_stated) return fallback;
    if (stated != fallback) {
      notes->push_back(std::string(outputs) + " in " + stated + ", as " + columns + "(--" + flag +
                       ", not given, would be " + fallback + ")");
    }
    return stated;
  }
  const std::string unit = py::str(given);
  if (is_stated && stated != unit) {
    throw InputError("--" + std::string(flag) + "=" + unit + ", but " + columns + stated +
                     ": give --" + flag + "=" + stated + ", or rename the columns if --" + flag +
                     " is right");
  }
  return unit;
}

// One log's calibration (calibrate_imu --mode=ml) and the data it came from.
struct Calibration {
  CalibrateImuReport report;
  DataSource source;
  std::vector<std::string> input_files;  // the log's file(s): what its writers never replace
};

// The calibration's unknowns: the 9, then the effect terms of the model discovery settled on
// (the calibration file's parameter_order), their values and covariance in that order.
std::vector<double> TriadValueList(const TriadMlResult& ml) {
  std::vector<double> values(ml.parameters.begin(), ml.parameters.end());
  for (const int c : TriadTermsInOrder(ml)) values.push_back(ml.effects[c]);
  return values;
}

Array TriadValues(const TriadMlResult& ml) {
  const std::vector<double> values = TriadValueList(ml);
  return Vector(values.data(), values.size());
}

Eigen::MatrixXd MlCovariance(const TriadMlResult& ml) { return TriadMlCovariance(ml); }

std::vector<std::string> TriadNames(const TriadMlResult& ml) {
  std::vector<std::string> names;
  for (const TriadParameterInfo& info : TriadParameterInfos()) names.push_back(info.name);
  for (const int c : TriadTermsInOrder(ml)) names.push_back(TriadEffectCoefficientList()[c].name);
  return names;
}

// The calibration file's record, as calibrate_imu --calibration_out writes it.
CalibrationRecord RecordOf(const Calibration& calibration) {
  CalibrationRecord record = TriadCalibrationRecord(calibration.report, calibration.source);
  ThrowIfError(AddGyroscopeSection(calibration.report, &record));
  return record;
}

// calibrate's options checked as calibrate_imu checks its flags, without a log (for a script that
// calibrates many: tools/many_devices.py refuses bad options before any work).
void CheckOptions(double g, double alpha, const py::object& initial_offset, int window,
                  double init_rest_s, int interval_samples, int min_intervals,
                  double threshold_factor, double min_interval_s, double initial_gyro_gain) {
  CalibrateImuOptionValues values;
  values.g = g;
  values.alpha = alpha;
  values.window = window;
  values.init_rest_s = init_rest_s;
  values.interval_samples = interval_samples;
  values.min_intervals = min_intervals;
  values.threshold_factor = threshold_factor;
  values.min_interval_s = min_interval_s;
  values.initial_gyro_gain = initial_gyro_gain;
  values.initial_offset =
      initial_offset.is_none() ? std::string("auto") : std::string(py::str(initial_offset));
  ThrowIfError(ValidateCalibrateImuOptions(values));
}

std::shared_ptr<Calibration> Calibrate(const py::object& log_or_path, double g,
                                       const py::object& unit, double alpha,
                                       const std::string& noise, const std::string& detector,
                                       const py::object& initial_offset, int window,
                                       double init_rest_s, int interval_samples, int min_intervals,
                                       double threshold_factor, double min_interval_s,
                                       const py::object& gyro_unit, double initial_gyro_gain,
                                       const std::string& columns, double rate_hz,
                                       const std::string& time_unit, const py::object& gyro_log) {
  // calibrate_imu's validation of its flags (reporting/calibrate_imu_options.h), before the
  // log is read, as the binary's: the same ranges and rules, in its words.
  CheckOptions(g, alpha, initial_offset, window, init_rest_s, interval_samples, min_intervals,
               threshold_factor, min_interval_s, initial_gyro_gain);
  std::shared_ptr<Log> log;
  if (py::isinstance<Log>(log_or_path)) {
    log = log_or_path.cast<std::shared_ptr<Log>>();
  } else {
    log = ReadLog(log_or_path, columns, rate_hz, time_unit, gyro_log, true);
  }
  auto calibration = std::make_shared<Calibration>();
  if (log->from_files) {
    calibration->input_files.push_back(log->path);
    if (!log->gyro_log.empty()) calibration->input_files.push_back(log->gyro_log);
  }
  CalibrateImuReport& report = calibration->report;
  calibration->source = log->data;
  report.log_path = log->path;
  report.log_layout = log->source.layout;
  report.log_notes = log->source.notes;
  report.log_timing = log->source.timing;
  report.log_metadata = log->source.metadata;
  CalibrateImuOptions options;
  const std::string unit_name =
      UnitFor(unit, log->source.accelerometer_unit, {"count", "m/s^2", "g"}, "unit", "outputs",
              "accelerometer", "count", &report.log_notes);
  ThrowIfError(ParseTriadOutputUnit(unit_name, &options.session.unit).WithContext("--unit"));
  options.session.gravity_mps2 = g;
  // initial_offset: "auto" or a number, as --initial_offset.
  const std::string offset_text =
      initial_offset.is_none() ? std::string("auto") : std::string(py::str(initial_offset));
  if (offset_text != "auto") {
    options.session.offset.automatic = false;
    if (!ParseFiniteNumber(offset_text, &options.session.offset.value))
      throw InputError("--initial_offset='" + offset_text + "' is not a number");
  }
  options.session.detector.window_samples = window;
  options.session.detector.threshold_factor = threshold_factor;
  options.session.detector.min_interval_s = min_interval_s;
  ThrowIfError(ParseTriadNoiseChoice(noise, &options.session.noise).WithContext("--noise"));
  options.session.alpha = alpha;
  options.init_rest_s = init_rest_s;
  options.imu_tk_window_samples = window == 0 ? 101 : window;
  options.interval_samples = interval_samples;
  options.min_intervals = min_intervals;
  options.detector = detector;
  options.log_name = log->path;
  options.gyroscope_log_name = log->gyro_log;
  if (log->samples.has_gyroscope()) {
    report.gyroscope_samples = log->samples.gyroscope.size();
    report.gyroscope_path = log->gyro_log;
    if (!log->gyro_log.empty())
      report.gyroscope_sha256 = log->data.files.at("log_gyroscope").sha256;
    report.log_notes.push_back("gyroscope: read (" + std::to_string(log->samples.gyroscope.size()) +
                               " samples); calibrated below by maximum likelihood");
    const std::string gyroscope_unit =
        UnitFor(gyro_unit, log->source.gyroscope_unit, {"count", "rad/s", "deg/s"}, "gyro_unit",
                "gyroscope outputs", "gyroscope", "count", &report.log_notes);
    ThrowIfError(ParseGyroscopeOutputUnit(gyroscope_unit, &options.gyroscope_unit)
                     .WithContext("--gyro_unit"));
    options.initial_gyro_gain = initial_gyro_gain;
    options.gyroscope_asked =
        !log->gyro_log.empty() || !gyro_unit.is_none() || initial_gyro_gain > 0.0;
  } else if (!gyro_unit.is_none() || initial_gyro_gain > 0.0) {
    throw InputError(log->path +
                     ": --gyro_unit and --initial_gyro_gain are for the gyroscope, and the log has "
                     "none: give imu_tk's gyroscope file with --gyro_log=FILE, or a log with "
                     "gyroscope columns (gx, gy, gz; docs/log-layouts.md)");
  }
  report.log_sha256 = log->data.files.at("log").sha256;
  report.sample_count = log->samples.size();
  report.first_t_s = log->samples.timestamp_s.front();
  report.last_t_s = log->samples.timestamp_s.back();
  Status status;
  {
    py::gil_scoped_release release;
    status = CalibrateImuModeMl(log->samples, options, &report);
  }
  ThrowIfError(status);
  return calibration;
}

// The triad's (and the gyroscope's) parameters and covariance for apply: from a calibration
// file, or from a Calibration through the record its file would hold.
CalibrationRecord RecordFor(const py::object& calibration, std::string* name) {
  if (py::isinstance<Calibration>(calibration)) {
    *name = "the calibration";
    return RecordOf(calibration.cast<const Calibration&>());
  }
  *name = PathOf(calibration);
  CalibrationRecord record;
  ThrowIfError(ReadCalibrationFile(*name, &record));
  return record;
}

// A sensor's words and range, for apply's refusal of a damaged sample (problems/apply.cc):
// 10^5 g for an accelerometer, 10^5 rad/s for a gyroscope.
struct SensorRange {
  const char* symbol;
  const char* unit;
  const char* sensor;
  double largest;
};
constexpr SensorRange kAccelerometerRange = {"a", "m/s^2", "accelerometer", 1e6};
constexpr SensorRange kGyroscopeRange = {"w", "rad/s", "gyroscope", 1e5};

// Every row of `outputs` corrected by `correct` (value, covariance), without the GIL:
// (values (N, 3), sigma (N, 3)), each sample finite and within the sensor's range, as apply
// requires.
template <typename Correct>
py::tuple Corrected(const std::vector<std::array<double, 3>>& outputs, const Correct& correct,
                    const SensorRange& range) {
  std::vector<Eigen::Vector3d> values(outputs.size());
  std::vector<Eigen::Matrix3d> covariances(outputs.size());
  {
    py::gil_scoped_release release;
    for (size_t j = 0; j < outputs.size(); ++j) correct(outputs[j], &values[j], &covariances[j]);
  }
  Array value_array({static_cast<py::ssize_t>(values.size()), static_cast<py::ssize_t>(3)});
  Array sigma_array({static_cast<py::ssize_t>(values.size()), static_cast<py::ssize_t>(3)});
  auto value = value_array.mutable_unchecked<2>();
  auto sigma = sigma_array.mutable_unchecked<2>();
  for (size_t j = 0; j < values.size(); ++j) {
    const double norm = values[j].norm();
    if (!values[j].allFinite() || !covariances[j].diagonal().allFinite() ||
        !(norm <= range.largest)) {
      throw InputError(StringPrintf(
          "sample %zu corrects to |%s| = %.3g %s, beyond any %s's range (%g %s): a damaged "
          "value; remove or repair the sample",
          j + 1, range.symbol, norm, range.unit, range.sensor, range.largest, range.unit));
    }
    for (int k = 0; k < 3; ++k) {
      value(j, k) = values[j][k];
      sigma(j, k) = std::sqrt(covariances[j](k, k));
    }
  }
  return py::make_tuple(value_array, sigma_array);
}

// The calibration's accelerometer correction of one output, its effect terms applied (apply's,
// estimation/tilt_table/calibration_correction.h); an output it cannot correct is refused.
CorrectedTriadSample CorrectedOutput(const TriadCalibrationModel& model,
                                     const std::array<double, 3>& output, size_t row) {
  CorrectedTriadSample sample;
  if (!CorrectTriad(model, output, &sample)) {
    throw InputError(StringPrintf(
        "acc row %zu has no specific force near the 9-parameter correction's under the "
        "calibration's effect terms: a damaged value, or a calibration of another sensor",
        row + 1));
  }
  return sample;
}

py::tuple Apply(const py::object& calibration, const Array& acc) {
  std::string name;
  const CalibrationRecord record = RecordFor(calibration, &name);
  TriadCalibrationModel model;
  ThrowIfError(TriadCalibrationModelOf(record, name, &model));
  size_t row = 0;
  const auto correct = [&](const std::array<double, 3>& output, Eigen::Vector3d* value,
                           Eigen::Matrix3d* value_covariance) {
    const CorrectedTriadSample sample = CorrectedOutput(model, output, row++);
    *value = sample.acceleration;
    *value_covariance = sample.covariance;
  };
  py::tuple corrected = Corrected(Rows(acc, "acc"), correct, kAccelerometerRange);
  // apply's check that the outputs are in the calibration's unit (reporting/apply_checks.h):
  // corrected, they read about 1 g.
  const Array values = corrected[0].cast<Array>();
  auto view = values.unchecked<2>();
  std::vector<double> magnitude(values.shape(0));
  for (size_t j = 0; j < magnitude.size(); ++j)
    magnitude[j] =
        std::sqrt(view(j, 0) * view(j, 0) + view(j, 1) * view(j, 1) + view(j, 2) * view(j, 2));
  if (!magnitude.empty()) {
    std::nth_element(magnitude.begin(), magnitude.begin() + magnitude.size() / 2, magnitude.end());
    ThrowIfError(CheckMedianMagnitude("acc", name, magnitude[magnitude.size() / 2],
                                      record.gravity_mps2, record.output_unit));
  }
  return corrected;
}

py::tuple ApplyGyroscope(const py::object& calibration, const Array& gyro, const py::object& acc) {
  std::string name;
  const CalibrationRecord record = RecordFor(calibration, &name);
  if (!record.has_gyroscope) {
    throw InputError(name +
                     " has no gyroscope section: calibrate a log with the gyroscope's "
                     "columns (or gyro_log) to correct a gyroscope");
  }
  GyroscopeCalibrationModel model;
  ThrowIfError(GyroscopeCalibrationModelOf(record.gyroscope, &model).WithContext(name));
  const std::vector<std::array<double, 3>> rows = Rows(gyro, "gyro");
  // A g-sensitivity reads the specific force of the same sample: the accelerometer's rows,
  // corrected by the calibration's accelerometer part.
  std::vector<Eigen::Vector3d> force(rows.size(), Eigen::Vector3d::Zero());
  if (model.needs_specific_force()) {
    if (acc.is_none()) {
      throw InputError(name +
                       "'s gyroscope carries a g-sensitivity (gyroscope_g_sensitivity_*), "
                       "which reads the specific force of each sample: give acc= (the same "
                       "samples' accelerometer rows, N x 3, the calibration's output unit)");
    }
    const std::vector<std::array<double, 3>> acc_rows = Rows(acc.cast<Array>(), "acc");
    if (acc_rows.size() != rows.size()) {
      throw InputError(StringPrintf("acc has %zu rows and gyro %zu: give the same samples' rows",
                                    acc_rows.size(), rows.size()));
    }
    TriadCalibrationModel triad;
    ThrowIfError(TriadCalibrationModelOf(record, name, &triad));
    for (size_t j = 0; j < rows.size(); ++j)
      force[j] = CorrectedOutput(triad, acc_rows[j], j).acceleration;
  }
  size_t row = 0;
  const auto correct = [&](const std::array<double, 3>& output, Eigen::Vector3d* value,
                           Eigen::Matrix3d* value_covariance) {
    const CorrectedGyroscopeSample sample = CorrectGyroscope(model, output, force[row++]);
    *value = sample.angular_rate;
    *value_covariance = sample.covariance;
  };
  return Corrected(rows, correct, kGyroscopeRange);
}

// A gyroscope's maximum-likelihood calibration, as the Python object Calibration.gyroscope.
struct GyroscopeView {
  std::shared_ptr<Calibration> owner;
  const CalibrateImuReport& report() const { return owner->report; }
};

py::dict Parameters(const std::vector<std::string>& names, const double* values) {
  py::dict dict;
  for (size_t i = 0; i < names.size(); ++i) dict[py::str(names[i])] = values[i];
  return dict;
}

// The fit's unknowns: the 9, the offsets, then its effect terms (the JSON's parameter_order).
std::vector<double> GyroscopeValues(const GyroscopeMlResult& g) {
  std::vector<double> values(g.parameters.begin(), g.parameters.end());
  values.insert(values.end(), g.offset.begin(), g.offset.end());
  for (const int c : g.effects_estimated) values.push_back(g.effects[c]);
  return values;
}

}  // namespace
}  // namespace accelcal

PYBIND11_MODULE(accelcal, m) {
  using namespace accelcal;
  m.doc() =
      "accelcal's triad calibration from Python: read_log, calibrate (calibrate_imu "
      "--mode=ml), apply and apply_gyroscope (apply's correction). docs/python.md.";
  // The calibration files' command_line: the writer, not a shell command.
  static char writer[] = "python3:accelcal";
  static char* writer_argv[] = {writer};
  RecordCommandLine(1, writer_argv);
  m.attr("__version__") = AccelcalVersion();
  // What --version prints after the binary's name: version, commit and build type.
  m.attr("__git_commit__") = AccelcalGitCommit();
  m.attr("__build_type__") = AccelcalBuildType();
  m.attr("build_info") = BuildInfoLine();
  static py::exception<InputError> error(m, "Error", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr pointer) {
    try {
      if (pointer) std::rethrow_exception(pointer);
    } catch (const InputError& e) {
      error(e.what());
    }
  });

  py::class_<Log, std::shared_ptr<Log>>(m, "Log",
                                        "An IMU log read from its file (read_log): samples in "
                                        "the sensor's own unit.")
      .def(py::init(&LogFromArrays), py::arg("time_s"), py::arg("acc"),
           py::arg("gyro") = py::none(), py::arg("name") = "numpy arrays",
           "A log from arrays: time_s (N,) in s, acc (N, 3) and gyro (N, 3) or None in the "
           "sensor's units, checked as a file's samples are (finite, time increasing and "
           "evenly spaced). Messages start with `name`; sha256 is that of the CSV text the "
           "arrays were written as.")
      .def_property_readonly(
          "time_s",
          [](const Log& log) { return Vector(log.samples.timestamp_s.data(), log.samples.size()); },
          "Time stamps, s, shape (N,).")
      .def_property_readonly(
          "acc", [](const Log& log) { return Columns(log.samples.output); },
          "Accelerometer outputs x, y, z in the log's unit, shape (N, 3).")
      .def_property_readonly(
          "gyro",
          [](const Log& log) -> py::object {
            if (!log.samples.has_gyroscope()) return py::none();
            return Columns(log.samples.gyroscope);
          },
          "Gyroscope outputs, shape (N, 3), or None.")
      .def_property_readonly(
          "unit",
          [](const Log& log) -> py::object {
            if (log.source.accelerometer_unit.empty()) return py::none();
            return py::str(log.source.accelerometer_unit);
          },
          "The accelerometer's unit the columns' names state, or None.")
      .def_property_readonly(
          "gyro_unit",
          [](const Log& log) -> py::object {
            if (log.source.gyroscope_unit.empty()) return py::none();
            return py::str(log.source.gyroscope_unit);
          },
          "The gyroscope's unit the columns' names state, or None.")
      .def_property_readonly("path", [](const Log& log) { return log.path; })
      .def_property_readonly("layout", [](const Log& log) { return log.source.layout; })
      .def_property_readonly("notes", [](const Log& log) { return log.source.notes; })
      .def_property_readonly(
          "source",
          [](const Log& log) {
            py::dict files;
            for (const auto& [key, file] : log.data.files) {
              py::dict entry;
              entry["path"] = file.path;
              entry["bytes"] = file.bytes;
              entry["sha256"] = file.sha256;
              files[py::str(key)] = entry;
            }
            return files;
          },
          "The files read: {'log': {'path', 'bytes', 'sha256'}[, 'log_gyroscope': ...]}.")
      .def_property_readonly("sha256",
                             [](const Log& log) { return log.data.files.at("log").sha256; })
      .def("__len__", [](const Log& log) { return log.samples.size(); })
      .def("__repr__", [](const Log& log) {
        return "<accelcal.Log " + log.path + ": " + std::to_string(log.samples.size()) +
               " samples" + (log.samples.has_gyroscope() ? ", gyroscope" : "") + ">";
      });

  py::class_<GyroscopeView>(m, "GyroscopeCalibration",
                            "The gyroscope's maximum-likelihood calibration w = T K (u - b).")
      .def_property_readonly("names",
                             [](const GyroscopeView& v) { return v.report().gyroscope_ml.names; })
      .def_property_readonly("units",
                             [](const GyroscopeView& v) { return v.report().gyroscope_ml.units; })
      .def_property_readonly("values",
                             [](const GyroscopeView& v) {
                               const std::vector<double> values =
                                   GyroscopeValues(v.report().gyroscope_ml);
                               return Vector(values.data(), values.size());
                             })
      .def_property_readonly("parameters",
                             [](const GyroscopeView& v) {
                               const std::vector<double> values =
                                   GyroscopeValues(v.report().gyroscope_ml);
                               return Parameters(v.report().gyroscope_ml.names, values.data());
                             })
      .def_property_readonly(
          "covariance",
          [](const GyroscopeView& v) { return Matrix(v.report().gyroscope_ml.covariance); })
      .def_property_readonly("stddev",
                             [](const GyroscopeView& v) {
                               const Eigen::VectorXd d =
                                   v.report().gyroscope_ml.covariance.diagonal().cwiseSqrt();
                               return Vector(d.data(), d.size());
                             })
      .def_property_readonly(
          "chi2", [](const GyroscopeView& v) { return v.report().gyroscope_ml.chi2_gyroscope; })
      .def_property_readonly("dof",
                             [](const GyroscopeView& v) {
                               return v.report().gyroscope_ml.gyroscope_degrees_of_freedom;
                             })
      .def_property_readonly(
          "p_value",
          [](const GyroscopeView& v) { return v.report().gyroscope_ml.gyroscope_p_value; })
      .def_property_readonly(
          "unit",
          [](const GyroscopeView& v) {
            return std::string(GyroscopeOutputUnitName(v.report().gyroscope_unit));
          })
      .def_property_readonly(
          "verdict", [](const GyroscopeView& v) { return v.report().gyroscope_discovery.verdict; })
      .def_property_readonly("verdict_kind", [](const GyroscopeView& v) {
        return std::string(VerdictCode(v.report().gyroscope_discovery.verdict_code));
      });

  py::class_<Calibration, std::shared_ptr<Calibration>>(
      m, "Calibration",
      "A triad's maximum-likelihood calibration a = T K (u - b) (calibrate_imu --mode=ml).")
      .def_property_readonly("names", [](const Calibration& c) { return TriadNames(c.report.ml); })
      .def_property_readonly(
          "units",
          [](const Calibration& c) {
            std::vector<std::string> units;
            for (int i = 0; i < kTriadParameterCount; ++i)
              units.push_back(TriadParameterUnit(i, c.report.unit));
            for (const int t : TriadTermsInOrder(c.report.ml)) {
              units.push_back(TriadEffectUnit(t, TriadOutputUnitName(c.report.unit)));
            }
            return units;
          })
      .def_property_readonly("values",
                             [](const Calibration& c) { return TriadValues(c.report.ml); })
      .def_property_readonly("parameters",
                             [](const Calibration& c) {
                               const std::vector<double> values = TriadValueList(c.report.ml);
                               return Parameters(TriadNames(c.report.ml), values.data());
                             })
      .def_property_readonly("covariance",
                             [](const Calibration& c) { return Matrix(MlCovariance(c.report.ml)); })
      .def_property_readonly("stddev",
                             [](const Calibration& c) {
                               const Eigen::VectorXd d =
                                   MlCovariance(c.report.ml).diagonal().cwiseSqrt();
                               return Vector(d.data(), d.size());
                             })
      .def_property_readonly("chi2", [](const Calibration& c) { return c.report.ml.chi2; })
      .def_property_readonly("dof",
                             [](const Calibration& c) { return c.report.ml.degrees_of_freedom; })
      .def_property_readonly("p_value", [](const Calibration& c) { return c.report.ml.p_value; })
      .def_property_readonly("poses", [](const Calibration& c) { return c.report.ml.pose_count; })
      .def_property_readonly("samples",
                             [](const Calibration& c) { return c.report.ml_sample_count; })
      .def_property_readonly(
          "noise_model",
          [](const Calibration& c) { return c.report.allan_noise ? "allan" : "white"; })
      .def_property_readonly("detector", [](const Calibration& c) { return c.report.detector; })
      .def_property_readonly(
          "unit",
          [](const Calibration& c) { return std::string(TriadOutputUnitName(c.report.unit)); })
      .def_property_readonly("g",
                             [](const Calibration& c) { return c.report.ml_options.gravity_mps2; })
      .def_property_readonly(
          "verdict", [](const Calibration& c) { return c.report.discovery.verdict; },
          "Discovery's verdict, the text calibrate_imu prints after "
          "'Verdict (kind): '.")
      .def_property_readonly(
          "verdict_kind",
          [](const Calibration& c) {
            return std::string(VerdictCode(c.report.discovery.verdict_code));
          },
          "explained, missing, unexplained or cannot_tell_apart.")
      .def_property_readonly("notes", [](const Calibration& c) { return c.report.log_notes; })
      .def_property_readonly("log_path", [](const Calibration& c) { return c.report.log_path; })
      .def_property_readonly("log_sha256", [](const Calibration& c) { return c.report.log_sha256; })
      .def_property_readonly(
          "gyroscope",
          [](const std::shared_ptr<Calibration>& c) -> py::object {
            if (!c->report.has_gyroscope_ml) return py::none();
            return py::cast(GyroscopeView{c});
          },
          "The gyroscope's calibration (GyroscopeCalibration), or None.")
      .def(
          "json",
          [](const Calibration& c) {
            nlohmann::json json = CalibrateImuJson(c.report);
            AddProvenanceJson(c.source, &json);
            std::string text;
            ThrowIfError(JsonText(json, &text));
            return text;
          },
          "The JSON calibrate_imu --json writes for the same run (text).")
      .def(
          "text", [](const Calibration& c) { return CalibrateImuTable(c.report, false); },
          "The table calibrate_imu prints for the same run.")
      .def(
          "file_text",
          [](const Calibration& c) {
            std::string text;
            ThrowIfError(JsonText(CalibrationJson(RecordOf(c)), &text));
            return text;
          },
          "The text write() writes: the calibration file apply reads.")
      .def(
          "write",
          [](const Calibration& c, const py::object& path) {
            // The binaries' guard first (calibrate_imu --calibration_out's): never an input of
            // this calibration (by path, link or identity), a folder or a special file.
            const std::string name = PathOf(path);
            CheckOutput(name, OutputPath::Kind::kFile, RunInputs{c.input_files, {}}, false, "path");
            std::string text;
            ThrowIfError(JsonText(CalibrationJson(RecordOf(c)), &text));
            py::gil_scoped_release release;
            ThrowIfError(WriteFileAtomically(name, text));
          },
          py::arg("path"),
          "Writes the calibration file apply reads (calibrate_imu --calibration_out's), "
          "atomically; refuses (accelcal.Error) a path that is an input of the calibration, a "
          "folder, a link or a special file, as the binaries do.")
      .def("__repr__", [](const Calibration& c) {
        return "<accelcal.Calibration " + c.report.log_path + ": " +
               std::to_string(c.report.ml.pose_count) + " poses, verdict " +
               VerdictCode(c.report.discovery.verdict_code) + ">";
      });

  m.def("read_log", &ReadLog, py::arg("path"), py::arg("columns") = "", py::arg("rate_hz") = 0.0,
        py::arg("time_unit") = "", py::arg("gyro_log") = py::none(), py::arg("even") = true,
        "Reads an IMU log in any layout calibrate_imu reads (docs/log-layouts.md); the keywords "
        "are its flags --columns, --rate_hz, --time_unit, --gyro_log. even=False accepts uneven "
        "time steps (apply's reading).");
  m.def("calibrate", &Calibrate, py::arg("log"), py::arg("g") = 9.81, py::arg("unit") = py::none(),
        py::arg("alpha") = 0.01, py::arg("noise") = "auto", py::arg("detector") = "noise_floor",
        py::arg("initial_offset") = "auto", py::arg("window") = 0, py::arg("init_rest_s") = 50.0,
        py::arg("interval_samples") = 100, py::arg("min_intervals") = 12,
        py::arg("threshold_factor") = 10.0, py::arg("min_interval_s") = 1.0,
        py::arg("gyro_unit") = py::none(), py::arg("initial_gyro_gain") = 0.0,
        py::arg("columns") = "", py::arg("rate_hz") = 0.0, py::arg("time_unit") = "",
        py::arg("gyro_log") = py::none(),
        "calibrate_imu --mode=ml on a Log or a log's path; the keywords are its flags (window "
        "0: its default). Returns a Calibration.");
  m.def("check_options", &CheckOptions, py::arg("g") = 9.81, py::arg("alpha") = 0.01,
        py::arg("initial_offset") = "auto", py::arg("window") = 0, py::arg("init_rest_s") = 50.0,
        py::arg("interval_samples") = 100, py::arg("min_intervals") = 12,
        py::arg("threshold_factor") = 10.0, py::arg("min_interval_s") = 1.0,
        py::arg("initial_gyro_gain") = 0.0,
        "calibrate's options checked as calibrate_imu checks its flags, without a log: raises "
        "accelcal.Error with the binary's message.");
  m.def("check_output", &CheckOutputPython, py::arg("path"), py::arg("kind") = "file",
        py::arg("inputs") = py::tuple(), py::arg("input_folders") = py::tuple(),
        py::arg("overwrite") = false, py::arg("flag") = "path",
        "The binaries' check of an output path (io/output_paths.h), before any work: raises "
        "accelcal.Error when `path` (kind 'file' or 'folder') is, holds or lies inside one of "
        "`inputs` (files) or `input_folders` (by real path or identity), is a link or a special "
        "file, exists as another kind, or has no parent folder; a folder that exists and is not "
        "empty also needs overwrite=True and accelcal's marker. `flag` names it in the message.");
  m.def("write_folder", &WriteFolder, py::arg("path"), py::arg("files"),
        py::arg("inputs") = py::tuple(), py::arg("input_folders") = py::tuple(),
        py::arg("overwrite") = false, py::arg("flag") = "path",
        "Writes `files` (name -> text) as the folder `path`, as the binaries write theirs: "
        "checked as check_output(kind='folder') does, filled beside it with accelcal's marker "
        "and swapped in whole; on any failure nothing changes. Raises accelcal.Error.");
  m.def("apply", &Apply, py::arg("calibration"), py::arg("acc"),
        "a = T K (u - b) of every row of acc (N, 3, the calibration's output unit), with a "
        "Calibration or a calibration file's path: (corrected m/s^2 (N, 3), sigma (N, 3)), the "
        "numbers of apply's CSV.");
  m.def("apply_gyroscope", &ApplyGyroscope, py::arg("calibration"), py::arg("gyro"),
        py::arg("acc") = py::none(),
        "w = T K (u - b) of every row of gyro (N, 3) by the calibration's gyroscope section, its "
        "effect terms applied: (rad/s (N, 3), sigma (N, 3)). acc (N, 3), the same samples' "
        "accelerometer rows, is needed when the section carries a g-sensitivity.");
}
