#include "estimation/gyroscope/gyroscope_turn_scale.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "common/format.h"
#include "common/vector3.h"

namespace accelcal {
namespace {

constexpr double kFactorToRefuse = 3.0;  // s outside [1/3, 3]
constexpr double kBetterToRefuse = 4.0;  // the miss's mean square 4 times smaller there
constexpr double kMissToRefuse = 0.05;   // rad (about 3 degrees) at s = 1
constexpr double kUnitMatch = 0.1;       // a physical unit's nominal gain within 10%

constexpr size_t kTurnsUsed = 8;
constexpr int kRailRun = 3;
constexpr int kGridSteps = 20;  // the grid: 2^(k/2), k in [-20, 20]
constexpr double kGridLog2 = 0.5;

struct Turn {
  std::vector<std::array<double, 3>> rate;  // at s = 1, rad/s
  std::vector<double> step_s;
  std::array<double, 3> before{}, after{};
};

double MeanSquareMiss(const std::vector<Turn>& turns, double scale) {
  double sum = 0.0;
  for (const Turn& turn : turns) {
    double rotation[9];
    IntegrateAngularRateHermite(
        static_cast<int>(turn.rate.size()),
        [&](int j, double* rate) {
          for (int k = 0; k < 3; ++k) rate[k] = scale * turn.rate[j][k];
        },
        turn.step_s, rotation);
    const std::array<double, 3>& n = turn.before;
    for (int k = 0; k < 3; ++k) {
      const double d =
          rotation[k] * n[0] + rotation[3 + k] * n[1] + rotation[6 + k] * n[2] - turn.after[k];
      sum += d * d;
    }
  }
  return sum / static_cast<double>(turns.size());
}

}  // namespace

GyroscopeTurnScale MeasureGyroscopeTurnScale(const TriadLog& log,
                                             const std::vector<StaticInterval>& intervals,
                                             const std::vector<std::array<double, 3>>& directions,
                                             const GyroscopeParameters& start) {
  GyroscopeTurnScale measured;
  const int poses = static_cast<int>(intervals.size());
  if (!log.has_gyroscope() || log.gyroscope.size() != log.size() ||
      static_cast<int>(directions.size()) != poses || poses < 2)
    return measured;
  GyroscopeOffset offset{};
  for (const StaticInterval& interval : intervals) {
    for (int k = 0; k < 3; ++k) {
      double sum = 0.0;
      for (int i = interval.start; i <= interval.end; ++i) sum += log.gyroscope[i][k];
      offset[k] += sum / interval.sample_count() / poses;
    }
  }
  // Each axis's extreme outputs: a turn that sits at one for kRailRun samples in a row may have
  // turned faster than the gyroscope measures (its integral short), and says nothing of s.
  std::array<double, 3> lowest = log.gyroscope[0], highest = log.gyroscope[0];
  for (const std::array<double, 3>& u : log.gyroscope) {
    for (int k = 0; k < 3; ++k) {
      lowest[k] = std::min(lowest[k], u[k]);
      highest[k] = std::max(highest[k], u[k]);
    }
  }
  std::vector<Turn> turns;
  for (int p = 0; p + 1 < poses; ++p) {
    const int first = intervals[p].end, last = intervals[p + 1].start;
    if (first < 0 || last >= static_cast<int>(log.size()) || last <= first) continue;
    bool at_rail = false;
    for (int k = 0; k < 3 && !at_rail; ++k) {
      int run = 0;
      for (int i = first; i <= last && !at_rail; ++i) {
        const double u = log.gyroscope[i][k];
        run = u == lowest[k] || u == highest[k] ? run + 1 : 0;
        at_rail = run >= kRailRun;
      }
    }
    if (at_rail) continue;
    Turn turn;
    turn.before = directions[p];
    turn.after = directions[p + 1];
    for (int i = first; i <= last; ++i) {
      std::array<double, 3> rate;
      GyroscopeAngularRate(start.data(), offset.data(), log.gyroscope[i].data(), rate.data());
      turn.rate.push_back(rate);
      if (i < last) turn.step_s.push_back(log.timestamp_s[i + 1] - log.timestamp_s[i]);
    }
    turns.push_back(std::move(turn));
  }
  // The turns that tilt most carry the scale most plainly: kTurnsUsed of them suffice (each
  // evaluation integrates them all).
  std::stable_sort(turns.begin(), turns.end(), [](const Turn& a, const Turn& b) {
    return AngleBetween(a.before, a.after) > AngleBetween(b.before, b.after);
  });
  if (turns.size() > kTurnsUsed) turns.resize(kTurnsUsed);
  measured.turns = static_cast<int>(turns.size());
  if (turns.empty()) return measured;
  const double at_one = MeanSquareMiss(turns, 1.0);
  int best = 0;
  double best_miss = at_one;
  for (int k = -kGridSteps; k <= kGridSteps; ++k) {
    const double miss = MeanSquareMiss(turns, std::exp2(k * kGridLog2));
    if (miss < best_miss) {
      best_miss = miss;
      best = k;
    }
  }
  // Golden section in log2 s between the best grid point's neighbours.
  const double ratio = 0.5 * (std::sqrt(5.0) - 1.0);
  double low = (best - 1) * kGridLog2, high = (best + 1) * kGridLog2;
  double a = high - ratio * (high - low), b = low + ratio * (high - low);
  double miss_a = MeanSquareMiss(turns, std::exp2(a)), miss_b = MeanSquareMiss(turns, std::exp2(b));
  for (int iteration = 0; iteration < 20; ++iteration) {
    if (miss_a < miss_b) {
      high = b;
      b = a;
      miss_b = miss_a;
      a = high - ratio * (high - low);
      miss_a = MeanSquareMiss(turns, std::exp2(a));
    } else {
      low = a;
      a = b;
      miss_a = miss_b;
      b = low + ratio * (high - low);
      miss_b = MeanSquareMiss(turns, std::exp2(b));
    }
  }
  const double refined = std::exp2(miss_a < miss_b ? a : b);
  const double refined_miss = std::min(miss_a, miss_b);
  measured.scale = refined_miss <= best_miss ? refined : std::exp2(best * kGridLog2);
  measured.rms_at_one = std::sqrt(at_one);
  measured.rms_at_scale = std::sqrt(std::min(refined_miss, best_miss));
  return measured;
}

Status CheckGyroscopeTurnScale(const GyroscopeTurnScale& measured, const GyroscopeParameters& start,
                               GyroscopeOutputUnit unit) {
  if (measured.turns < 3) return Status::Ok();
  const double s = measured.scale;
  if (s >= 1.0 / kFactorToRefuse && s <= kFactorToRefuse) return Status::Ok();
  if (!(measured.rms_at_one >= kMissToRefuse) ||
      !(measured.rms_at_scale * measured.rms_at_scale * kBetterToRefuse <=
        measured.rms_at_one * measured.rms_at_one)) {
    return Status::Ok();
  }
  double gain = 0.0;
  for (int k = 0; k < 3; ++k) gain += std::abs(start[kGyroscopeGainX + k]) / 3.0;
  const double scaled = s * gain;  // rad/s per unit of the outputs
  std::string flags;
  for (const GyroscopeOutputUnit physical :
       {GyroscopeOutputUnit::kRadPerS, GyroscopeOutputUnit::kDegPerS}) {
    const double nominal = GyroscopeNominalGain(physical);
    if (std::abs(scaled / nominal - 1.0) <= kUnitMatch)
      flags = StringPrintf("--gyro_unit=%s", GyroscopeOutputUnitName(physical));
  }
  if (flags.empty()) flags = StringPrintf("--gyro_unit=count --initial_gyro_gain=%.6g", scaled);
  return Status::Error(StringPrintf(
      "the gyroscope's turns, integrated at the gains the %s outputs start from (%.6g rad/s per "
      "unit), carry the poses' gravity directions to the next poses as if the rates were %.3g "
      "times as large (rms miss %.3g rad at that factor, %.3g rad as given, over %d turns): the "
      "outputs are not in the unit or at the gain given; give %s",
      GyroscopeOutputUnitName(unit), gain, s, measured.rms_at_scale, measured.rms_at_one,
      measured.turns, flags.c_str()));
}

}  // namespace accelcal
