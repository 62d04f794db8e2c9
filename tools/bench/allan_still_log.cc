// allan_still_log: writes a simulated still log of an Xsens-like accelerometer (one rest, no
// turns) of any length, for tools/bench/allan_bench.sh: imu_tk's ASCII layout, "t x y z" per
// line, outputs in counts about 32768 with gravity along z. Each axis is white noise (--white
// counts a sample, Xsens's 3.2 by default) plus a random walk (--walk counts a step), rounded
// to counts. Written in 1 MiB blocks as it is simulated, so that memory does not grow with
// --rows (10^8 rows are 2.6 GB of text), to a temporary name renamed at the end.
//
//   allan_still_log --rows=2160000 --rate_hz=200 --out=$TMPDIR/still.txt
//
// Prints one line: the rows, the rate, the file. Exit status 2 on bad flags or a failed write.

#include <gflags/gflags.h>

#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>

#include "simulation/random.h"

DEFINE_int64(rows, 2160000, "Samples (>= 1000).");
DEFINE_double(rate_hz, 200.0, "Sampling rate, Hz.");
DEFINE_uint64(seed, 1, "Seed of the noise.");
DEFINE_double(white, 3.2, "White noise, counts (standard deviation of a sample).");
DEFINE_double(
    walk, 0.0005,
    "Random walk, counts (standard deviation of a step): small enough that a day at 1 kHz "
    "stays one static interval for the noise-floor detector (its variance about its mean, "
    "walk^2 rows / 6, 4 counts^2 at 10^8 rows, below the detector's threshold).");
DEFINE_string(out, "", "The log to write. Required.");

namespace accelcal {
namespace {

int Run() {
  if (FLAGS_rows < 1000 || !(FLAGS_rate_hz > 0.0) || !(FLAGS_white >= 0.0) ||
      !(FLAGS_walk >= 0.0) || FLAGS_out.empty()) {
    std::cerr << "allan_still_log: --rows >= 1000, --rate_hz > 0, --white and --walk >= 0 and "
                 "--out are required\n";
    return 2;
  }
  const std::string partial = FLAGS_out + ".partial";
  std::FILE* out = std::fopen(partial.c_str(), "wb");
  if (out == nullptr) {
    std::cerr << "allan_still_log: cannot write " << partial << "\n";
    return 2;
  }
  RandomSource random(FLAGS_seed, 0x7374696c6c);
  const std::array<double, 3> offset = {32768.0, 32768.0, 32768.0 + 4096.0};
  std::array<double, 3> walk = {0.0, 0.0, 0.0};
  std::string text;
  text.reserve((size_t{1} << 20) + 128);
  bool ok = true;
  for (long long i = 0; i < FLAGS_rows && ok; ++i) {
    char line[128];
    char* end = line;
    end = std::to_chars(end, line + sizeof(line), static_cast<double>(i) / FLAGS_rate_hz,
                        std::chars_format::fixed, 6)
              .ptr;
    for (int k = 0; k < 3; ++k) {
      walk[k] += FLAGS_walk * random.StandardNormal();
      const double value = offset[k] + walk[k] + FLAGS_white * random.StandardNormal();
      *end++ = ' ';
      end = std::to_chars(end, line + sizeof(line), std::llround(value)).ptr;
    }
    *end++ = '\n';
    text.append(line, end);
    if (text.size() >= (size_t{1} << 20)) {
      ok = std::fwrite(text.data(), 1, text.size(), out) == text.size();
      text.clear();
    }
  }
  ok = ok && std::fwrite(text.data(), 1, text.size(), out) == text.size();
  ok = std::fclose(out) == 0 && ok;
  if (!ok || std::rename(partial.c_str(), FLAGS_out.c_str()) != 0) {
    std::remove(partial.c_str());
    std::cerr << "allan_still_log: cannot write " << FLAGS_out << "\n";
    return 2;
  }
  std::printf("allan_still_log: %lld rows at %g Hz, seed %llu: %s\n",
              static_cast<long long>(FLAGS_rows), FLAGS_rate_hz,
              static_cast<unsigned long long>(FLAGS_seed), FLAGS_out.c_str());
  return 0;
}

}  // namespace
}  // namespace accelcal

int main(int argc, char** argv) {
  gflags::SetUsageMessage(
      "A simulated still accelerometer log (counts, imu_tk's layout) for allan_bench.sh.\n"
      "  allan_still_log --rows=N --rate_hz=HZ --out=FILE");
  gflags::ParseCommandLineFlags(&argc, &argv, true);
  return accelcal::Run();
}
