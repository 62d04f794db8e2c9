// triad_bench: accelcal's side of the triad benchmark against numpy/SciPy (issue 20,
// tools/bench/triad_bench.sh). It runs calibrate_imu's pipeline on a triad log --repetitions
// times, in-process, each stage timed with std::chrono::steady_clock:
//
//   read    the log, parsed and checked (io/imu_log.h, ReadImuLog)
//   imu_tk  imu_tk's calibration (estimation/triad/imu_tk_calibration.h, CalibrateImuTk): the
//           initial rest's variance, the sliding variance norm, the static intervals for
//           k = 2..10 and one Levenberg-Marquardt solve of 1/2 sum (g - |T K (u - b)|)^2 per k
//   ml      the poses of the chosen k's intervals and the maximum-likelihood fit with unknown
//           gravity directions, its rank checks and ceres::Covariance
//           (estimation/triad/triad_ml_calibration.h, PoseMeansOfIntervals + CalibrateTriadMl)
//   total   read + imu_tk + ml of the same repetition
//
// and, apart, `detect`: the detector's share of imu_tk (the rest's variance, the sliding
// variance norm, the intervals for every k), timed in its own call so that the pipeline above
// is exactly what calibrate_imu runs. Each figure is the median over the repetitions, of the
// wall time and of the process's CPU time.
// Then the floor (issue 20's 10x target against the peer): what any pipeline that reads this
// file and makes imu_tk's solves in Ceres must spend, however fast the rest: the file's bytes
// into memory (no parsing), and for every solved k one Ceres solve of that k's samples (the
// analytic batch residual, imu_tk's start and tolerances, nothing else in the problem), with
// each of Ceres' two dense linear solvers; the floor takes the faster.
// The JSON holds the times and calibrate_imu's two JSON results (imu_tk and ml modes, built
// outside the clock), so that tools/bench/triad_scipy.py can check it computed the same thing.
//
//   build/bin/triad_bench --log=../shared/data/imu_tk-xsens/xsens_acc.mat --g=9.81744 \
//       --init_rest_s=50 --initial_offset=32768 --repetitions=21 --json=cc.json

#include <ceres/ceres.h>
#include <gflags/gflags.h>
#include <glog/logging.h>
#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "estimation/triad/imu_tk_calibration.h"
#include "estimation/triad/static_intervals.h"
#include "estimation/triad/triad_ml_calibration.h"
#include "io/atomic_file.h"
#include "io/imu_log.h"
#include "io/provenance.h"
#include "reporting/calibrate_imu_report.h"
#include "residuals/imu_tk_residual.h"

DEFINE_string(log, "", "The triad log (as calibrate_imu --log), e.g. imu_tk's xsens_acc.mat.");
DEFINE_double(g, 9.81744, "Local gravity in m/s^2 (imu_tk's Xsens example: 9.81744).");
DEFINE_double(init_rest_s, 50.0, "Initial rest in s (imu_tk's Xsens example: 50).");
DEFINE_double(initial_offset, 32768.0, "Initial guess of the offsets, counts (imu_tk's: 32768).");
DEFINE_int32(repetitions, 21, "Runs of the whole pipeline (>= 1); each time is their median.");
DEFINE_string(json, "-", "Where to write the JSON result (atomically); '-': stdout.");

namespace accelcal {
namespace {

constexpr int kExitBadInput = 2;

using Clock = std::chrono::steady_clock;

// Wall time, and the process's CPU time beside it: on a machine shared with builds, a stage
// that waited for a core shows it in the wall time only.
struct Stamp {
  Clock::time_point wall;
  double cpu_s = 0.0;
};

Stamp Now() {
  timespec cpu{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &cpu);
  return {Clock::now(), cpu.tv_sec + 1e-9 * cpu.tv_nsec};
}

struct StageTimes {
  std::vector<double> wall_s;
  std::vector<double> cpu_s;
  void Add(const Stamp& start, const Stamp& stop) {
    wall_s.push_back(std::chrono::duration<double>(stop.wall - start.wall).count());
    cpu_s.push_back(stop.cpu_s - start.cpu_s);
  }
};
using Timings = std::map<std::string, StageTimes>;

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

struct PipelineOutput {
  TriadLog log;
  CalibrateImuReport report;
};

ImuTkOptions ImuTkOptionsFromFlags() {
  ImuTkOptions options;
  options.gravity_mps2 = FLAGS_g;
  options.init_rest_s = FLAGS_init_rest_s;
  options.initial =
      TriadParametersWithOffset(FLAGS_initial_offset, FLAGS_initial_offset, FLAGS_initial_offset);
  return options;
}

// calibrate_imu's Load and Solve in both modes, without the provenance (hashing the file is
// not part of the computation the peers do). Records each stage's duration in `timings`.
Status RunPipeline(PipelineOutput* out, Timings* timings) {
  CalibrateImuReport& report = out->report;
  report = CalibrateImuReport();
  report.options = ImuTkOptionsFromFlags();
  const Stamp start = Now();
  ImuLogSource log_source;
  ACCELCAL_RETURN_IF_ERROR(
      ReadImuLog(FLAGS_log, ImuLogReadOptions(), &out->log, ImuLogSpacing::kEven, &log_source));
  const Stamp read = Now();
  report.log_layout = log_source.layout;
  ACCELCAL_RETURN_IF_ERROR(
      CalibrateImuTk(out->log, report.options, &report.result).WithContext(FLAGS_log));
  const Stamp imu_tk = Now();
  const std::vector<TriadPoseMean> poses =
      PoseMeansOfIntervals(out->log, report.result.intervals, report.options.interval_samples);
  report.ml_options.gravity_mps2 = FLAGS_g;
  report.ml_options.initial = report.result.best().parameters;
  ACCELCAL_RETURN_IF_ERROR(
      CalibrateTriadMl(poses, report.ml_options, &report.ml).WithContext(FLAGS_log));
  const Stamp ml = Now();
  for (const TriadPoseMean& pose : poses) report.ml_sample_count += pose.sample_count;
  (*timings)["read"].Add(start, read);
  (*timings)["imu_tk"].Add(read, imu_tk);
  (*timings)["ml"].Add(imu_tk, ml);
  (*timings)["total"].Add(start, ml);
  return Status::Ok();
}

// The detector's part of CalibrateImuTk, alone: the same calls in the same order.
int TimeDetector(const TriadLog& log, const ImuTkOptions& options, StageTimes* times) {
  const Stamp start = Now();
  const int rest_end = InitialRestEnd(log, options.init_rest_s);
  const std::array<double, 3> v = IntervalVariance(log, 0, rest_end);
  const double rest_norm = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  const std::vector<double> variance_norm = SlidingVarianceNorm(log, options.window_samples);
  int intervals = 0;
  for (int k = options.min_multiplier; k <= options.max_multiplier; ++k) {
    intervals += static_cast<int>(
        DetectStaticIntervals(log, variance_norm, options.window_samples, k * rest_norm).size());
  }
  times->Add(start, Now());
  return intervals;  // used, so that nothing is optimised away
}

// The file's bytes into one buffer, with nothing parsed: the least any reader must do.
Status ReadBytes(const std::string& path, std::string* bytes) {
  struct stat status {};
  if (stat(path.c_str(), &status) != 0) return Status::Error(path + ": cannot stat");
  bytes->resize(static_cast<size_t>(status.st_size));
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) return Status::Error(path + ": cannot open");
  const size_t read = std::fread(bytes->data(), 1, bytes->size(), file);
  std::fclose(file);
  if (read != bytes->size()) return Status::Error(path + ": short read");
  return Status::Ok();
}

struct SolveFloor {
  std::string linear_solver;
  double seconds = 0.0;                  // the sum over the solved k of each k's median solve time
  double cpu_seconds = 0.0;              // the same in CPU time
  double largest_cost_difference = 0.0;  // relative, against CalibrateImuTk's cost at that k
};

// One Ceres solve per solved k, as SolveImuTkProblem makes it (ImuTkSolverOptions) but with
// `linear_solver`.
SolveFloor TimeCeresSolves(const TriadLog& log, const ImuTkOptions& options,
                           const ImuTkResult& result, ceres::LinearSolverType linear_solver,
                           int repetitions) {
  SolveFloor floor;
  floor.linear_solver = ceres::LinearSolverTypeToString(linear_solver);
  const int window = ImuTkWindow(options);
  const std::vector<double> variance_norm = SlidingVarianceNorm(log, window);
  for (const ImuTkSweepEntry& entry : result.sweep) {
    if (!entry.solved) continue;
    int used = 0;
    const std::vector<int> samples =
        ImuTkSamples(DetectStaticIntervals(log, variance_norm, window, entry.threshold),
                     options.interval_samples, &used);
    std::vector<std::array<double, 3>> raw;
    for (const int i : samples) raw.push_back(log.output[i]);
    ceres::Solver::Options solver_options = ImuTkSolverOptions(options);
    solver_options.linear_solver_type = linear_solver;
    StageTimes times;
    double cost = 0.0;
    for (int repetition = 0; repetition < repetitions; ++repetition) {
      TriadParameters parameters = options.initial;
      const Stamp start = Now();
      ceres::Problem problem;
      problem.AddResidualBlock(new ImuTkBatchResidual(raw, options.gravity_mps2), nullptr,
                               parameters.data());
      ceres::Solver::Summary summary;
      ceres::Solve(solver_options, &problem, &summary);
      times.Add(start, Now());
      cost = summary.final_cost;
    }
    floor.seconds += Median(times.wall_s);
    floor.cpu_seconds += Median(times.cpu_s);
    floor.largest_cost_difference =
        std::max(floor.largest_cost_difference, std::abs(cost - entry.cost) / entry.cost);
  }
  return floor;
}

nlohmann::json TimingJson(const StageTimes& times) {
  return {{"seconds_median", Median(times.wall_s)},
          {"seconds", times.wall_s},
          {"cpu_seconds_median", Median(times.cpu_s)},
          {"cpu_seconds", times.cpu_s}};
}

int Run(int argc, char** argv) {
  gflags::SetUsageMessage(
      "Times calibrate_imu's pipeline (read, imu_tk's sweep, maximum likelihood with covariance) "
      "in-process and writes the times and both modes' results as JSON.\n"
      "  triad_bench --log=../shared/data/imu_tk-xsens/xsens_acc.mat --repetitions=21 "
      "--json=cc.json");
  gflags::ParseCommandLineFlags(&argc, &argv, true);
  FLAGS_logtostderr = true;
  FLAGS_minloglevel = google::GLOG_WARNING;
  google::InitGoogleLogging(argv[0]);
  auto fail = [](const Status& status) {
    std::cerr << "triad_bench: error: " << status.message() << "\n";
    return kExitBadInput;
  };
  if (argc > 1) return fail(Status::Error(std::string("unexpected argument '") + argv[1] + "'"));
  if (FLAGS_log.empty()) return fail(Status::Error("--log is required: the triad log to time"));
  if (FLAGS_repetitions < 1) return fail(Status::Error("--repetitions must be at least 1"));

  PipelineOutput out;
  Timings timings;
  int detected = 0;
  for (int repetition = 0; repetition < FLAGS_repetitions; ++repetition) {
    const Status status = RunPipeline(&out, &timings);
    if (!status.ok()) return fail(status);
    detected = TimeDetector(out.log, out.report.options, &timings["detect"]);
  }

  std::string bytes;
  StageTimes read_bytes;
  for (int repetition = 0; repetition < FLAGS_repetitions; ++repetition) {
    const Stamp start = Now();
    const Status status = ReadBytes(FLAGS_log, &bytes);
    if (!status.ok()) return fail(status);
    read_bytes.Add(start, Now());
  }
  std::vector<SolveFloor> solves;
  for (const ceres::LinearSolverType solver : {ceres::DENSE_QR, ceres::DENSE_NORMAL_CHOLESKY}) {
    solves.push_back(
        TimeCeresSolves(out.log, out.report.options, out.report.result, solver, FLAGS_repetitions));
  }
  const SolveFloor& fastest = *std::min_element(
      solves.begin(), solves.end(),
      [](const SolveFloor& a, const SolveFloor& b) { return a.seconds < b.seconds; });

  // Outside the clock: what calibrate_imu would write in each mode.
  CalibrateImuReport& report = out.report;
  InputFile file;
  Status status = HashInputFile(FLAGS_log, &file);
  if (!status.ok()) return fail(status);
  report.log_path = FLAGS_log;
  report.log_sha256 = file.sha256;
  report.sample_count = out.log.size();
  report.first_t_s = out.log.timestamp_s.front();
  report.last_t_s = out.log.timestamp_s.back();
  report.rest_end_s = out.log.timestamp_s[report.result.rest_end];
  nlohmann::json json;
  json["timing"] = {{"clock", "std::chrono::steady_clock; CPU: CLOCK_PROCESS_CPUTIME_ID"},
                    {"statistic", "median over repetitions"},
                    {"repetitions", FLAGS_repetitions},
                    {"threads", 1},
                    {"detect_note", "the detector's share of imu_tk, timed in its own call"},
                    {"detected_intervals_all_k", detected}};
  for (const auto& [stage, times] : timings) json["timing"]["stages"][stage] = TimingJson(times);
  nlohmann::json& floor = json["timing"]["floor"];
  floor["note"] =
      "what any pipeline reading this file and making imu_tk's solves in Ceres must spend: the "
      "file's bytes read (no parsing) plus, per solved k, one Ceres solve of its samples (median "
      "wall time), with the faster dense linear solver";
  floor["read_bytes_seconds"] = Median(read_bytes.wall_s);
  floor["read_bytes_cpu_seconds"] = Median(read_bytes.cpu_s);
  floor["file_bytes"] = bytes.size();
  for (const SolveFloor& solve : solves) {
    floor["solves"][solve.linear_solver] = {
        {"seconds", solve.seconds},
        {"cpu_seconds", solve.cpu_seconds},
        {"largest_cost_difference", solve.largest_cost_difference}};
  }
  floor["solved_k"] = std::count_if(report.result.sweep.begin(), report.result.sweep.end(),
                                    [](const ImuTkSweepEntry& entry) { return entry.solved; });
  floor["fastest_linear_solver"] = fastest.linear_solver;
  floor["seconds"] = Median(read_bytes.wall_s) + fastest.seconds;
  floor["cpu_seconds"] = Median(read_bytes.cpu_s) + fastest.cpu_seconds;
  // The solves shared between the machine's two cores, at best half the time each.
  floor["seconds_two_cores"] = Median(read_bytes.wall_s) + 0.5 * fastest.seconds;
  report.mode = "imu_tk";
  json["imu_tk"] = CalibrateImuJson(report);
  report.mode = "ml";
  json["ml"] = CalibrateImuJson(report);
  json["ml"]["pooled_noise_variance"] = report.ml.noise_variance;
  json["ml"]["pose_count"] = report.ml.pose_count;
  json["ml"]["sample_count"] = report.ml_sample_count;

  const std::string text = json.dump(2) + "\n";
  if (FLAGS_json.empty() || FLAGS_json == "-") {
    std::cout << text << std::flush;
    return 0;
  }
  status = WriteFileAtomically(FLAGS_json, text).WithContext("--json");
  return status.ok() ? 0 : fail(status);
}

}  // namespace
}  // namespace accelcal

int main(int argc, char** argv) { return accelcal::Run(argc, argv); }
