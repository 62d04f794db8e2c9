// hand_held_log: writes a simulated hand-held session of an Xsens-like IMU (accelerometer and
// gyroscope in counts, 100 Hz by default) as imu_tk's two ASCII files, "t x y z" per line, for
// the benchmarks that run imu_tk's own example beside calibrate_imu at any size
// (tools/bench/imu_tk_scale_bench.sh). The session is what imu_tk's example expects: an initial
// rest (50 s), then holds of uniformly drawn length in random directions at least
// --min_turn_deg apart, with turns of --turn_s between them, each also turning about gravity by
// up to 90 degrees (simulation/triad_log_simulator.h); the log is cut at --rows samples. The
// truths are studies/'s Xsens-like triad and gyroscope; the noise is Xsens's own (about 3.2
// counts per sample on the accelerometer, 27 on the gyroscope), rounded to counts.
//
//   hand_held_log --rows=1000000 --seed=1 --acc_out=acc.txt --gyro_out=gyro.txt
//
// Prints one line: the rows, the holds started, the files. Exit status 2 on bad flags or a
// failed write (nothing is left half-written: each file is written whole, then renamed).

#include <gflags/gflags.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "io/atomic_file.h"
#include "simulation/random.h"
#include "simulation/triad_log_simulator.h"
#include "studies/gyroscope_monte_carlo.h"
#include "studies/triad_monte_carlo.h"

DEFINE_int64(rows, 100000, "Samples in each file (>= 10000).");
DEFINE_uint64(seed, 1, "Seed of the directions, the hold lengths and the noise.");
DEFINE_string(acc_out, "", "The accelerometer's file (t [s], x, y, z [counts]). Required.");
DEFINE_string(gyro_out, "", "The gyroscope's file (the same time stamps; counts). Required.");
DEFINE_double(rate_hz, 100.0, "Sampling rate, Hz.");
DEFINE_double(rest_s, 50.0, "The initial rest, s (imu_tk's example assumes 50).");
DEFINE_double(hold_min_s, 3.0, "Shortest hold after the rest, s.");
DEFINE_double(hold_max_s, 20.0, "Longest hold, s.");
DEFINE_double(turn_s, 1.5, "Each turn's duration, s.");
DEFINE_double(min_turn_deg, 30.0, "Least angle between consecutive holds' directions, degrees.");

namespace accelcal {
namespace {

// "t x y z\n" with t to 1 us and the counts as integers (they are rounded).
void AppendLine(double t, const std::array<double, 3>& u, std::string* text) {
  char buffer[128];
  char* end = buffer;
  end = std::to_chars(end, buffer + sizeof(buffer), t, std::chars_format::fixed, 6).ptr;
  for (double value : u) {
    *end++ = ' ';
    end =
        std::to_chars(end, buffer + sizeof(buffer), static_cast<long long>(std::lround(value))).ptr;
  }
  *end++ = '\n';
  text->append(buffer, end);
}

int Run() {
  if (FLAGS_rows < 10000 || FLAGS_acc_out.empty() || FLAGS_gyro_out.empty() ||
      !(FLAGS_rate_hz > 0.0) || !(FLAGS_rest_s > 0.0) || !(FLAGS_hold_min_s > 0.0) ||
      !(FLAGS_hold_max_s >= FLAGS_hold_min_s) || !(FLAGS_turn_s > 0.0) ||
      !(FLAGS_min_turn_deg >= 0.0 && FLAGS_min_turn_deg < 90.0)) {
    std::cerr << "hand_held_log: --rows >= 10000, --acc_out and --gyro_out are required; rates, "
                 "durations > 0, --hold_max_s >= --hold_min_s, --min_turn_deg in [0, 90)\n";
    return 2;
  }
  RandomSource random(FLAGS_seed, 0x68616e64);
  const double samples_per_s = FLAGS_rate_hz;
  std::vector<TriadHold> holds;
  double samples = 0.0;
  std::array<double, 3> direction = {0.0, 0.0, 1.0};
  // 1% to spare: the simulator rounds each hold and turn to whole samples.
  while (samples < 1.01 * static_cast<double>(FLAGS_rows) + samples_per_s * FLAGS_hold_max_s) {
    const double hold_s =
        holds.empty() ? FLAGS_rest_s
                      : FLAGS_hold_min_s + (FLAGS_hold_max_s - FLAGS_hold_min_s) * random.Uniform();
    if (!holds.empty()) {
      // A direction uniform on the sphere, at least min_turn_deg from the last.
      std::array<double, 3> next;
      do {
        double norm = 0.0;
        for (double& x : next) {
          x = random.StandardNormal();
          norm += x * x;
        }
        for (double& x : next) x /= std::sqrt(norm);
      } while (next[0] * direction[0] + next[1] * direction[1] + next[2] * direction[2] >
               std::cos(FLAGS_min_turn_deg * M_PI / 180.0));
      direction = next;
    }
    TriadHold hold;
    hold.direction = direction;
    hold.duration_s = hold_s;
    hold.turn_yaw_deg = 90.0 * (2.0 * random.Uniform() - 1.0);
    holds.push_back(hold);
    samples += samples_per_s * (hold_s + FLAGS_turn_s);
  }
  TriadLogSimulationOptions simulation;
  simulation.truth = XsensLikeTriad();
  simulation.gravity_mps2 = 9.81744;
  simulation.rate_hz = FLAGS_rate_hz;
  simulation.turn_s = FLAGS_turn_s;
  simulation.noise_stddev = {3.2, 3.2, 3.2};
  simulation.gyroscope.enabled = true;
  simulation.gyroscope.truth = XsensLikeGyroscope();
  simulation.gyroscope.offset = XsensLikeGyroscopeOffset();
  simulation.gyroscope.noise_stddev = {27.0, 27.0, 27.0};
  RandomSource noise(FLAGS_seed, 1);
  const TriadSession session = SimulateTriadSession(simulation, holds, &noise);
  const size_t rows = std::min(static_cast<size_t>(FLAGS_rows), session.log.size());
  for (int which = 0; which < 2; ++which) {
    std::string text;
    text.reserve(rows * 32);
    for (size_t i = 0; i < rows; ++i) {
      AppendLine(session.log.timestamp_s[i],
                 which == 0 ? session.log.output[i] : session.log.gyroscope[i], &text);
    }
    const std::string& path = which == 0 ? FLAGS_acc_out : FLAGS_gyro_out;
    const Status written = WriteFileAtomically(path, text);
    if (!written.ok()) {
      std::cerr << "hand_held_log: " << written.message() << "\n";
      return 2;
    }
  }
  size_t started = 0;
  for (const TriadHoldSamples& hold : session.holds)
    if (static_cast<size_t>(hold.start) < rows) ++started;
  std::printf("hand_held_log: %zu rows, %zu holds started, seed %llu: %s %s\n", rows, started,
              static_cast<unsigned long long>(FLAGS_seed), FLAGS_acc_out.c_str(),
              FLAGS_gyro_out.c_str());
  return 0;
}

}  // namespace
}  // namespace accelcal

int main(int argc, char** argv) {
  gflags::SetUsageMessage(
      "Writes a simulated hand-held session (Xsens-like accelerometer and gyroscope, counts) as "
      "imu_tk's two ASCII files.\n  hand_held_log --rows=1000000 --seed=1 --acc_out=acc.txt "
      "--gyro_out=gyro.txt");
  gflags::ParseCommandLineFlags(&argc, &argv, true);
  return accelcal::Run();
}
