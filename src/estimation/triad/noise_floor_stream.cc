#include "estimation/triad/noise_floor_stream.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <vector>

#include "common/statistics.h"
#include "common/streaming_rank.h"
#include "estimation/statistics/chi_square.h"
#include "estimation/triad/static_intervals.h"
#include "estimation/triad/window_variance_stream.h"

namespace accelcal {
namespace {

// Selection buffers: 2^16 bins, at most 2^19 values kept (4.5 MB a selector, up to six at once).
constexpr int kBinBits = 16;
constexpr int kKeptBits = 19;

using Variances = std::array<double, 3>;
using Selectors = std::array<std::unique_ptr<StreamingRankSelector>, 3>;

Selectors NewSelectors() {
  Selectors selectors;
  for (auto& selector : selectors) {
    selector = std::make_unique<StreamingRankSelector>(0.0, std::numeric_limits<double>::infinity(),
                                                       kBinBits, kKeptBits);
  }
  return selectors;
}

// RankQuantile's rank (common/statistics.h) among `size` values.
uint64_t QuantileRank(double q, uint64_t size) {
  return static_cast<uint64_t>(q * static_cast<double>(size - 1) + 0.5);
}

// One pass over the log: visit(j, V_j) for every window in order; OutputSteps into *step when
// given.
template <typename Visit>
Status ForEachWindow(const TriadSampleSource& log, int window, Visit&& visit,
                     std::array<double, 3>* step = nullptr) {
  WindowVarianceStream stream(window);
  long long j = 0;
  std::array<double, 3> previous{};
  return ForEachSample(log, 0, log.size() - 1,
                       [&](size_t i, double, const std::array<double, 3>& output) {
                         if (step != nullptr && i > 0) UpdateOutputSteps(previous, output, step);
                         previous = output;
                         if (stream.Add(output)) visit(j++, stream.variance());
                       });
}

// visit(j, V_j) for the windows j = first .. last (inclusive) only, reading from the sample
// where the stream re-anchors at or before `first` (a multiple of the window), so that every V_j
// is the whole pass's to the last bit.
template <typename Visit>
Status ForEachWindowIn(const TriadSampleSource& log, int window, long long first, long long last,
                       Visit&& visit) {
  const long long anchor = first / window * window;
  WindowVarianceStream stream(window);
  long long j = anchor;
  return ForEachSample(log, static_cast<size_t>(anchor), static_cast<size_t>(last + window - 1),
                       [&](size_t, double, const std::array<double, 3>& output) {
                         if (!stream.Add(output)) return;
                         if (j >= first) visit(j, stream.variance());
                         ++j;
                       });
}

// Passes of `pass` until every selector of `groups` has its rank, which rank(group, axis) gives
// after each pass (the counts a pass makes may set it); none once a pass leaves *values at 0 (no
// value to select from).
Status SelectAll(const std::vector<Selectors*>& groups, const std::function<Status(int)>& pass,
                 const std::function<uint64_t(size_t, int)>& rank, const long long* values) {
  for (int number = 0;; ++number) {
    ACCELCAL_RETURN_IF_ERROR(pass(number));
    if (*values == 0) return Status::Ok();
    bool done = true;
    for (size_t group = 0; group < groups.size(); ++group) {
      for (int axis = 0; axis < 3; ++axis)
        done = (*groups[group])[axis]->FinishPass(rank(group, axis)) && done;
    }
    if (done) return Status::Ok();
  }
}

void AddAll(Selectors* selectors, const Variances& values) {
  for (int axis = 0; axis < 3; ++axis) (*selectors)[axis]->Add(values[axis]);
}

bool Below(const Variances& v, const Variances& threshold) {
  return v[0] < threshold[0] && v[1] < threshold[1] && v[2] < threshold[2];
}

// A run of still windows [first, last] with its threshold (SortRuns' input).
struct StillRun {
  long long first = 0;
  long long last = 0;
  Variances threshold{};
};

// The runs of `still` (windows offset by `first`) with `threshold`, appended to *runs.
void AppendRuns(const std::vector<bool>& still, long long first, const Variances& threshold,
                std::vector<StillRun>* runs) {
  for (size_t i = 0; i < still.size();) {
    if (!still[i]) {
      ++i;
      continue;
    }
    size_t last = i;
    while (last + 1 < still.size() && still[last + 1]) ++last;
    runs->push_back(
        {first + static_cast<long long>(i), first + static_cast<long long>(last), threshold});
    i = last + 1;
  }
}

// SortRuns of noise_floor_detector.cc on the runs, each interval described from the samples.
Status SortStillRuns(const TriadSampleSource& log, const NoiseFloorOptions& options,
                     const std::vector<StillRun>& runs, NoiseFloorDetection* detection) {
  const int half = options.window_samples / 2;
  for (const StillRun& run : runs) {
    StaticInterval interval;
    interval.start = static_cast<int>(run.first + half);
    interval.end = static_cast<int>(run.last + half);
    ACCELCAL_RETURN_IF_ERROR(DescribeInterval(log, &interval));
    FileInterval(interval, run.threshold, options, detection);
  }
  return Status::Ok();
}

// What both rules share: the window's white-noise quantiles c(q), the 5 % quantiles of V, the
// output's step.
struct Common {
  int window = 0;
  long long count = 0;  // windows
  double factor = 0.0;
  double c05 = 0.0, c10 = 0.0, c50 = 0.0;
  Variances q05{};
  std::array<double, 3> step{};
};

bool ShapesPass(const Selectors& median, const Selectors& low, double white_shape,
                std::array<double, 3>* shape) {
  bool pass = true;
  for (int axis = 0; axis < 3; ++axis) {
    const double m = median[axis]->value();
    (*shape)[axis] = m > 0.0 ? low[axis]->value() / m / white_shape : 0.0;
    pass = pass && (*shape)[axis] >= noise_floor::kMinFloorShape;
  }
  return pass;
}

// The per-pose rule (PoseFloorRule); *accepted false where it refuses. *stuck: StuckAxis's
// answer with its loose thresholds.
Status PoseFloors(const TriadSampleSource& log, const NoiseFloorOptions& options,
                  size_t max_run_windows, const Common& common, NoiseFloorDetection* detection,
                  bool* accepted, bool* stuck) {
  *accepted = false;
  *stuck = false;
  const double factor = common.factor;
  Variances resolution{}, loose{};
  for (int axis = 0; axis < 3; ++axis) {
    resolution[axis] = common.step[axis] * common.step[axis] / 12.0;
    detection->floor_variance[axis] = std::max(common.q05[axis] / common.c05, resolution[axis]);
    detection->floor_stddev[axis] = std::sqrt(detection->floor_variance[axis]);
    loose[axis] = factor * noise_floor::kPoseFloorSpread * detection->floor_variance[axis];
    detection->threshold_variance[axis] = loose[axis];
  }
  Selectors median = NewSelectors(), low = NewSelectors();
  std::vector<StillRun> runs;
  long long still_count = 0;
  std::array<long long, 3> moving{}, constant{};
  std::vector<Variances> run;  // the candidate run's V
  long long run_first = 0;
  long long run_last = 0;
  bool run_long = false;  // longer than max_run_windows: its V are not held (close_long_run)
  // The two thresholds of each long run (a window is still below both), in the order of the
  // runs, found in the first pass and reused in the next.
  std::vector<std::array<Variances, 2>> long_thresholds;
  size_t long_index = 0;
  Status long_status;
  bool first_pass = true;
  // A candidate run's own floor, twice, and its still windows (PoseFloorRule's loop).
  auto close_run = [&] {
    std::vector<bool> keep(run.size(), true);
    Variances threshold = loose;
    for (int pass = 0; pass < 2; ++pass) {
      for (int axis = 0; axis < 3; ++axis) {
        std::vector<double> values;
        for (size_t i = 0; i < run.size(); ++i)
          if (keep[i]) values.push_back(run[i][axis]);
        if (values.empty()) break;
        const double floor = std::max(RankQuantile(&values, 0.5) / common.c50, resolution[axis]);
        threshold[axis] = std::min(loose[axis], factor * floor);
      }
      for (size_t i = 0; i < run.size(); ++i) keep[i] = keep[i] && Below(run[i], threshold);
    }
    for (size_t i = 0; i < run.size(); ++i) {
      if (!keep[i]) continue;
      if (first_pass) ++still_count;
      Variances ratio;
      for (int axis = 0; axis < 3; ++axis)
        ratio[axis] = std::max(run[i][axis], resolution[axis]) / threshold[axis];
      AddAll(&median, ratio);
      AddAll(&low, ratio);
    }
    if (first_pass) AppendRuns(keep, run_first, threshold, &runs);
    run.clear();
  };
  // close_run for a run too long to hold (a still log of hours is one run): the same floors,
  // thresholds and still windows, from passes over the run's windows (ForEachWindowIn) instead
  // of their values held.
  auto close_long_run = [&] {
    const long long first = run_first, last = run_last;
    run_long = false;
    run.clear();
    if (!long_status.ok()) return;
    if (first_pass) {
      std::array<Variances, 2> thresholds;
      Variances threshold = loose;
      for (int pass = 0; pass < 2 && long_status.ok(); ++pass) {
        Selectors run_median = NewSelectors();
        long long kept = 0;
        long_status = SelectAll(
            {&run_median},
            [&](int number) {
              return ForEachWindowIn(log, common.window, first, last,
                                     [&](long long, const Variances& v) {
                                       for (int earlier = 0; earlier < pass; ++earlier)
                                         if (!Below(v, thresholds[earlier])) return;
                                       if (number == 0) ++kept;
                                       AddAll(&run_median, v);
                                     });
            },
            [&](size_t, int) { return QuantileRank(0.5, kept); }, &kept);
        for (int axis = 0; axis < 3 && kept > 0; ++axis) {
          const double floor = std::max(run_median[axis]->value() / common.c50, resolution[axis]);
          threshold[axis] = std::min(loose[axis], factor * floor);
        }
        thresholds[pass] = threshold;
      }
      long_thresholds.push_back(thresholds);
    }
    if (!long_status.ok() || long_index >= long_thresholds.size()) return;
    const std::array<Variances, 2> thresholds = long_thresholds[long_index++];
    // The still windows: ratios into the selections, and (first pass) their runs and count.
    long long kept_first = -1, kept_last = -1;
    long_status =
        ForEachWindowIn(log, common.window, first, last, [&](long long j, const Variances& v) {
          const bool keep = Below(v, thresholds[0]) && Below(v, thresholds[1]);
          if (first_pass && !keep && kept_first >= 0) {
            runs.push_back({kept_first, kept_last, thresholds[1]});
            kept_first = -1;
          }
          if (!keep) return;
          if (first_pass) {
            ++still_count;
            if (kept_first < 0) kept_first = j;
            kept_last = j;
          }
          Variances ratio;
          for (int axis = 0; axis < 3; ++axis)
            ratio[axis] = std::max(v[axis], resolution[axis]) / thresholds[1][axis];
          AddAll(&median, ratio);
          AddAll(&low, ratio);
        });
    if (first_pass && kept_first >= 0) runs.push_back({kept_first, kept_last, thresholds[1]});
  };
  auto close = [&] {
    if (run_long) {
      close_long_run();
    } else {
      close_run();
    }
  };
  auto pass = [&](int number) {
    first_pass = number == 0;
    long_index = 0;
    const Status status = ForEachWindow(log, common.window, [&](long long j, const Variances& v) {
      if (first_pass) {
        for (int axis = 0; axis < 3; ++axis) {
          bool other_moves = false;
          for (int other = 0; other < 3; ++other)
            other_moves = other_moves || (other != axis && v[other] > loose[other]);
          if (!other_moves) continue;
          ++moving[axis];
          if (v[axis] == 0.0) ++constant[axis];
        }
      }
      if (Below(v, loose)) {
        if (run.empty() && !run_long) run_first = j;
        run_last = j;
        if (run_long) return;
        if (run.size() >= max_run_windows) {
          run_long = true;
          std::vector<Variances>().swap(run);
        } else {
          run.push_back(v);
        }
      } else if (!run.empty() || run_long) {
        close();
      }
    });
    if (!run.empty() || run_long) close();
    ACCELCAL_RETURN_IF_ERROR(long_status);
    return status;
  };
  ACCELCAL_RETURN_IF_ERROR(pass(0));
  for (int axis = 0; axis < 3; ++axis) {
    *stuck = *stuck || common.step[axis] == 0.0 ||
             (moving[axis] > 0 && 2 * constant[axis] > moving[axis]);
  }
  if (*stuck) return Status::Ok();
  detection->still_fraction = static_cast<double>(still_count) / common.count;
  if (still_count > 0) {
    // The first pass's values are in; the selections finish in further passes.
    std::vector<Selectors*> groups = {&median, &low};
    auto rank = [&](size_t group, int) {
      return QuantileRank(group == 0 ? 0.5 : noise_floor::kShapeLowQuantile, still_count);
    };
    bool done = true;
    for (int axis = 0; axis < 3; ++axis) {
      done = median[axis]->FinishPass(rank(0, axis)) && done;
      done = low[axis]->FinishPass(rank(1, axis)) && done;
    }
    if (!done)
      ACCELCAL_RETURN_IF_ERROR(SelectAll(
          groups, [&](int) { return pass(1); }, rank, &still_count));
    const double white_shape = common.c10 / common.c50;
    if (!ShapesPass(median, low, white_shape, &detection->floor_shape)) return Status::Ok();
  }
  if (detection->still_fraction < noise_floor::kMinStillFraction) return Status::Ok();
  ACCELCAL_RETURN_IF_ERROR(SortStillRuns(log, options, runs, detection));
  *accepted = true;
  return Status::Ok();
}

// The single floor (GlobalFloorRule); *accepted false where it refuses.
Status GlobalFloor(const TriadSampleSource& log, const NoiseFloorOptions& options,
                   const Common& common, NoiseFloorDetection* detection, bool* accepted) {
  *accepted = false;
  const double factor = common.factor;
  Variances provisional{};
  for (int axis = 0; axis < 3; ++axis) {
    provisional[axis] = factor * common.q05[axis] / common.c05;
    if (!(provisional[axis] > 0.0)) return Status::Ok();
  }
  // The provisional still windows' medians.
  Selectors median = NewSelectors();
  long long provisional_count = 0;
  ACCELCAL_RETURN_IF_ERROR(SelectAll(
      {&median},
      [&](int number) {
        return ForEachWindow(log, common.window, [&](long long, const Variances& v) {
          if (!Below(v, provisional)) return;
          if (number == 0) ++provisional_count;
          AddAll(&median, v);
        });
      },
      [&](size_t, int) { return QuantileRank(0.5, provisional_count); }, &provisional_count));
  if (provisional_count == 0) return Status::Ok();  // no still window: refused
  for (int axis = 0; axis < 3; ++axis) {
    detection->floor_variance[axis] = median[axis]->value() / common.c50;
    if (!(detection->floor_variance[axis] > 0.0)) return Status::Ok();
    detection->floor_stddev[axis] = std::sqrt(detection->floor_variance[axis]);
    detection->threshold_variance[axis] = factor * detection->floor_variance[axis];
  }
  const Variances threshold = detection->threshold_variance;
  // The still windows: their count, runs, medians and 10 % quantiles.
  Selectors still_median = NewSelectors(), still_low = NewSelectors();
  long long still_count = 0;
  // The current run of still windows by its first window and length (not a flag per window:
  // a still log of 10^8 samples is one run).
  long long run_length = 0;
  long long run_first = 0;
  std::vector<StillRun> runs;
  ACCELCAL_RETURN_IF_ERROR(SelectAll(
      {&still_median, &still_low},
      [&](int number) {
        return ForEachWindow(log, common.window, [&](long long j, const Variances& v) {
          const bool still = Below(v, threshold);
          if (number == 0) {
            if (still && run_length == 0) run_first = j;
            if (still) {
              ++run_length;
              ++still_count;
            } else if (run_length > 0) {
              runs.push_back({run_first, run_first + run_length - 1, threshold});
              run_length = 0;
            }
          }
          if (!still) return;
          AddAll(&still_median, v);
          AddAll(&still_low, v);
        });
      },
      [&](size_t group, int) {
        return QuantileRank(group == 0 ? 0.5 : noise_floor::kShapeLowQuantile, still_count);
      },
      &still_count));
  if (run_length > 0) runs.push_back({run_first, run_first + run_length - 1, threshold});
  detection->still_fraction = static_cast<double>(still_count) / common.count;
  if (still_count > 0) {
    const double white_shape = common.c10 / common.c50;
    if (!ShapesPass(still_median, still_low, white_shape, &detection->floor_shape))
      return Status::Ok();
  }
  if (detection->still_fraction < noise_floor::kMinStillFraction) return Status::Ok();
  ACCELCAL_RETURN_IF_ERROR(SortStillRuns(log, options, runs, detection));
  *accepted = true;
  return Status::Ok();
}

}  // namespace

Status DetectStaticIntervalsFromNoiseFloorStreamed(const TriadSampleSource& log,
                                                   const NoiseFloorStreamOptions& stream_options,
                                                   NoiseFloorDetection* detection, bool* decided) {
  *decided = false;
  *detection = NoiseFloorDetection();
  NoiseFloorOptions options = stream_options.detector;
  if (options.min_intervals != 0 || log.size() < 2) return Status::Ok();
  TriadLog ends;
  ACCELCAL_RETURN_IF_ERROR(log.Read(0, 1, &ends));
  const double first_s = ends.timestamp_s[0];
  ACCELCAL_RETURN_IF_ERROR(log.Read(log.size() - 1, 1, &ends));
  if (options.window_samples == 0)
    options.window_samples = DefaultNoiseFloorWindow(log.size(), ends.timestamp_s[0] - first_s);
  if (!CheckNoiseFloorOptions(options).ok()) return Status::Ok();
  Common common;
  common.window = options.window_samples;
  if (static_cast<long long>(log.size()) < common.window) return Status::Ok();
  common.count = static_cast<long long>(log.size()) - common.window + 1;
  common.factor = options.threshold_factor;
  const double dof = common.window - 1;
  common.c05 = ChiSquareQuantile(noise_floor::kFloorQuantile, dof) / dof;
  common.c10 = ChiSquareQuantile(noise_floor::kShapeLowQuantile, dof) / dof;
  common.c50 = ChiSquareQuantile(0.5, dof) / dof;
  detection->window_samples = common.window;
  detection->white_false_alarm = ChiSquareSurvival(common.factor * dof, dof);
  // The 5 % quantiles, and the output's steps in the first pass.
  Selectors q05 = NewSelectors();
  ACCELCAL_RETURN_IF_ERROR(SelectAll(
      {&q05},
      [&](int number) {
        return ForEachWindow(
            log, common.window, [&](long long, const Variances& v) { AddAll(&q05, v); },
            number == 0 ? &common.step : nullptr);
      },
      [&](size_t, int) { return QuantileRank(noise_floor::kFloorQuantile, common.count); },
      &common.count));
  for (int axis = 0; axis < 3; ++axis) common.q05[axis] = q05[axis]->value();
  q05 = Selectors();
  NoiseFloorDetection pose_floors = *detection;
  pose_floors.rule = kPoseFloorsRule;
  bool per_pose = false, stuck = false;
  ACCELCAL_RETURN_IF_ERROR(PoseFloors(log, options, stream_options.max_run_windows, common,
                                      &pose_floors, &per_pose, &stuck));
  if (stuck) return Status::Ok();
  detection->rule = kGlobalFloorRule;
  bool global = false;
  ACCELCAL_RETURN_IF_ERROR(GlobalFloor(log, options, common, detection, &global));
  // DetectWithWindow's choice, where it does not quote the single floor's refusal.
  if (global && !(per_pose && pose_floors.intervals.size() > detection->intervals.size())) {
    *decided = true;
  } else if (global && per_pose) {
    pose_floors.rule_reason = MorePosesReason(
        detection->intervals.size(), pose_floors.intervals.size(), options.threshold_factor);
    *detection = std::move(pose_floors);
    *decided = true;
  }
  return Status::Ok();
}

}  // namespace accelcal
