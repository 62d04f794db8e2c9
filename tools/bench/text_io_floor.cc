// text_io_floor: what any `apply` of a triad's text log must spend at least, reading and writing
// text, for tools/bench/stream_scale_bench.sh (issue 36: "apply within 3x of the time to read and
// write the file"). It streams the log with the reader apply uses (io/imu_log.h, StreamImuLog,
// the same batches) and writes, per sample, a row of the same shape and formatting as apply's
// triad output (common/format.h: t and three values at full precision, three sigmas and three
// correlations to 9 digits) to --out, in 1 MiB blocks. The numbers are the outputs scaled (so
// that they have the digits corrected values have), not a correction: no calibration, no
// covariance, no range checks, no median, no checksum, no temporary file. A floor, not a result.
//
//   text_io_floor --log=LOG --out=OUT
//   text_io_floor --log=LOG --parse_only      (the reading alone: allan's floor)
//
// Prints the samples and bytes written. Exit status 2 on a bad log or a failed write.

#include <gflags/gflags.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "common/format.h"
#include "common/triad_log.h"
#include "io/imu_log.h"

DEFINE_string(log, "", "The triad's text log (as apply --in). Required.");
DEFINE_string(out, "", "Where to write the rows (overwritten; a benchmark's scratch file).");
DEFINE_bool(
    parse_only, false,
    "Only read the log (no --out): the floor of any binary that reads the text log, as "
    "allan does (tools/bench/allan_bench.sh). Prints the samples and a sum of the outputs.");

namespace accelcal {
namespace {

// --parse_only: the log read by the same reader, each output added up (so that nothing is left
// unparsed), nothing written.
int ParseOnly() {
  size_t samples = 0;
  double sum = 0.0;
  const Status read =
      StreamImuLog(FLAGS_log, ImuLogReadOptions(), 65536, [&](const TriadLog& batch) {
        for (size_t j = 0; j < batch.size(); ++j)
          sum +=
              batch.timestamp_s[j] + batch.output[j][0] + batch.output[j][1] + batch.output[j][2];
        samples += batch.size();
      });
  if (!read.ok()) {
    std::cerr << "text_io_floor: " << read.message() << "\n";
    return 2;
  }
  std::printf("text_io_floor: %zu samples read (sum %.17g)\n", samples, sum);
  return 0;
}

int Run() {
  if (FLAGS_parse_only && !FLAGS_log.empty()) return ParseOnly();
  if (FLAGS_log.empty() || FLAGS_out.empty()) {
    std::cerr << "text_io_floor: --log and --out are required\n";
    return 2;
  }
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> out(std::fopen(FLAGS_out.c_str(), "wb"),
                                                      &std::fclose);
  if (!out) {
    std::cerr << "text_io_floor: cannot write " << FLAGS_out << "\n";
    return 2;
  }
  constexpr size_t kBlock = 1 << 20;
  std::string text;
  text.reserve(2 * kBlock);
  size_t samples = 0, bytes = 0;
  bool written = true;
  auto flush = [&]() {
    if (std::fwrite(text.data(), 1, text.size(), out.get()) != text.size()) written = false;
    bytes += text.size();
    text.clear();
  };
  const Status read =
      StreamImuLog(FLAGS_log, ImuLogReadOptions(), 65536, [&](const TriadLog& batch) {
        for (size_t j = 0; j < batch.size(); ++j) {
          const std::array<double, 3>& u = batch.output[j];
          AppendRoundTripDouble(batch.timestamp_s[j], &text);
          for (int k = 0; k < 3; ++k) {
            text.push_back(',');
            AppendRoundTripDouble(2.4130085690791713e-3 * (u[k] - 32768.0), &text);
          }
          for (int k = 0; k < 3; ++k) {
            text.push_back(',');
            AppendGeneral(1.2e-7 * std::abs(u[k] - 32000.0) + 4e-4, 9, &text);
          }
          for (int k = 0; k < 3; ++k) {
            text.push_back(',');
            AppendGeneral((u[k] - u[(k + 1) % 3]) / 65536.0, 9, &text);
          }
          text.push_back('\n');
          if (text.size() >= kBlock) flush();
        }
        samples += batch.size();
      });
  if (!read.ok()) {
    std::cerr << "text_io_floor: " << read.message() << "\n";
    return 2;
  }
  flush();
  if (!written || std::fflush(out.get()) != 0) {
    std::cerr << "text_io_floor: writing " << FLAGS_out << " failed\n";
    return 2;
  }
  std::printf("text_io_floor: %zu samples read, %zu bytes written to %s\n", samples, bytes,
              FLAGS_out.c_str());
  return 0;
}

}  // namespace
}  // namespace accelcal

int main(int argc, char** argv) {
  gflags::SetUsageMessage(
      "Reads a triad's text log as apply does and writes rows of apply's shape and format: the "
      "floor of reading and writing the file.\n  text_io_floor --log=LOG --out=OUT\n"
      "  text_io_floor --log=LOG --parse_only");
  gflags::ParseCommandLineFlags(&argc, &argv, true);
  return accelcal::Run();
}
