// allan: the noise of an accelerometer triad from its static data (issue 21, item 1;
// docs/noise.md).
//
// Per axis, the overlapping Allan variance sigma^2(tau) of the static segments at octave cluster
// times with chi-square intervals, and the fit
//   sigma^2(tau) = N^2 / tau + (2 ln 2 / pi) B^2 + K^2 tau / 3
// (white noise N, bias instability B, random walk K; estimation/statistics/allan_variance.h) with
// sigmas from a parametric bootstrap (studies/allan_study.h). With the log's poses known, the
// variance of each pose mean from the model over white noise's, the chi2/dof that a calibration
// weighted by white noise should expect.
//
// Input: a triad log (io/imu_log.h). Output: the table on stdout, --json, --plot (a PNG drawn by
// tools/plot_allan.py with /usr/bin/python3); both written atomically, nothing on failure.
//
//   allan --log=../shared/data/imu_tk-xsens/xsens_acc.mat --unit=count --gain=0.0024
//         --static=longest --plot=allan.png --json=allan.json

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>

#include "common/format.h"
#include "estimation/statistics/allan_variance.h"
#include "estimation/triad/noise_floor_detector.h"
#include "io/cleanup.h"
#include "io/csv_reader.h"
#include "io/imu_log.h"
#include "models/triad_units.h"
#include "problem_support.h"
#include "reporting/allan_report.h"
#include "reporting/analyze_report.h"
#include "studies/allan_study.h"

DEFINE_string(log, "",
              "The accelerometer log, in any layout calibrate_imu reads (docs/log-layouts.md): "
              "imu_tk's ASCII layout (t [s], x, y, z), CSV or other text with a header, a .mat.");
ACCELCAL_DEFINE_IMU_LOG_FLAGS();
DEFINE_string(unit, "count", "The unit of the log's outputs: count, m/s^2 or g.");
DEFINE_string(
    gain, "auto",
    "m/s^2 per unit of output, to state the results in SI: auto (1 for m/s^2, 9.80665 for g; for "
    "count the results stay in counts) or a positive number (e.g. a calibration's gain).");
DEFINE_string(segment, "",
              "Static segments as START_S:END_S[,START_S:END_S...] (seconds of the log's time), "
              "instead of --static.");
DEFINE_string(static, "longest",
              "Which poses of the noise-floor detector to use without --segment: longest (the "
              "longest static interval, e.g. a log's initial rest) or all (every pose, pooled).");
DEFINE_int32(bootstrap, 1000,
             "Simulated series of the parametric bootstrap whose test inversion gives the terms' "
             "intervals (docs/noise.md), 100 to 20000; the 2.5% tails need several hundred.");
DEFINE_uint64(seed, 1, "Seed of the bootstrap.");
DEFINE_double(confidence, 0.95, "Level of the intervals, in (0, 1).");
DEFINE_string(json, "", "Write the results as JSON to this file (atomically).");
DEFINE_string(plot, "",
              "Draw the log-log Allan plot with the fitted terms into this PNG file "
              "(tools/plot_allan.py with /usr/bin/python3 and matplotlib).");
DEFINE_string(tools_dir, accelcal::DefaultToolsDir(ACCELCAL_TOOLS_DIR),
              "Folder of the plot scripts.");
ACCELCAL_FLAG_RANGE(bootstrap, 100, 20000);
ACCELCAL_FLAG_OPEN_RANGE(confidence, 0.0, 1.0);

namespace accelcal {
namespace {

constexpr const char* kUsage =
    "Allan deviation and noise terms (white noise N, bias instability B, random walk K) of a\n"
    "triad log's static data, per axis, with intervals (docs/noise.md).\n"
    "  allan --log=FILE [--unit=count|m/s^2|g] [--gain=auto|G] [--segment=S:E,... | "
    "--static=longest|all]\n"
    "        [--json=out.json] [--plot=allan.png]\n"
    "Units: U is m/s^2 with --gain=G (m/s^2 per unit of output) or a log in m/s^2 or g, else\n"
    "the log's own unit (count). Allan deviation in U; N (white noise density, velocity random\n"
    "walk) in U/sqrt(Hz) (x 60 for per sqrt(hour)); B (bias instability) in U, the deviation's\n"
    "floor being 0.664 B; K (acceleration random walk) in U sqrt(Hz) = U/sqrt(s). Each term has\n"
    "a --confidence interval from a parametric bootstrap; one reaching 0 is 'not resolved' and\n"
    "its upper bound is stated. Variance of a pose mean of T s: N^2/T + 0.441 B^2 + K^2 T/3 "
    "(U^2).\n"
    "The log is read whole (some 90 bytes a sample: 0.9 GB at 10^7); the bootstrap's cost does\n"
    "not grow with it beyond 2^16 samples of static data (docs/noise.md, long data).";

Status ParseSegments(std::vector<std::pair<double, double>>* segments) {
  std::stringstream list(FLAGS_segment);
  std::string item;
  while (std::getline(list, item, ',')) {
    const size_t colon = item.find(':');
    double start = 0.0, end = 0.0;
    if (colon == std::string::npos || !ParseFiniteNumber(item.substr(0, colon), &start) ||
        !ParseFiniteNumber(item.substr(colon + 1), &end) || !(end > start)) {
      return Status::Error("--segment: '" + item +
                           "' is not START_S:END_S with END_S > START_S (seconds)");
    }
    segments->emplace_back(start, end);
  }
  // Samples in two segments would enter the Allan variance twice and narrow its intervals.
  std::vector<std::pair<double, double>> sorted = *segments;
  std::sort(sorted.begin(), sorted.end());
  for (size_t j = 1; j < sorted.size(); ++j) {
    if (sorted[j].first <= sorted[j - 1].second) {
      return Status::Error(StringPrintf(
          "--segment: %g:%g and %g:%g overlap; their common samples would count twice in the "
          "Allan variance: give disjoint segments",
          sorted[j - 1].first, sorted[j - 1].second, sorted[j].first, sorted[j].second));
    }
  }
  return Status::Ok();
}

Status ValidateFlags() {
  if (FLAGS_log.empty()) return Status::Error("--log is required: the accelerometer log");
  TriadOutputUnit unit;
  ACCELCAL_RETURN_IF_ERROR(ParseTriadOutputUnit(FLAGS_unit, &unit).WithContext("--unit"));
  double gain = 0.0;
  if (FLAGS_gain != "auto" && (!ParseFiniteNumber(FLAGS_gain, &gain) || !(gain > 0.0))) {
    return Status::Error("--gain='" + FLAGS_gain +
                         "' is neither auto nor a positive number (m/s^2 per unit of output)");
  }
  if (FLAGS_static != "longest" && FLAGS_static != "all")
    return Status::Error("--static='" + FLAGS_static + "' is not longest or all");
  if (!FLAGS_segment.empty() && !gflags::GetCommandLineFlagInfoOrDie("static").is_default) {
    return Status::Error("--segment and --static both choose the segments; give one of the two");
  }
  std::vector<std::pair<double, double>> segments;
  ACCELCAL_RETURN_IF_ERROR(ParseSegments(&segments));
  if (!FLAGS_plot.empty() && FLAGS_plot.size() < 4) {
    return Status::Error("--plot='" + FLAGS_plot + "' does not end in .png");
  }
  if (!FLAGS_plot.empty() && FLAGS_plot.substr(FLAGS_plot.size() - 4) != ".png")
    return Status::Error("--plot='" + FLAGS_plot + "' does not end in .png; name a PNG file");
  return CheckOutputPaths({{"--json", FLAGS_json}, {"--plot", FLAGS_plot}},
                          RunInputs{{FLAGS_log}, {}});
}

// The samples of [first, last] as segments of the result unit, and the sample period: the
// median step, every step within 50% of it (a gap would put unequal spacing into the clusters).
Status TakeSegment(const TriadLog& log, int first, int last, double gain, AllanReport* report,
                   std::array<std::vector<std::vector<double>>, 3>* data) {
  AllanSegment segment;
  segment.start_s = log.timestamp_s[first];
  segment.end_s = log.timestamp_s[last];
  segment.sample_count = last - first + 1;
  report->segments.push_back(segment);
  for (int k = 0; k < 3; ++k) {
    (*data)[k].emplace_back();
    for (int i = first; i <= last; ++i) (*data)[k].back().push_back(gain * log.output[i][k]);
  }
  return Status::Ok();
}

Status CheckSampling(const TriadLog& log, AllanReport* report) {
  std::vector<double> steps;
  for (size_t i = 1; i < log.size(); ++i)
    steps.push_back(log.timestamp_s[i] - log.timestamp_s[i - 1]);
  std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
  const double tau0 = steps[steps.size() / 2];
  report->sample_period_s = tau0;
  for (const AllanSegment& segment : report->segments) {
    const auto begin =
        std::lower_bound(log.timestamp_s.begin(), log.timestamp_s.end(), segment.start_s);
    for (auto it = begin + 1; it != log.timestamp_s.end() && *it <= segment.end_s; ++it) {
      const double step = *it - *(it - 1);
      if (step > 1.5 * tau0 || step < 0.5 * tau0) {
        return Status::Error(StringPrintf(
            "%s: a step of %.6g s at t = %.6g s in segment %.3f..%.3f s, against the median "
            "%.6g s; an Allan variance needs uniform sampling: choose a segment without the gap, "
            "or, if the time stamps only jitter (a host's), give --rate_hz=%.4g to time the "
            "samples by their order",
            FLAGS_log.c_str(), step, *it, segment.start_s, segment.end_s, tau0,
            (log.size() - 1) / (log.timestamp_s.back() - log.timestamp_s.front())));
      }
    }
  }
  return Status::Ok();
}

Status Solve(const TriadLog& log, AllanReport* report) {
  TriadOutputUnit unit;
  ACCELCAL_RETURN_IF_ERROR(ParseTriadOutputUnit(FLAGS_unit, &unit));
  // A log in m/s^2 said to be in counts (or the reverse) would give every term in the wrong
  // unit; the outputs' magnitude tells, as calibrate_imu checks it.
  const double offset = unit == TriadOutputUnit::kCount ? AdcMidScale(log) : 0.0;
  ACCELCAL_RETURN_IF_ERROR(CheckOutputsMatchUnit(log, unit, offset).WithContext(FLAGS_log));
  report->output_unit = TriadOutputUnitName(unit);
  report->log_path = FLAGS_log;
  report->gain = 1.0;
  report->unit = report->output_unit;
  if (FLAGS_gain != "auto") {
    ParseFiniteNumber(FLAGS_gain, &report->gain);
    report->unit = "m/s^2";
  } else if (unit == TriadOutputUnit::kG) {
    report->gain = 9.80665;
    report->unit = "m/s^2";
  }
  // The poses, for the pose-mean variances and (without --segment) the segments.
  NoiseFloorOptions detector;
  detector.min_intervals = 0;
  NoiseFloorDetection detection;
  const Status detected = DetectStaticIntervalsFromNoiseFloor(log, detector, &detection);
  std::array<std::vector<std::vector<double>>, 3> data;
  if (!FLAGS_segment.empty()) {
    std::vector<std::pair<double, double>> wanted;
    ACCELCAL_RETURN_IF_ERROR(ParseSegments(&wanted));
    report->selection = "--segment";
    for (const auto& [start, end] : wanted) {
      const int first =
          static_cast<int>(std::lower_bound(log.timestamp_s.begin(), log.timestamp_s.end(), start) -
                           log.timestamp_s.begin());
      const int last =
          static_cast<int>(std::upper_bound(log.timestamp_s.begin(), log.timestamp_s.end(), end) -
                           log.timestamp_s.begin()) -
          1;
      if (last - first + 1 < 4) {
        return Status::Error(StringPrintf(
            "--segment %g:%g holds %d samples of %s (t = %.3f .. %.3f s); an Allan variance "
            "needs at least 4",
            start, end, std::max(0, last - first + 1), FLAGS_log.c_str(), log.timestamp_s.front(),
            log.timestamp_s.back()));
      }
      ACCELCAL_RETURN_IF_ERROR(TakeSegment(log, first, last, report->gain, report, &data));
    }
  } else {
    ACCELCAL_RETURN_IF_ERROR(
        detected.WithContext(FLAGS_log + " (the static segments; or give --segment)"));
    if (detection.intervals.empty()) {
      return Status::Error(
          FLAGS_log +
          ": the noise-floor detector found no static interval of 1 s or more; give --segment");
    }
    report->selection = FLAGS_static == "all" ? "every pose of the noise-floor detector"
                                              : "the longest pose of the noise-floor detector";
    std::vector<StaticInterval> chosen = detection.intervals;
    if (FLAGS_static == "longest") {
      chosen = {*std::max_element(chosen.begin(), chosen.end(), [](const auto& a, const auto& b) {
        return a.sample_count() < b.sample_count();
      })};
    }
    for (const StaticInterval& interval : chosen)
      ACCELCAL_RETURN_IF_ERROR(
          TakeSegment(log, interval.start, interval.end, report->gain, report, &data));
  }
  ACCELCAL_RETURN_IF_ERROR(CheckSampling(log, report));
  report->options.confidence = FLAGS_confidence;
  report->bootstrap_series = FLAGS_bootstrap;
  // One bootstrap table serves the three axes: they share the segments and taus.
  for (int k = 0; k < 3; ++k) {
    ACCELCAL_RETURN_IF_ERROR(
        ComputeAllanVariance(data[k], report->sample_period_s, report->options, &report->curves[k])
            .WithContext(FLAGS_log + std::string(", axis ") + "xyz"[k]));
  }
  AllanBootstrapOptions bootstrap;
  bootstrap.series = FLAGS_bootstrap;
  bootstrap.seed = FLAGS_seed;
  AllanBootstrapTable table;
  ACCELCAL_RETURN_IF_ERROR(
      MakeAllanBootstrapTable(report->options, report->curves[0], bootstrap, &table));
  for (int k = 0; k < 3; ++k) {
    ACCELCAL_RETURN_IF_ERROR(
        FitAllanNoiseWithBootstrap(report->options, table, &report->curves[k], &report->fits[k])
            .WithContext(FLAGS_log + std::string(", axis ") + "xyz"[k]));
  }
  // Pose means: s_k^2 pooled within the poses, as the maximum-likelihood calibration weighs them.
  if (detected.ok() && !detection.intervals.empty()) {
    std::array<double, 3> squares{};
    long long dof = 0;
    for (const StaticInterval& interval : detection.intervals) {
      for (int k = 0; k < 3; ++k) {
        const double sd = report->gain * interval.noise_stddev[k];
        squares[k] += sd * sd * (interval.sample_count() - 1);
      }
      dof += interval.sample_count() - 1;
    }
    for (int k = 0; k < 3; ++k) report->pooled_pose_variance[k] = squares[k] / dof;
    for (const StaticInterval& interval : detection.intervals) {
      AllanPoseRatio pose;
      pose.start_s = interval.start_s;
      pose.sample_count = interval.sample_count();
      pose.duration_s = pose.sample_count * report->sample_period_s;
      for (int k = 0; k < 3; ++k) {
        pose.model_over_white[k] =
            AllanPoseMeanVariance(FittedNoiseTerms(report->fits[k]), pose.duration_s) /
            (report->pooled_pose_variance[k] / pose.sample_count);
      }
      report->poses.push_back(pose);
    }
  }
  return Status::Ok();
}

// The PNG's bytes, drawn in a temporary folder that is removed on every path out.
Status DrawPlot(const AllanReport& report, const nlohmann::json& json, std::string* png) {
  const char* tmpdir = std::getenv("TMPDIR");
  std::string pattern =
      std::string(tmpdir != nullptr && *tmpdir ? tmpdir : "/tmp") + "/accelcal_allan.XXXXXX";
  std::vector<char> buffer(pattern.begin(), pattern.end());
  buffer.push_back('\0');
  std::string dir;
  WithCleanupHeld([&] {
    if (mkdtemp(buffer.data()) != nullptr) {
      dir = buffer.data();
      RegisterTemporary(dir);
    }
  });
  if (dir.empty()) return Status::Error("cannot create a temporary folder for --plot (set TMPDIR)");
  const std::string data_path = dir + "/allan.json";
  const std::string png_path = dir + "/allan.png";
  Status status = WriteJsonAtomically(data_path, json);
  std::string why;
  if (status.ok()) {
    why = Plot({FLAGS_tools_dir, "/usr/bin/python3"}, "plot_allan.py",
               {"--json=" + data_path, "--out=" + png_path});
    std::ifstream file(png_path, std::ios::binary);
    if (why.empty() && file) {
      *png = std::string(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
    } else {
      status = Status::Error("--plot: " +
                             (why.empty() ? std::string("plot_allan.py wrote no figure") : why));
    }
  }
  std::remove(data_path.c_str());
  std::remove(png_path.c_str());
  rmdir(dir.c_str());
  ForgetTemporary(dir);
  (void)report;
  return status;
}

int Run(int argc, char** argv) {
  if (!InitProblem("allan", kUsage, "problems/allan", &argc, &argv)) return kExitBadInput;
  TriadLog log;
  AllanReport report;
  DataSource source;
  std::string json_text, png;
  Status status = ValidateFlags();
  ImuLogReadOptions read_options;
  ImuLogSource log_source;
  if (status.ok()) status = ACCELCAL_IMU_LOG_OPTIONS(&read_options);
  if (status.ok())
    status = ReadImuLog(FLAGS_log, read_options, &log, ImuLogSpacing::kAny, &log_source);
  if (status.ok())
    status = TakeStatedUnit(log_source, &FLAGS_unit, &log_source.notes).WithContext(FLAGS_log);
  if (status.ok()) {
    for (const std::string& note : log_source.notes) std::cerr << "allan: note: " << note << "\n";
  }
  if (status.ok()) status = DescribeMeasuredData("", {{"log", FLAGS_log}}, &source);
  if (status.ok()) status = Solve(log, &report);
  const nlohmann::json json =
      status.ok() ? WithProvenance(AllanJson(report), source) : nlohmann::json();
  if (status.ok() && !FLAGS_json.empty()) status = JsonText(json, &json_text);
  if (status.ok() && !FLAGS_plot.empty()) status = DrawPlot(report, json, &png);
  if (status.ok()) status = WriteOutputFiles({{FLAGS_json, json_text}, {FLAGS_plot, png}});
  if (!status.ok()) return ExitWithError("allan", status);
  std::cout << WithDataLine(source, AllanTable(report)) << std::flush;
  return 0;
}

}  // namespace
}  // namespace accelcal

int main(int argc, char** argv) {
  return accelcal::GuardedMain("allan", accelcal::Run, argc, argv);
}
