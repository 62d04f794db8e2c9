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
#include <cstdint>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <sstream>

#include "common/format.h"
#include "common/streaming_rank.h"
#include "common/triad_sample_source.h"
#include "estimation/statistics/allan_variance.h"
#include "estimation/triad/noise_floor_detector.h"
#include "estimation/triad/noise_floor_stream.h"
#include "io/cleanup.h"
#include "io/course_data.h"
#include "io/csv_reader.h"
#include "io/imu_log.h"
#include "io/sample_spool.h"
#include "models/triad_units.h"
#include "problem_support.h"
#include "reporting/allan_report.h"
#include "reporting/analyze_report.h"
#include "reporting/progress_printer.h"
#include "studies/allan_study.h"

DEFINE_string(log, "",
              "The accelerometer log, in any layout calibrate_imu reads (docs/log-layouts.md): "
              "imu_tk's ASCII layout (t [s], x, y, z), CSV or other text with a header, a .mat.");
ACCELCAL_DEFINE_IMU_LOG_FLAGS();
ACCELCAL_DEFINE_PROGRESS_FLAG();
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
DEFINE_bool(stream, true,
            "Read a text log in passes over a temporary binary copy of its samples: memory "
            "independent of the log's length (docs/noise.md, long data). A .mat log and a pair of "
            "files are read whole whatever this says; --stream=false reads a text log whole too "
            "(the same results, for comparison).");
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
    "A text log is read in passes over a temporary binary copy of its samples (32 bytes a sample\n"
    "in $TMPDIR), in memory independent of its length, its segments' included; a MATLAB .mat\n"
    "file is read whole. The bootstrap's cost does not grow with the data beyond 2^16 samples of\n"
    "static data (docs/noise.md, long data). --progress shows the steps on a terminal.";

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

// Streaming (issue 36, item 2). A text log is spooled to a temporary binary file as it is read
// (io/sample_spool.h) and everything below reads it back in passes, holding what does not grow
// with the log: the exact medians (the step, |u - offset|) by StreamingRankSelector
// (common/streaming_rank.h), the static detector in its streamed form
// (estimation/triad/noise_floor_stream.h; a run of candidate windows longer than 2^16 in passes
// over it), the step check and the Allan sums of each segment in passes over it
// (AllanVarianceAccumulator::AddStreamed: a ring of sums and cursors, never the segment whole,
// so that a still log of 10^8 samples, one segment, fits in the same memory as a short one;
// issue 49, item 1). The results are the whole-log path's to the last bit
// (the same arithmetic in the same order). A .mat log, a log whose rows are ordered by sample
// number, a read or time check that fails, or a log the detector refuses is read whole after
// all (ReadImuLog), so that the message is the whole path's: a refused log's cost.

// The value of rank `rank` (from 0) of the values `pass` adds, exactly, in passes (selection
// buffers of 4.5 MB: 2^16 bins, at most 2^19 values kept).
Status SelectRank(uint64_t rank, const std::function<Status(int, StreamingRankSelector*)>& pass,
                  double* value) {
  StreamingRankSelector selector(0.0, std::numeric_limits<double>::infinity(), 16, 19);
  int number = 0;
  do {
    ACCELCAL_RETURN_IF_ERROR(pass(number++, &selector));
  } while (!selector.FinishPass(rank));
  *value = selector.value();
  return Status::Ok();
}

// What allan needs of the whole log besides its segments.
struct SampleFacts {
  double first_s = 0.0;
  double last_s = 0.0;
  double lowest = 0.0;  // of the outputs, and 0
  double highest = 0.0;
  // CheckLogTime's median step, the sample period: the value of rank (n - 1) / 2 of the n - 1
  // steps.
  double step_s = 0.0;
};

// The facts in one pass over the log (and more for the median step when its first cannot
// hold the candidates). At least 2 samples.
Status ScanSamples(const TriadSampleSource& log, SampleFacts* facts) {
  return SelectRank((log.size() - 1) / 2,
                    [&](int number, StreamingRankSelector* selector) {
                      double previous_s = 0.0;
                      return ForEachSample(
                          log, 0, log.size() - 1,
                          [&](size_t i, double t_s, const std::array<double, 3>& u) {
                            if (i > 0) selector->Add(t_s - previous_s);
                            previous_s = t_s;
                            if (number > 0) return;
                            facts->first_s = i == 0 ? t_s : facts->first_s;
                            facts->last_s = t_s;
                            for (double value : u) {
                              facts->lowest = std::min(facts->lowest, value);
                              facts->highest = std::max(facts->highest, value);
                            }
                          });
                    },
                    &facts->step_s);
}

double TimeAt(const TriadSampleSource& log, size_t i, Status* status) {
  TriadLog sample;
  *status = log.Read(i, 1, &sample);
  return status->ok() ? sample.timestamp_s[0] : 0.0;
}

// A segment of samples [first, last] (0-based, inclusive).
struct SampleRange {
  long long first = 0;
  long long last = 0;
};

// The samples of each --segment START:END: from the first at or after START to the last at or
// before END (lower_bound and upper_bound on the increasing time axis), by counting.
Status SegmentRanges(const TriadSampleSource& log,
                     const std::vector<std::pair<double, double>>& wanted,
                     std::vector<SampleRange>* ranges) {
  std::vector<long long> before(wanted.size(), 0), through(wanted.size(), 0);
  ACCELCAL_RETURN_IF_ERROR(
      ForEachSample(log, 0, log.size() - 1, [&](size_t, double t_s, const std::array<double, 3>&) {
        for (size_t w = 0; w < wanted.size(); ++w) {
          before[w] += t_s < wanted[w].first ? 1 : 0;
          through[w] += t_s <= wanted[w].second ? 1 : 0;
        }
      }));
  for (size_t w = 0; w < wanted.size(); ++w) ranges->push_back({before[w], through[w] - 1});
  return Status::Ok();
}

// The segments' Allan variances: the step check of each segment against the median step tau0
// (every step within 50% of it: a gap would put unequal spacing into the clusters), then its
// samples in the result unit into the three axes' sums, one segment held at a time.
Status AccumulateSegments(const TriadSampleSource& log, const std::vector<SampleRange>& ranges,
                          double first_s, double last_s, AllanReport* report) {
  const double tau0 = report->sample_period_s;
  std::vector<long long> sizes;
  for (const SampleRange& range : ranges) sizes.push_back(range.last - range.first + 1);
  std::array<AllanVarianceAccumulator, 3> sums;
  std::array<Status, 3> axis;  // each axis's first failure, said in the axes' order
  for (int k = 0; k < 3; ++k) axis[k] = sums[k].Start(tau0, report->options, sizes);
  TriadLog batch;
  for (size_t s = 0; s < ranges.size(); ++s) {
    // The steps in one pass; the first outside 50% of tau0 is the one said.
    bool gap = false;
    double previous_s = 0.0, gap_step = 0.0, gap_at_s = 0.0;
    ACCELCAL_RETURN_IF_ERROR(ForEachSample(log, ranges[s].first, ranges[s].last,
                                           [&](size_t i, double t_s, const std::array<double, 3>&) {
                                             const double step = t_s - previous_s;
                                             previous_s = t_s;
                                             if (gap || i == static_cast<size_t>(ranges[s].first))
                                               return;
                                             if (step > 1.5 * tau0 || step < 0.5 * tau0) {
                                               gap = true;
                                               gap_step = step;
                                               gap_at_s = t_s;
                                             }
                                           }));
    if (gap) {
      const AllanSegment& where = report->segments[s];
      return Status::Error(StringPrintf(
          "%s: a step of %.6g s at t = %.6g s in segment %.3f..%.3f s, against the median "
          "%.6g s; an Allan variance needs uniform sampling: choose a segment without the gap, "
          "or, if the time stamps only jitter (a host's), give --rate_hz=%.4g to time the "
          "samples by their order",
          FLAGS_log.c_str(), gap_step, gap_at_s, where.start_s, where.end_s, tau0,
          (log.size() - 1) / (last_s - first_s)));
    }
    // Each axis's sums from the segment read in passes (AddStreamed: memory independent of its
    // length).
    for (int k = 0; k < 3; ++k) {
      if (!axis[k].ok()) continue;
      axis[k] =
          sums[k].AddStreamed(sizes[s], [&](long long first, long long count, double* values) {
            ACCELCAL_RETURN_IF_ERROR(log.Read(ranges[s].first + first, count, &batch));
            for (long long i = 0; i < count; ++i) values[i] = report->gain * batch.output[i][k];
            return Status::Ok();
          });
    }
  }
  for (int k = 0; k < 3; ++k) {
    if (axis[k].ok()) axis[k] = sums[k].Finish(&report->curves[k]);
    ACCELCAL_RETURN_IF_ERROR(axis[k].WithContext(FLAGS_log + std::string(", axis ") + "xyz"[k]));
  }
  return Status::Ok();
}

// `log` is the samples; `whole` the log in memory when it was read whole (its detector then
// says why it refuses), else null: then *read_whole is set when the streamed detector cannot
// decide, and nothing else is known.
// What a run shows on a terminal (--progress): its steps as each starts and ends.
constexpr int kSteps = 5;

Status Solve(const TriadSampleSource& log, const SampleFacts& facts, const TriadLog* whole,
             ProgressPrinter* progress, AllanReport* report, bool* read_whole) {
  *read_whole = false;
  TriadOutputUnit unit;
  ACCELCAL_RETURN_IF_ERROR(ParseTriadOutputUnit(FLAGS_unit, &unit));
  const double first_s = facts.first_s, last_s = facts.last_s;
  // A log in m/s^2 said to be in counts (or the reverse) would give every term in the wrong
  // unit; the outputs' magnitude tells, as calibrate_imu checks it.
  const double offset =
      unit == TriadOutputUnit::kCount ? AdcMidScale(facts.lowest, facts.highest) : 0.0;
  double median_magnitude = 0.0;
  ACCELCAL_RETURN_IF_ERROR(SelectRank(
      log.size() / 2,
      [&](int, StreamingRankSelector* selector) {
        return ForEachSample(log, 0, log.size() - 1,
                             [&](size_t, double, const std::array<double, 3>& u) {
                               selector->Add(OutputMagnitude(u, offset));
                             });
      },
      &median_magnitude));
  ACCELCAL_RETURN_IF_ERROR(
      CheckMedianMagnitudeMatchesUnit(median_magnitude, unit, offset).WithContext(FLAGS_log));
  progress->EndStep();
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
  progress->StartStep(3, kSteps, "the static segments");
  NoiseFloorStreamOptions detector;
  // Runs of more windows than this are found in passes over them: the same detection in less
  // memory (24 MB at the default 2^20, under 2 MB here).
  detector.max_run_windows = size_t{1} << 16;
  detector.detector.min_intervals = 0;
  NoiseFloorDetection detection;
  Status detected;
  if (whole != nullptr) {
    detected = DetectStaticIntervalsFromNoiseFloor(*whole, detector.detector, &detection);
  } else {
    bool decided = false;
    ACCELCAL_RETURN_IF_ERROR(
        DetectStaticIntervalsFromNoiseFloorStreamed(log, detector, &detection, &decided));
    if (!decided) {
      *read_whole = true;
      return Status::Ok();
    }
  }
  std::vector<SampleRange> ranges;
  if (!FLAGS_segment.empty()) {
    std::vector<std::pair<double, double>> wanted;
    ACCELCAL_RETURN_IF_ERROR(ParseSegments(&wanted));
    report->selection = "--segment";
    ACCELCAL_RETURN_IF_ERROR(SegmentRanges(log, wanted, &ranges));
    for (size_t w = 0; w < wanted.size(); ++w) {
      const long long count = ranges[w].last - ranges[w].first + 1;
      if (count < 4) {
        return Status::Error(StringPrintf(
            "--segment %g:%g holds %lld samples of %s (t = %.3f .. %.3f s); an Allan variance "
            "needs at least 4",
            wanted[w].first, wanted[w].second, std::max(0LL, count), FLAGS_log.c_str(), first_s,
            last_s));
      }
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
    for (const StaticInterval& interval : chosen) ranges.push_back({interval.start, interval.end});
  }
  for (const SampleRange& range : ranges) {
    AllanSegment segment;
    Status read;
    segment.start_s = TimeAt(log, range.first, &read);
    ACCELCAL_RETURN_IF_ERROR(read);
    segment.end_s = TimeAt(log, range.last, &read);
    ACCELCAL_RETURN_IF_ERROR(read);
    segment.sample_count = range.last - range.first + 1;
    report->segments.push_back(segment);
  }
  report->sample_period_s = facts.step_s;
  report->options.confidence = FLAGS_confidence;
  progress->EndStep();
  progress->StartStep(4, kSteps, "the Allan variance");
  ACCELCAL_RETURN_IF_ERROR(AccumulateSegments(log, ranges, first_s, last_s, report));
  progress->EndStep();
  progress->StartStep(5, kSteps,
                      StringPrintf("the noise fit (%d bootstrap series)", FLAGS_bootstrap));
  report->bootstrap_series = FLAGS_bootstrap;
  // One bootstrap table serves the three axes: they share the segments and taus.
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
  progress->EndStep();
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

// The log read whole (a .mat log, --stream=false, or what the streamed path hands back).
Status SolveWhole(const ImuLogReadOptions& read_options, ProgressPrinter* progress,
                  AllanReport* report, DataSource* source) {
  progress->StartStep(1, kSteps, "reading the log whole");
  TriadLog log;
  ImuLogSource log_source;
  ACCELCAL_RETURN_IF_ERROR(
      ReadImuLog(FLAGS_log, read_options, &log, ImuLogSpacing::kAny, &log_source));
  ACCELCAL_RETURN_IF_ERROR(
      TakeStatedUnit(log_source, &FLAGS_unit, &log_source.notes).WithContext(FLAGS_log));
  for (const std::string& note : log_source.notes) std::cerr << "allan: note: " << note << "\n";
  ACCELCAL_RETURN_IF_ERROR(DescribeMeasuredData("", {{"log", FLAGS_log}}, source));
  const TriadLogSamples samples(log);
  SampleFacts facts;
  progress->EndStep();
  progress->StartStep(2, kSteps, "the sample period and the outputs' unit");
  ACCELCAL_RETURN_IF_ERROR(ScanSamples(samples, &facts));
  bool read_whole = false;
  return Solve(samples, facts, &log, progress, report, &read_whole);
}

// The streamed path: *solved false (nothing printed, nothing changed) when the log must be read
// whole after all.
Status SolveStreamed(const ImuLogReadOptions& read_options, ProgressPrinter* progress,
                     AllanReport* report, DataSource* source, bool* solved) {
  *solved = false;
  if (!DescribeMeasuredData("", {{"log", FLAGS_log}}, source).ok()) return Status::Ok();
  // No room for the spool in $TMPDIR (missing, read-only, full): the log is read whole instead,
  // and a note says so, with what it costs and what to do (issue 45: it read 910 MB silently).
  const auto whole_instead = [&](const Status& why) {
    progress->Close();
    std::cerr << "allan: note: the log is read whole into memory (some 100 bytes per sample), "
                 "not streamed: its temporary copy in $TMPDIR could not be written ("
              << why.message()
              << "); set TMPDIR to a writable folder with room for 32 bytes per sample\n";
    return Status::Ok();
  };
  progress->StartStep(1, kSteps, "reading the log");
  SampleSpool spool;
  const Status opened = spool.Open();
  if (!opened.ok()) return whole_instead(opened);
  Status spooled;
  ImuLogSource log_source;
  const Status read = StreamImuLog(
      FLAGS_log, read_options, 1 << 16,
      [&](const TriadLog& batch) {
        for (size_t i = 0; i < batch.size() && spooled.ok(); ++i)
          spooled = spool.Append(batch.timestamp_s[i], batch.output[i]);
      },
      &log_source);
  if (!read.ok() || log_source.times_need_whole_log) return Status::Ok();
  if (!spooled.ok()) return whole_instead(spooled);
  const Status finished = spool.Finish();
  if (!finished.ok()) return whole_instead(finished);
  // ReadImuLog's time checks (CheckTimeUnit, CheckLogTime) on the median step.
  if (spool.size() < 2) return Status::Ok();
  progress->EndStep();
  progress->StartStep(2, kSteps, "the sample period and the outputs' unit");
  SampleFacts facts;
  ACCELCAL_RETURN_IF_ERROR(ScanSamples(spool, &facts));
  if (facts.step_s < kMinRunStepS || facts.step_s > kMaxRunStepS) return Status::Ok();
  const std::string unit = FLAGS_unit;
  ACCELCAL_RETURN_IF_ERROR(
      TakeStatedUnit(log_source, &FLAGS_unit, &log_source.notes).WithContext(FLAGS_log));
  bool read_whole = false;
  const Status solve = Solve(spool, facts, nullptr, progress, report, &read_whole);
  if (read_whole) {
    progress->Close();
    FLAGS_unit = unit;
    *report = AllanReport();
    return Status::Ok();
  }
  *solved = true;
  for (const std::string& note : log_source.notes) std::cerr << "allan: note: " << note << "\n";
  return solve;
}

int Run(int argc, char** argv) {
  if (!InitProblem("allan", kUsage, "problems/allan", &argc, &argv)) return kExitBadInput;
  AllanReport report;
  DataSource source;
  std::string json_text, png;
  Status status = ValidateFlags();
  ImuLogReadOptions read_options;
  if (status.ok()) status = ACCELCAL_IMU_LOG_OPTIONS(&read_options);
  ProgressStyle progress_style;
  if (status.ok()) status = ProgressStyleFromFlag(FLAGS_progress, &progress_style);
  if (!status.ok()) progress_style.show = false;
  ProgressPrinter progress("allan", "steps", progress_style, &std::cerr);
  bool solved = false;
  if (status.ok() && FLAGS_stream && StreamsLikeReadImuLog(FLAGS_log, read_options))
    status = SolveStreamed(read_options, &progress, &report, &source, &solved);
  if (status.ok() && !solved) status = SolveWhole(read_options, &progress, &report, &source);
  progress.Close();  // a step that failed left its line open on a terminal
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
