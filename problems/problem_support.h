#ifndef ACCELCAL_PROBLEMS_PROBLEM_SUPPORT_H_
#define ACCELCAL_PROBLEMS_PROBLEM_SUPPORT_H_

// What every problem binary does around its pipeline: parse flags (an unknown flag, a
// malformed value or a stray argument is bad input: one line, exit 2), show only the binary's own
// flags under --help, keep glog quiet unless --v is raised, and turn a failed Status into one line
// on stderr with exit status 2.

#include <gflags/gflags.h>
#include <glog/logging.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <initializer_list>
#include <iostream>
#include <map>
#include <new>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "common/build_info.h"
#include "common/format.h"
#include "common/line_text.h"
#include "common/measurements.h"
#include "common/status.h"
#include "io/atomic_file.h"
#include "io/cleanup.h"
#include "io/course_data.h"
#include "io/csv_reader.h"
#include "io/imu_log.h"
#include "io/input_file.h"
#include "io/json_file.h"
#include "io/output_paths.h"
#include "io/provenance.h"
#include "io/run_conditions.h"
#include "io/scenario_json.h"
#include "reporting/progress_printer.h"
#include "simulation/scenario.h"

namespace accelcal {

constexpr int kExitBadInput = 2;

// A message as one readable line: control characters become blanks or \xNN escapes, and a
// message longer than a screenful keeps its start and its end (what is wrong, and what to do).
inline std::string OneLine(const std::string& message) {
  constexpr size_t kMaxBytes = 600;
  std::string line;
  for (const char c : message) {
    const unsigned char byte = static_cast<unsigned char>(c);
    if (c == '\n' || c == '\r' || c == '\t') {
      line += ' ';
    } else if (byte < 0x20 || byte == 0x7f) {
      line += StringPrintf("\\x%02X", byte);
    } else {
      line += c;
    }
  }
  if (line.size() > kMaxBytes) {
    line = line.substr(0, kMaxBytes / 2) + " [...] " + line.substr(line.size() - kMaxBytes / 2);
  }
  return line;
}

inline int ExitWithError(const char* program, const Status& status) {
  std::cerr << program << ": error: " << OneLine(status.message()) << "\n";
  return kExitBadInput;
}

// What stdout received: the table printed is the only result of a run without --json, so a
// write to it that failed (a full disk, ENOSPC; a pipe whose reader is gone, EPIPE; EIO) is a
// failure like a failed file write: one line on stderr and exit status 2, never a silent 0.
// Flushes stdout (std::cout writes through it) and returns `exit_status` when every write
// reached it; a run that failed already keeps its own status and its one line.
inline int CheckStdoutWritten(const char* program, int exit_status) {
  errno = 0;
  std::cout.flush();
  const bool flush_failed = std::fflush(stdout) != 0;
  int error = flush_failed ? errno : 0;
  if (!flush_failed && !std::ferror(stdout) && !std::cout.fail()) return exit_status;
  if (exit_status != 0) return exit_status;
  // A write that failed earlier in the run left no errno behind: one more byte, to an output
  // already lost or cut, says why (ENOSPC, EPIPE, EIO).
  if (error == 0 && ::write(STDOUT_FILENO, "\n", 1) < 0) error = errno;
  std::cerr << program << ": error: writing the results to stdout failed ("
            << (error != 0 ? std::strerror(error) : "an earlier write failed")
            << "): the printed output is lost or incomplete; free space on the device, or keep "
               "the reader of the pipe open, and run again (or write --json where the binary has "
               "it)\n";
  return kExitBadInput;
}

// main() of every binary: `run` with no exception escaping, and its stdout checked
// (CheckStdoutWritten). Running out of memory is one line and exit status 2 like any other
// failure; anything else is a bug, said as such. SIGPIPE is ignored so that a write into a
// closed pipe fails with EPIPE and is said, instead of ending the process without a word.
inline int GuardedMain(const char* program, int (*run)(int, char**), int argc, char** argv) {
  std::signal(SIGPIPE, SIG_IGN);
  int exit_status = 0;
  try {
    exit_status = run(argc, argv);
  } catch (const std::bad_alloc&) {
    // clang-format off
    exit_status = ExitWithError(program, Status::Error("not enough memory for this input; free memory, raise the limit (ulimit -v) or use less data"));
    // clang-format on
  } catch (const std::exception& exception) {
    exit_status =
        ExitWithError(program, Status::Error(std::string("internal error (") + exception.what() +
                                             "); please report it with the command line"));
  }
  return CheckStdoutWritten(program, exit_status);
}

// A flag holding a comma-separated list of at most 20 numbers, each accepted by `valid`; a
// value it refuses is named with what it should be, `expected` ("a number in (0, 0.5)").
inline Status ParseNumberList(const char* flag, const std::string& text, bool (*valid)(double),
                              const char* expected, std::vector<double>* values) {
  values->clear();
  std::istringstream stream(text);
  for (std::string item; std::getline(stream, item, ',');) {
    double value;
    if (!ParseFiniteNumber(item, &value) || !valid(value)) {
      return Status::Error(std::string(flag) + ": '" + item.substr(0, 40) + "' is not " + expected);
    }
    values->push_back(value);
  }
  if (values->empty()) return Status::Error(std::string(flag) + " is empty");
  if (values->size() > 20) return Status::Error(std::string(flag) + " lists more than 20 values");
  return Status::Ok();
}

// The allowed range of a numeric flag, declared once beside the flag:
//   ACCELCAL_FLAG_RANGE(bins, 4, 1000);          closed: 4 <= --bins <= 1000
//   ACCELCAL_FLAG_OPEN_RANGE(alpha, 0.0, 0.5);   open:   0 < --alpha < 0.5
// gflags checks it whenever the flag is set, and the message names the range.
struct FlagRange {
  double low = 0.0;
  double high = 0.0;
  bool open = false;
  std::string Text() const {
    return StringPrintf(open ? "(%.10g, %.10g)" : "[%.10g, %.10g]", low, high);
  }
  bool Contains(double value) const {
    return open ? (value > low && value < high) : (value >= low && value <= high);
  }
};

inline std::map<std::string, FlagRange>& FlagRanges() {
  static std::map<std::string, FlagRange> ranges;
  return ranges;
}

template <typename T>
bool FlagInRange(const char* name, T value) {
  const auto found = FlagRanges().find(name);
  return found == FlagRanges().end() || found->second.Contains(static_cast<double>(value));
}

template <typename T>
bool RegisterFlagRange(const char* name, const T* flag, double low, double high, bool open) {
  FlagRanges()[name] = FlagRange{low, high, open};
  return gflags::RegisterFlagValidator(flag, &FlagInRange<T>);
}

#define ACCELCAL_FLAG_RANGE(name, low, high)                      \
  static const bool accelcal_flag_range_##name [[maybe_unused]] = \
      ::accelcal::RegisterFlagRange(#name, &FLAGS_##name, low, high, false)
#define ACCELCAL_FLAG_OPEN_RANGE(name, low, high)                 \
  static const bool accelcal_flag_range_##name [[maybe_unused]] = \
      ::accelcal::RegisterFlagRange(#name, &FLAGS_##name, low, high, true)

// A flag that was renamed, declared beside the new one so that the old name gets one line
// saying so rather than "unknown flag":
//   ACCELCAL_RENAMED_FLAG(num_threads, threads);   "--num_threads was renamed --threads"
inline std::map<std::string, std::string>& RenamedFlags() {
  static std::map<std::string, std::string> renamed;
  return renamed;
}

inline bool RegisterRenamedFlag(const char* old_name, const char* new_name) {
  RenamedFlags()[old_name] = new_name;
  return true;
}

#define ACCELCAL_RENAMED_FLAG(old_name, new_name)                       \
  static const bool accelcal_renamed_flag_##old_name [[maybe_unused]] = \
      ::accelcal::RegisterRenamedFlag(#old_name, #new_name)

// --threads, defined by every binary that runs threads, with one meaning and one help text;
// `default_value` may differ between binaries. ThreadCount turns it into a count.
// clang-format off
#define ACCELCAL_DEFINE_THREADS_FLAG(default_value)                                                  \
  DEFINE_int32(threads, default_value, "Threads to use, 0 to 256; 0: all cores. The results do not depend on it."); \
  ACCELCAL_FLAG_RANGE(threads, 0, 256);                                                              \
  ACCELCAL_RENAMED_FLAG(num_threads, threads)
// clang-format on

// The number of threads --threads asks for: itself, or all cores for 0.
inline int ThreadCount(int threads_flag) {
  if (threads_flag > 0) return threads_flag;
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

// Checks every argument before gflags sees it: gflags ends the program with status 1
// (and a multi-line message) on an unknown flag or a malformed value, and ignores
// stray arguments. Returns the one-line message for the first bad argument, or "".
inline std::string FirstBadArgument(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string argument = argv[i];
    if (argument == "--") break;
    if (argument.size() < 2 || argument[0] != '-') {
      return "unknown flag or argument '" + OneLine(argument.substr(0, 80)) + "'";
    }
    const std::string body = argument.substr(argument[1] == '-' ? 2 : 1);
    const size_t equals = body.find('=');
    std::string name = body.substr(0, equals);
    // gflags' own ways of reading flags end the program with status 1 and a message of
    // theirs on a bad value; every flag is given on the command line instead.
    if (name == "flagfile" || name == "fromenv" || name == "tryfromenv" || name == "undefok") {
      return "--" + name + " is not supported; give each flag on the command line";
    }
    gflags::CommandLineFlagInfo info;
    if (!gflags::GetCommandLineFlagInfo(name.c_str(), &info)) {
      const auto renamed = RenamedFlags().find(name);
      if (renamed != RenamedFlags().end()) {
        return "--" + name + " was renamed --" + renamed->second;
      }
      // --nofoo is gflags' spelling of --foo=false for booleans.
      if (name.rfind("no", 0) == 0 && gflags::GetCommandLineFlagInfo(name.c_str() + 2, &info) &&
          info.type == "bool" && equals == std::string::npos) {
        continue;
      }
      return "unknown flag or argument '" + OneLine(argument.substr(0, 80)) + "'";
    }
    std::string value;
    if (equals != std::string::npos) {
      value = body.substr(equals + 1);
    } else if (info.type == "bool") {
      continue;
    } else if (i + 1 < argc) {
      value = argv[++i];  // "--flag value"
    } else {
      return "flag --" + name + " needs a value";
    }
    // Setting the value now checks it; ParseCommandLineFlags sets it again below.
    if (gflags::SetCommandLineOption(name.c_str(), value.c_str()).empty()) {
      const auto range = FlagRanges().find(name);
      return "--" + name + "='" + OneLine(value.substr(0, 80)) + "' is not a valid " + info.type +
             (range == FlagRanges().end() ? std::string() : " in " + range->second.Text());
    }
  }
  return "";
}

// Returns false (after printing one line) when the command line is not usable.
// `source_fragment` selects the flags --help lists (the binary's own source file).
inline bool InitProblem(const char* program, const char* usage, const char* source_fragment,
                        int* argc, char*** argv) {
  // First, before any thread starts: an interruption removes our temporary files.
  InstallInterruptCleanup();
  // The provenance's checksums are of the bytes the readers parsed (io/input_file.h).
  StartRecordingInputReads();
  RecordCommandLine(*argc, *argv);
  gflags::SetUsageMessage(usage);
  gflags::SetVersionString(BuildInfoLine());
  for (int i = 1; i < *argc; ++i) {
    const char* argument = (*argv)[i];
    if (std::strcmp(argument, "--help") == 0 || std::strcmp(argument, "-help") == 0 ||
        std::strcmp(argument, "-h") == 0) {
      gflags::ShowUsageWithFlagsRestrict(program, source_fragment);
      std::exit(CheckStdoutWritten(program, 0));
    }
  }
  const std::string bad_argument = FirstBadArgument(*argc, *argv);
  if (!bad_argument.empty()) {
    std::cerr << program << ": error: " << bad_argument << "; see " << program << " --help\n";
    return false;
  }
  gflags::ParseCommandLineFlags(argc, argv, true);
  FLAGS_logtostderr = true;
  // Every failure of Ceres reaches the estimators as a return value (a solver summary,
  // Covariance::Compute() == false) and leaves as one line of ours; Ceres' own warnings and
  // errors (e.g. a residual block that evaluated to NaN) would only add lines of internals.
  // --v=1 shows them.
  if (FLAGS_v <= 0) FLAGS_minloglevel = google::GLOG_FATAL;
  google::InitGoogleLogging(program);
  return true;
}

// The default of analyze's --tools_dir, the folder of the plot scripts: for an installed
// binary (PREFIX/bin/analyze, found through /proc/self/exe, so a moved prefix still works)
// PREFIX/share/accelcal/tools when it holds the scripts; otherwise `source_tools_dir`, the
// source tree's tools/ that the build compiled in. The first call decides; the pointer stays
// valid for the life of the program, as a flag's default must.
inline const char* DefaultToolsDir(const char* source_tools_dir) {
  static const std::string tools_dir = [source_tools_dir] {
    char executable[4096];
    const ssize_t length = readlink("/proc/self/exe", executable, sizeof(executable) - 1);
    if (length > 0) {
      const std::string path(executable, static_cast<size_t>(length));
      const std::string bin_dir = path.substr(0, path.rfind('/'));
      const std::string installed = bin_dir.substr(0, bin_dir.rfind('/')) + "/share/accelcal/tools";
      if (access((installed + "/plot_discovery.py").c_str(), R_OK) == 0) return installed;
    }
    return std::string(source_tools_dir);
  }();
  return tools_dir.c_str();
}

// --theta_unit, defined in each binary that reads a tilt test (so that its --help lists it)
// with one help text.
// clang-format off
#define ACCELCAL_DEFINE_THETA_UNIT_FLAG() \
  DEFINE_string(theta_unit, "auto", "Unit of the tilt test's angles: rad, deg, or auto (radians, but a span over two turns is refused as likely degrees).")
// clang-format on

// --columns, --rate_hz and --time_unit: how a three-axis IMU log is read (io/imu_log.h,
// docs/log-layouts.md), defined by every binary that reads one, with one help text each;
// --gyro_log by those that read imu_tk's pair of files. ImuLogOptionsFromFlags collects them.
// clang-format off
#define ACCELCAL_DEFINE_IMU_LOG_FLAGS()                                                                      \
  DEFINE_string(columns, "", "The log's columns when their names do not say (docs/log-layouts.md): KEY:NAME pairs, keys t (time), index (sample number), ax, ay, az (accelerometer), gx, gy, gz (gyroscope); NAME a header name or a column number from 1, e.g. --columns=t:TIME,ax:ACCEL_BMI160_0_X,ay:ACCEL_BMI160_0_Y,az:ACCEL_BMI160_0_Z. In a .mat file NAME is a variable or NAME(:,K), and acc:NAME, gyr:NAME take N x 3 variables. Keys not given are chosen by name."); \
  DEFINE_double(rate_hz, 0.0, "The log's sampling rate in Hz when it has no time column (or its sample-number column, e.g. imucal's 'samples', gives time): time = row (or sample number) / rate. 0: time from the time column."); \
  DEFINE_string(time_unit, "", "The unit of the time column: s, ms, us or ns. Empty: the column's name states it (t_s, time_ms, timestamp [ns]) or it is inferred from the median step (1 Hz to 100 kHz), and the output says which; a Unix time is counted from the first sample."); \
  DEFINE_string(topic, "", "A ROS 2 bag (a folder with metadata.yaml, or its .db3 file; docs/log-layouts.md): the sensor_msgs/msg/Imu topic to read, e.g. --topic=/imu/data. Empty: the bag's one Imu topic (said so in the output); a bag with several is refused, listing them."); \
  DEFINE_string(bag_time, "header", "A ROS 2 bag: the samples' time. header: the messages' header stamps (sec + nanosec, the driver's sample times); receive: the times the recorder received them (the bag's timestamp column). Counted from the first message.")
#define ACCELCAL_DEFINE_GYRO_LOG_FLAG() \
  DEFINE_string(gyro_log, "", "imu_tk's pair of files: the gyroscope's log (same layout and time stamps as the accelerometer's --log). Its samples are read and checked beside the accelerometer's.")
// clang-format on

inline Status ImuLogOptionsFromFlags(const std::string& columns, double rate_hz,
                                     const std::string& time_unit, const std::string& gyro_log,
                                     const std::string& topic, const std::string& bag_time,
                                     ImuLogReadOptions* options) {
  if (bag_time != "header" && bag_time != "receive") {
    return Status::Error("--bag_time='" + bag_time +
                         "' is not a time of a bag's messages; use header or receive");
  }
  std::vector<ImuColumnChoice> choices;
  ACCELCAL_RETURN_IF_ERROR(ParseImuColumnChoices(columns, &choices));
  if (!(rate_hz >= 0.0 && rate_hz <= 1e6)) {
    return Status::Error(StringPrintf(
        "--rate_hz=%g is not a sampling rate in (0, 1e6] Hz (0: time from the log's time column)",
        rate_hz));
  }
  double seconds = 0.0;
  if (!time_unit.empty() && !TimeUnitToSeconds(time_unit, &seconds))
    return Status::Error("--time_unit='" + time_unit + "' is not a unit; use s, ms, us or ns");
  if (!time_unit.empty() && rate_hz > 0.0)
    return Status::Error(
        "--time_unit and --rate_hz: give one (--rate_hz replaces the time column)");
  options->columns = columns;
  options->rate_hz = rate_hz;
  options->time_unit = time_unit;
  options->gyroscope_path = gyro_log;
  options->topic = topic;
  options->bag_time = bag_time;
  return Status::Ok();
}
// The unit a triad's columns' names state (acc_x_g, "a_x [m s^-2]", gyr_x_dps) stands for its
// unit flag (`*unit_flag`, --`flag`) when that was not given, said in `notes`, and must agree
// with it when it was. `outputs` names the outputs in the note ("outputs", "gyroscope outputs"),
// `sensor` the columns ("accelerometer"). `stated_by`: what states the unit when it is not the
// columns' names (a ROS 2 bag's message type, ImuLogSource::units_stated_by).
inline Status TakeStatedUnitOf(const std::string& stated, const std::vector<std::string>& known,
                               const char* flag, const char* outputs, const char* sensor,
                               std::string* unit_flag, std::vector<std::string>* notes,
                               const std::string& stated_by = "") {
  if (std::find(known.begin(), known.end(), stated) == known.end()) return Status::Ok();
  const std::string columns =
      stated_by.empty() ? std::string("the ") + sensor + " columns' names say " : stated_by + " ";
  if (!stated_by.empty() && !gflags::GetCommandLineFlagInfoOrDie(flag).is_default &&
      stated != *unit_flag) {
    return Status::Error("--" + std::string(flag) + "=" + *unit_flag + ", but " + columns + stated +
                         ": give --" + flag + "=" + stated + ", or leave --" + flag + " out");
  }
  if (gflags::GetCommandLineFlagInfoOrDie(flag).is_default) {
    if (stated != *unit_flag) {
      notes->push_back(std::string(outputs) + " in " + stated + ", as " + columns + "(--" + flag +
                       ", not given, would be " + *unit_flag + ")");
      *unit_flag = stated;
    }
    return Status::Ok();
  }
  if (stated != *unit_flag) {
    return Status::Error("--" + std::string(flag) + "=" + *unit_flag + ", but " + columns + stated +
                         ": give --" + flag + "=" + stated + ", or rename the columns if --" +
                         flag + " is right");
  }
  return Status::Ok();
}

// The accelerometer's: --unit.
inline Status TakeStatedUnit(const ImuLogSource& log_source, std::string* unit_flag,
                             std::vector<std::string>* notes) {
  return TakeStatedUnitOf(log_source.accelerometer_unit, {"count", "m/s^2", "g"}, "unit", "outputs",
                          "accelerometer", unit_flag, notes, log_source.units_stated_by);
}

#define ACCELCAL_IMU_LOG_OPTIONS(options)                                               \
  ::accelcal::ImuLogOptionsFromFlags(FLAGS_columns, FLAGS_rate_hz, FLAGS_time_unit, "", \
                                     FLAGS_topic, FLAGS_bag_time, options)

// --calibration_file, --run_file, --landmarks_file and --conditions_file: one file of the data,
// overriding --data_dir's (or, without --data_dir, all four together). Defined by every binary
// that reads a data folder, with one help text each; a binary that reads only the tilt test
// and its conditions defines those two.
// clang-format off
#define ACCELCAL_DEFINE_CALIBRATION_FILE_FLAG() \
  DEFINE_string(calibration_file, "", "The tilt test as a single file, overriding --data_dir's: .mat with tita (Nx1, rad) and datos (Nx2, m/s^2), or .csv with columns theta,ax,ay.")
#define ACCELCAL_DEFINE_CONDITIONS_FILE_FLAG() \
  DEFINE_string(conditions_file, "", "Initial position (m), initial velocity (m/s) and stated noise variances ((m/s^2)^2): datos.txt or scenario.json, overriding --data_dir's.")
#define ACCELCAL_DEFINE_DATA_FILE_FLAGS()                                                                  \
  ACCELCAL_DEFINE_CALIBRATION_FILE_FLAG();                                                                 \
  DEFINE_string(run_file, "", "The vehicle run as a single file, overriding --data_dir's: .mat with t (Mx1, s) and Aerr (Mx2, m/s^2), or .csv with columns t,ax,ay. Time must be uniformly spaced."); \
  DEFINE_string(landmarks_file, "", "The landmarks as a single file, overriding --data_dir's: .mat with one 1x2 [x y] (m) per variable, or .csv with columns name,x,y."); \
  ACCELCAL_DEFINE_CONDITIONS_FILE_FLAG()
// clang-format on

// The data a binary's flags name: --data_dir and the --*_file overrides
// (ACCELCAL_DEFINE_DATA_FILE_FLAGS), as ACCELCAL_DATA_FLAGS() collects them.
struct DataFlags {
  std::string data_dir;
  DataFiles overrides;

  // The flag that names measured data (--data_dir, else the first --*_file given), or ""
  // when none does and the data are simulated.
  std::string MeasuredDataFlag() const {
    if (!data_dir.empty()) return "--data_dir";
    for (const auto& [role, path] : FileRoles(overrides)) {
      if (!path.empty()) return "--" + role + "_file";
    }
    return "";
  }
};

#define ACCELCAL_DATA_FLAGS()                                                     \
  ::accelcal::DataFlags {                                                         \
    FLAGS_data_dir, ::accelcal::DataFiles {                                       \
      ::accelcal::DataLayout::kCourseMat, FLAGS_calibration_file, FLAGS_run_file, \
          FLAGS_landmarks_file, FLAGS_conditions_file                             \
    }                                                                             \
  }

// The load options the binary's --theta_unit asks for.
inline Status LoadOptionsFromFlags(const std::string& theta_unit, LoadOptions* options) {
  return ParseAngleUnit(theta_unit, &options->theta_unit);
}

// What the loaders read correctly but want said (e.g. a transposed matrix): one line each on
// stderr, "program: note: ...".
inline void PrintInputNotes(const std::vector<std::string>& notes) {
  for (const std::string& note : notes) {
    std::cerr << gflags::ProgramInvocationShortName() << ": note: " << note << "\n";
  }
}

// g for the tilt test: `flag_g` (the binary's --g) when given on the command line, else
// the data's own (scenario.json may state it), else the flag's default.
inline double ChooseGravity(const RunConditions& conditions, double flag_g) {
  const bool flag_given = !gflags::GetCommandLineFlagInfoOrDie("g").is_default;
  return conditions.has_gravity && !flag_given ? conditions.gravity_mps2 : flag_g;
}

// What a run reads, for the output checks (io/output_paths.h): the data folder and every
// file resolved in it or named by a --*_file flag.
inline RunInputs InputsOf(const std::string& data_dir, const DataFiles& files) {
  RunInputs inputs;
  if (!data_dir.empty()) inputs.folders.push_back(data_dir);
  for (const auto& [role, path] : FileRoles(files)) {
    if (!path.empty()) inputs.files.push_back(path);
  }
  return inputs;
}

// The files a binary writes, all or none (io/atomic_file.h); those with an empty path were
// not asked for.
struct OutputFile {
  std::string path;
  std::string contents;
};

inline Status WriteOutputFiles(const std::vector<OutputFile>& files) {
  std::vector<std::pair<std::string, std::string>> requested;
  for (const OutputFile& file : files) {
    if (!file.path.empty()) requested.emplace_back(file.path, file.contents);
  }
  return WriteFilesAtomically(requested);
}

// The data a problem works on: a data folder read as is (either layout) or, without one,
// the embedded tp2-2018 scenario simulated with `assignments` (name=value,...) hidden in it.
struct Experiment : CourseData {
  std::map<std::string, std::string> files;  // role -> path; empty when simulated
  nlohmann::json truth = nullptr;            // truth.json's content when simulated
  std::string source;                        // one line saying where the data came from
  DataSource data_source;                    // the same, with checksums (io/provenance.h)
  RunInputs inputs;                          // what was read (empty when simulated)
};

// Flag help texts list the catalogue's effects from the catalogue itself (models/effects.h),
// so an effect registered later appears in --help without an edit here.
//
// "angle_offset (rad), ..., run_bias_shift_x/y (m/s^2, needs a landmark)": the effects an
// estimator can add to the baseline, with their units.
inline std::string EstimableEffectsText() {
  std::string text;
  for (const EffectInfo& effect : kEffectInfos) {
    if (effect.role != Role::kEffect) continue;
    text += std::string(text.empty() ? "" : ", ") + effect.name +
            (effect.scope == Scope::kPerAxis ? "_x/y" : "") + " (" + effect.unit +
            (effect.acts_in == ActsIn::kVehicleRun ? ", needs a landmark" : "") + ")";
  }
  return text;
}

// "bias_x m/s^2, scale_x 1, angle_offset rad, ...": every parameter of the catalogue by its
// x-axis name and unit (a noise variance as a ratio to the stated one).
inline std::string CatalogueParametersText() {
  std::string text;
  for (const EffectInfo& effect : kEffectInfos) {
    text += std::string(text.empty() ? "" : ", ") + effect.name +
            (effect.scope == Scope::kPerAxis ? "_x " : " ") +
            (effect.role == Role::kNoiseRatio ? "ratio" : effect.unit);
  }
  return text;
}

// --progress, defined in each binary that runs for more than a few seconds (so that its
// --help lists it) with one help text.
// clang-format off
#define ACCELCAL_DEFINE_PROGRESS_FLAG() \
  DEFINE_string(progress, "auto", "Progress lines with the time left, on stderr: auto (only when stderr is a terminal), always, or never. stdout and the output files are the same whatever it says.")
// clang-format on

// The style --progress asks for on this process's stderr.
inline Status ProgressStyleFromFlag(const std::string& mode, ProgressStyle* style) {
  return ProgressStyleFor(mode, isatty(STDERR_FILENO) != 0, style);
}

// `outputs` are checked against the files once they are resolved, before any is read.
// The flags that choose or shape a simulation (e.g. --set, --seed, --scenario) mean nothing
// when the data come from files (`data_flag`, e.g. --data_dir, was given): one of them given
// with it is refused with one line rather than silently ignored, so a user never believes a
// measured result reflects an effect they asked to hide.
inline Status RefuseSimulationFlags(const char* data_flag,
                                    std::initializer_list<const char*> simulation_flags) {
  for (const char* name : simulation_flags) {
    gflags::CommandLineFlagInfo info;
    if (gflags::GetCommandLineFlagInfo(name, &info) && !info.is_default) {
      return Status::Error(std::string("--") + name + "=" + info.current_value +
                           " applies only to simulated data, but " + data_flag +
                           " names measured data; drop one of the two");
    }
  }
  return Status::Ok();
}

// The provenance every binary gives (io/provenance.h): the "data: ..." line first on stdout,
// and source, input_files, command_line and accelcal_version in its JSON.
inline nlohmann::json WithProvenance(nlohmann::json json, const DataSource& source) {
  AddProvenanceJson(source, &json);
  return json;
}

inline std::string WithDataLine(const DataSource& source, const std::string& text) {
  return DataLine(source) + "\n" + text;
}

// The scenario a simulation or study runs (--scenario FILE, else the embedded one, with
// --set's `assignments`), after `outputs` are checked against the scenario file; `source`
// says so with `seed`.
inline Status LoadSimulationScenario(const std::string& scenario_file,
                                     const std::string& assignments, uint64_t seed,
                                     const std::vector<OutputPath>& outputs, Scenario* scenario,
                                     DataSource* source) {
  RunInputs inputs;
  if (!scenario_file.empty()) inputs.files.push_back(scenario_file);
  ACCELCAL_RETURN_IF_ERROR(CheckOutputPaths(outputs, inputs));
  ACCELCAL_RETURN_IF_ERROR(LoadScenarioOrDefault(scenario_file, assignments, scenario));
  return DescribeSimulation(*scenario, scenario_file, seed, source);
}

// Measured data when `data` names any (refusing then every flag of `simulation_flags` that
// was given, e.g. --set, --seed), else the embedded scenario simulated with `assignments`.
inline Status LoadExperiment(const DataFlags& data, const std::string& assignments, uint64_t seed,
                             std::initializer_list<const char*> simulation_flags,
                             const LoadOptions& options, const std::vector<OutputPath>& outputs,
                             Experiment* experiment) {
  const std::string data_flag = data.MeasuredDataFlag();
  if (data_flag.empty()) {
    ACCELCAL_RETURN_IF_ERROR(CheckOutputPaths(outputs, RunInputs()));
    Scenario scenario;
    ACCELCAL_RETURN_IF_ERROR(LoadScenarioOrDefault("", assignments, &scenario));
    SimulatedData simulated = SimulateScenario(scenario, seed);
    ACCELCAL_RETURN_IF_ERROR(DescribeSimulation(scenario, "", seed, &experiment->data_source));
    experiment->truth = TruthJson(scenario, simulated, seed);
    experiment->source =
        "simulated from the embedded scenario " + scenario.name + " (seed " + std::to_string(seed) +
        ") with " + (assignments.empty() ? std::string("nothing") : assignments) + " hidden in it";
    experiment->test = std::move(simulated.test);
    experiment->run = std::move(simulated.run);
    experiment->landmarks = std::move(simulated.landmarks);
    experiment->conditions = simulated.conditions;
    return Status::Ok();
  }
  ACCELCAL_RETURN_IF_ERROR(RefuseSimulationFlags(data_flag.c_str(), simulation_flags));
  if (data.data_dir.empty()) {
    for (const auto& [role, path] : FileRoles(data.overrides)) {
      if (path.empty()) {
        return Status::Error(
            "without --data_dir, give all of --calibration_file, --run_file, "
            "--landmarks_file and --conditions_file (--" +
            role + "_file is missing)");
      }
    }
  }
  DataFiles files;
  ACCELCAL_RETURN_IF_ERROR(ResolveDataFiles(data.data_dir, data.overrides, &files));
  experiment->inputs = InputsOf(data.data_dir, files);
  ACCELCAL_RETURN_IF_ERROR(CheckOutputPaths(outputs, experiment->inputs));
  ACCELCAL_RETURN_IF_ERROR(LoadDataFiles(files, experiment, options));
  PrintInputNotes(experiment->notes);
  experiment->source =
      "measured data in " +
      (data.data_dir.empty() ? files.calibration + " and the files with it" : data.data_dir);
  experiment->files = FileRoles(files);
  ACCELCAL_RETURN_IF_ERROR(
      DescribeMeasuredData(data.data_dir, experiment->files, &experiment->data_source));
  return Status::Ok();
}

}  // namespace accelcal

#endif  // ACCELCAL_PROBLEMS_PROBLEM_SUPPORT_H_
