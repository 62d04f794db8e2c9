// The closed-form baseline at scale (issue 9, "Scale"), and the references its figures are
// stated against:
//
//   BM_BaselineInMemory/N/T  CalibrationAccumulator::AddTest over a test held in memory
//                            (24 bytes per sample: theta, m_x, m_y as doubles), T threads.
//   BM_MemoryBandwidth/N/T   a plain pass summing the same three arrays, the same bytes, on
//                            T threads: the most any one-pass method could do on T cores.
//                            The baseline's bytes/s over this one's is the fraction of the
//                            limit it reaches.
//   BM_ReadCsvFile/N       read(2) of a calibration.csv of N samples in 4 MiB chunks,
//                          touching every byte: the same reference for the CSV path.
//   BM_ParseCsv/N          the streaming reader (io/calibration_stream.h) on that file, the
//                          samples dropped: the CSV parser's MB/s.
//   BM_StreamCsv/N         the same into the accumulator, as linear_ls does: MB/s, samples/s,
//                          and the peak resident memory while streaming (peak_rss_MiB), which
//                          must not grow with N.
//
// The files are generated once (tp2-2018's Table 1 truth and noise, written at round-trip
// precision, about 56 bytes per line) into $ACCELCAL_BENCH_DIR, where they are kept for the
// next run, or else into a temporary folder removed at exit. They are read back from the page
// cache, so these are parsing figures, not disk figures; they are timed by the wall clock all
// the same, since a read that waits for the disk costs no CPU time. N goes up to 10^7, or up
// to $ACCELCAL_BENCH_MAX_SAMPLES: 10^8 needs 2.4 GB of memory for the in-memory test and
// 5.6 GB of disk for the CSV file.
//
//   build/bin/streaming_bench
//   ACCELCAL_BENCH_MAX_SAMPLES=100000000 build/bin/streaming_bench
//   tools/bench/streaming_bench.sh   (each CSV size in its own process, and linear_ls itself)

#include <benchmark/benchmark.h>
#include <fcntl.h>
#include <malloc.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "estimation/tilt_table/linear_ls.h"
#include "io/calibration_stream.h"
#include "simulation/simulator.h"

namespace accelcal {
namespace {

constexpr double kGravity = 9.8;
constexpr int64_t kBytesPerSample = 3 * sizeof(double);

// Samples [first, first + count) of an N-sample uniform sweep over [0, 2 pi], with the
// course's Table 1 as truth. Blocks are independent noise streams, so a test of any N is
// generated in bounded memory and the same N always gives the same samples.
CalibrationTest SimulateBlock(int64_t sample_count, int64_t first, int64_t count, uint64_t block) {
  const double step = 2.0 * M_PI / static_cast<double>(sample_count - 1);
  TiltSchedule schedule;
  schedule.sample_count = static_cast<int>(count);
  schedule.theta_begin_rad = step * static_cast<double>(first);
  schedule.theta_end_rad = step * static_cast<double>(first + count - 1);
  return SimulateTiltTest(schedule, CourseTableOneTruth(), /*seed=*/1, /*stream=*/block);
}

constexpr int64_t kBlockSamples = int64_t{1} << 16;

// The in-memory test of the last N asked for (one at a time: 10^8 samples are 2.4 GB).
std::unique_ptr<CalibrationTest>& CachedTest() {
  static std::unique_ptr<CalibrationTest> test;
  return test;
}

const CalibrationTest& InMemoryTest(int64_t sample_count) {
  std::unique_ptr<CalibrationTest>& test = CachedTest();
  if (test == nullptr || test->size() != sample_count) {
    test.reset();
    test = std::make_unique<CalibrationTest>();
    test->theta_rad.reserve(sample_count);
    test->measured_x.reserve(sample_count);
    test->measured_y.reserve(sample_count);
    for (int64_t first = 0; first < sample_count; first += kBlockSamples) {
      const int64_t count = std::min(kBlockSamples, sample_count - first);
      const CalibrationTest block =
          SimulateBlock(sample_count, first, count, static_cast<uint64_t>(first / kBlockSamples));
      test->Append(block);
    }
  }
  return *test;
}

void SetThroughput(benchmark::State& state, int64_t samples_per_iteration,
                   int64_t bytes_per_iteration) {
  state.SetItemsProcessed(state.iterations() * samples_per_iteration);
  state.SetBytesProcessed(state.iterations() * bytes_per_iteration);
}

void BM_BaselineInMemory(benchmark::State& state) {
  const int64_t sample_count = state.range(0);
  const int threads = static_cast<int>(state.range(1));
  const CalibrationTest& test = InMemoryTest(sample_count);
  for (auto _ : state) {
    CalibrationAccumulator statistics(kGravity);
    statistics.AddTest(test, threads);
    benchmark::DoNotOptimize(statistics);
  }
  SetThroughput(state, sample_count, sample_count * kBytesPerSample);
}

// Sums the three arrays with eight independent sums each, so that the latency of a floating
// add (4 cycles, one add in flight per sum) does not bound the pass below what the memory
// delivers; the compiler packs them two by two into SSE2 adds.
double SumArrays(const double* a, const double* b, const double* c, size_t n) {
  constexpr size_t kLanes = 8;
  double sums[3][kLanes] = {};
  size_t i = 0;
  for (; i + kLanes <= n; i += kLanes) {
    for (size_t lane = 0; lane < kLanes; ++lane) {
      sums[0][lane] += a[i + lane];
      sums[1][lane] += b[i + lane];
      sums[2][lane] += c[i + lane];
    }
  }
  double total = 0.0;
  for (; i < n; ++i) total += a[i] + b[i] + c[i];
  for (const auto& row : sums) {
    for (double sum : row) total += sum;
  }
  return total;
}

// SumArrays over `threads` contiguous parts at once, as AddTest splits the test (each part
// on its own thread, the first on the calling one).
double SumArraysThreaded(const CalibrationTest& test, int threads) {
  const size_t size = test.theta_rad.size();
  std::vector<double> totals(threads, 0.0);
  const auto sum_part = [&](int part) {
    const size_t begin = size * part / threads;
    const size_t end = size * (part + 1) / threads;
    totals[part] = SumArrays(test.theta_rad.data() + begin, test.measured_x.data() + begin,
                             test.measured_y.data() + begin, end - begin);
  };
  std::vector<std::thread> workers;
  for (int part = 1; part < threads; ++part) workers.emplace_back(sum_part, part);
  sum_part(0);
  for (std::thread& worker : workers) worker.join();
  double total = 0.0;
  for (double part_total : totals) total += part_total;
  return total;
}

void BM_MemoryBandwidth(benchmark::State& state) {
  const int64_t sample_count = state.range(0);
  const int threads = static_cast<int>(state.range(1));
  const CalibrationTest& test = InMemoryTest(sample_count);
  for (auto _ : state) {
    benchmark::DoNotOptimize(SumArraysThreaded(test, threads));
  }
  SetThroughput(state, sample_count, sample_count * kBytesPerSample);
}

// ---- CSV files -----------------------------------------------------------------------------

// Where the CSV files go: $ACCELCAL_BENCH_DIR (kept), or a temporary folder removed at exit.
class BenchDir {
 public:
  BenchDir() {
    const char* given = std::getenv("ACCELCAL_BENCH_DIR");
    if (given != nullptr && *given != '\0') {
      path_ = given;
      return;
    }
    const char* base = std::getenv("TMPDIR");
    std::string pattern = std::string(base != nullptr ? base : "/tmp") + "/streaming_bench_XXXXXX";
    if (mkdtemp(pattern.data()) != nullptr) {
      path_ = pattern;
      owned_ = true;
    }
  }
  ~BenchDir() {
    if (!owned_) return;
    for (const std::string& file : files_) std::remove(file.c_str());
    rmdir(path_.c_str());
  }
  // "" when there is no folder to write in.
  std::string File(const std::string& name) {
    if (path_.empty()) return "";
    return *files_.insert(path_ + "/" + name).first;
  }

 private:
  std::string path_;
  bool owned_ = false;
  std::set<std::string> files_;
};

BenchDir& Dir() {
  static BenchDir dir;
  return dir;
}

void AppendNumber(double value, char separator, std::string* text) {
  char digits[32];
  // Shortest round-trip form: reading it back gives the same double.
  const auto [end, error] = std::to_chars(digits, digits + sizeof(digits), value);
  text->append(digits, end);
  text->push_back(separator);
}

// Writes calibration_<N>.csv unless it is already there (written to a temporary name and
// renamed, so a run interrupted mid-write leaves no truncated file to be reused). Memory
// stays at one block, so generating does not raise the peak that BM_StreamCsv reports.
std::string CsvFile(int64_t sample_count) {
  const std::string path = Dir().File("calibration_" + std::to_string(sample_count) + ".csv");
  if (path.empty() || access(path.c_str(), R_OK) == 0) return path;
  const std::string partial = path + ".partial";
  std::FILE* file = std::fopen(partial.c_str(), "wb");
  if (file == nullptr) return "";
  std::string text = "theta,ax,ay\n";
  for (int64_t first = 0; first < sample_count; first += kBlockSamples) {
    const int64_t count = std::min(kBlockSamples, sample_count - first);
    const CalibrationTest block =
        SimulateBlock(sample_count, first, count, static_cast<uint64_t>(first / kBlockSamples));
    for (int i = 0; i < block.size(); ++i) {
      AppendNumber(block.theta_rad[i], ',', &text);
      AppendNumber(block.measured_x[i], ',', &text);
      AppendNumber(block.measured_y[i], '\n', &text);
    }
    if (std::fwrite(text.data(), 1, text.size(), file) != text.size()) break;
    text.clear();
  }
  const bool written = text.empty() && std::fclose(file) == 0;
  if (!written || std::rename(partial.c_str(), path.c_str()) != 0) {
    std::remove(partial.c_str());
    return "";
  }
  return path;
}

int64_t FileBytes(const std::string& path) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) return 0;
  std::fseek(file, 0, SEEK_END);
  const int64_t bytes = std::ftell(file);
  std::fclose(file);
  return bytes;
}

// The process' peak resident memory in MiB (ru_maxrss is in KiB on Linux).
double PeakRssMiB() {
  rusage usage;
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

// Resets the peak to the current resident memory (Linux >= 4.0), so that the peak reported
// is the stream's, not that of what ran before it in this process.
bool ResetPeakRss() {
  const int fd = open("/proc/self/clear_refs", O_WRONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const bool reset = write(fd, "5", 1) == 1;
  close(fd);
  return reset;
}

// The CSV file of state.range(0) samples, after freeing the in-memory test; "" after
// SkipWithError.
std::string PrepareCsv(benchmark::State& state) {
  CachedTest().reset();
  const std::string path = CsvFile(state.range(0));
  if (path.empty()) state.SkipWithError("cannot write the CSV file (disk space?)");
#ifdef __GLIBC__
  // Give back what generating the file left in the heap, so that it does not count in the
  // resident memory the stream's peak starts from.
  malloc_trim(0);
#endif
  return path;
}

void BM_ReadCsvFile(benchmark::State& state) {
  const std::string path = PrepareCsv(state);
  if (path.empty()) return;
  const int64_t bytes = FileBytes(path);
  constexpr size_t kChunkBytes = size_t{4} << 20;
  std::vector<uint64_t> buffer(kChunkBytes / sizeof(uint64_t));
  for (auto _ : state) {
    const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
    uint64_t sum = 0;
    ssize_t count;
    while ((count = read(fd, buffer.data(), kChunkBytes)) > 0) {
      const size_t words = static_cast<size_t>(count) / sizeof(uint64_t);
      for (size_t i = 0; i < words; ++i) sum += buffer[i];
    }
    close(fd);
    benchmark::DoNotOptimize(sum);
  }
  SetThroughput(state, state.range(0), bytes);
}

void StreamCsv(benchmark::State& state, bool accumulate) {
  const std::string path = PrepareCsv(state);
  if (path.empty()) return;
  const int64_t bytes = FileBytes(path);
  const double rss_before_mib = PeakRssMiB();
  const bool peak_reset = ResetPeakRss();
  CalibrationStreamStats stats;
  for (auto _ : state) {
    CalibrationAccumulator statistics(kGravity);
    int64_t samples = 0;
    const Status status = StreamCalibrationCsv(
        path, CalibrationStreamOptions(),
        [&](const CalibrationTest& batch) {
          if (accumulate) statistics.AddTest(batch);
          samples += batch.size();
        },
        &stats);
    if (!status.ok() || samples != state.range(0)) {
      state.SkipWithError(status.ok() ? "wrong sample count" : status.message().c_str());
      break;
    }
    benchmark::DoNotOptimize(statistics);
  }
  SetThroughput(state, state.range(0), bytes);
  state.counters["file_MB"] = static_cast<double>(bytes) / 1e6;
  state.counters["reader_MiB"] = static_cast<double>(stats.reserved_bytes) / (1 << 20);
  state.counters["peak_rss_MiB"] = PeakRssMiB();
  // Without the reset, peak_rss_MiB is the whole process' peak, which may be an earlier
  // benchmark's; rss_before_MiB says what it was when this one started.
  if (!peak_reset) state.counters["rss_before_MiB"] = rss_before_mib;
}

void BM_ParseCsv(benchmark::State& state) { StreamCsv(state, /*accumulate=*/false); }
void BM_StreamCsv(benchmark::State& state) { StreamCsv(state, /*accumulate=*/true); }

// Registered per size, baseline and reference side by side, so that each size's test is
// generated once.
void RegisterBenchmarks(int64_t max_samples) {
  for (const int64_t n : {20000LL, 100000LL, 1000000LL, 10000000LL, 100000000LL}) {
    if (n > max_samples) break;
    // Two threads only where AddTest splits the test (at least kParallelMinSamples each).
    const int max_threads = n >= 2 * CalibrationAccumulator::kParallelMinSamples ? 2 : 1;
    for (int threads = 1; threads <= max_threads; ++threads) {
      benchmark::RegisterBenchmark("BM_BaselineInMemory", BM_BaselineInMemory)
          ->Args({n, threads})
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
      benchmark::RegisterBenchmark("BM_MemoryBandwidth", BM_MemoryBandwidth)
          ->Args({n, threads})
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
  }
  for (const int64_t n : {1000000LL, 10000000LL, 100000000LL}) {
    if (n > max_samples) break;
    for (const auto& [name, function] : {std::make_pair("BM_ReadCsvFile", BM_ReadCsvFile),
                                         std::make_pair("BM_ParseCsv", BM_ParseCsv),
                                         std::make_pair("BM_StreamCsv", BM_StreamCsv)}) {
      benchmark::RegisterBenchmark(name, function)
          ->Arg(n)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
  }
}

int64_t MaxSamples() {
  const char* given = std::getenv("ACCELCAL_BENCH_MAX_SAMPLES");
  return given != nullptr && *given != '\0' ? std::atoll(given) : 10000000;
}

}  // namespace
}  // namespace accelcal

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  accelcal::RegisterBenchmarks(accelcal::MaxSamples());
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
