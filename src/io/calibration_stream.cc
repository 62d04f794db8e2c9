#include "io/calibration_stream.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <string_view>
#include <vector>

#include "io/csv_reader.h"
#include "io/input_file.h"
#include "io/theta_agreement.h"

namespace accelcal {
namespace {

// Closes the file on every return path.
class FileDescriptor {
 public:
  explicit FileDescriptor(int fd) : fd_(fd) {}
  ~FileDescriptor() {
    if (fd_ >= 0) close(fd_);
  }
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

// Parsed samples waiting for the sink, and what the whole stream has seen of theta.
class Batcher {
 public:
  Batcher(const CalibrationStreamOptions& options, const CalibrationSink& sink)
      : sink_(sink),
        degrees_(options.theta_unit == AngleUnit::kDegree),
        capacity_(std::max<size_t>(1, options.batch_samples)),
        agreement_(options.theta_unit) {
    batch_.theta_rad.reserve(capacity_);
    batch_.measured_x.reserve(capacity_);
    batch_.measured_y.reserve(capacity_);
  }

  void Add(double theta, double measured_x, double measured_y) {
    // The same expression as LoadCalibrationTest's conversion of a test read whole, so that
    // both give the same bits.
    if (degrees_) theta *= M_PI / 180.0;
    if (count_ == 0) theta_min_rad_ = theta_max_rad_ = theta;
    theta_min_rad_ = std::min(theta_min_rad_, theta);
    theta_max_rad_ = std::max(theta_max_rad_, theta);
    ++count_;
    batch_.theta_rad.push_back(theta);
    batch_.measured_x.push_back(measured_x);
    batch_.measured_y.push_back(measured_y);
    if (batch_.theta_rad.size() == capacity_) Flush();
  }

  void Flush() {
    if (batch_.theta_rad.empty()) return;
    agreement_.Add(batch_);
    sink_(batch_);
    // clear() keeps the capacity: no allocation after the first batch.
    batch_.theta_rad.clear();
    batch_.measured_x.clear();
    batch_.measured_y.clear();
  }

  // The batch, and the agreement's four blocks of 512 doubles.
  size_t reserved_bytes() const {
    return 3 * capacity_ * sizeof(double) + 4 * 512 * sizeof(double);
  }
  double theta_min_rad() const { return theta_min_rad_; }
  double theta_max_rad() const { return theta_max_rad_; }
  const ThetaAgreement& agreement() const { return agreement_; }

 private:
  const CalibrationSink& sink_;
  const bool degrees_;
  const size_t capacity_;
  CalibrationTest batch_;
  ThetaAgreement agreement_;
  long long count_ = 0;
  double theta_min_rad_ = 0.0;
  double theta_max_rad_ = 0.0;
};

Status LineTooLong(long long line_number, std::string_view start, size_t max_line_bytes) {
  const bool carriage_returns = start.find('\r') != std::string_view::npos;
  return Status::Error(
      "line " + std::to_string(line_number) + " is longer than " + std::to_string(max_line_bytes) +
      " bytes, while a row of theta,ax,ay is a few dozen" +
      (carriage_returns ? "; its lines end in '\\r' alone (old Mac line endings): convert them "
                          "to '\\n'"
                        : "; is this a calibration CSV file?"));
}

Status Stream(const std::string& path, const CalibrationStreamOptions& options,
              const CalibrationSink& sink, CalibrationStreamStats* stats) {
  // Any size: the file is never held whole.
  uint64_t size = 0;
  ACCELCAL_RETURN_IF_ERROR(
      CheckInputFile(path, std::numeric_limits<uint64_t>::max(), "a CSV file", &size));
  const FileDescriptor file(open(path.c_str(), O_RDONLY | O_CLOEXEC));
  if (file.get() < 0) {
    return Status::Error(std::string("cannot open the file (") + strerror(errno) +
                         "); check the path and permissions");
  }
  // A hint only: the kernel may read further ahead.
  posix_fadvise(file.get(), 0, 0, POSIX_FADV_SEQUENTIAL);

  const size_t chunk_bytes = std::max<size_t>(1, options.chunk_bytes);
  const size_t max_line_bytes = std::max<size_t>(1, options.max_line_bytes);
  // Room for one read after the start of a line carried over from the previous read.
  // Not value-initialised, so pages a short-lined file never reaches are never touched.
  const size_t buffer_bytes = chunk_bytes + max_line_bytes;
  const std::unique_ptr<char[]> buffer(new char[buffer_bytes]);
  CsvLineParser parser({{"theta"}, {"ax"}, {"ay"}});
  Batcher batcher(options, sink);
  stats->reserved_bytes = buffer_bytes + batcher.reserved_bytes();

  auto parse = [&](std::string_view line) {
    if (line.size() > max_line_bytes) {
      return LineTooLong(parser.line_number() + 1, line.substr(0, max_line_bytes), max_line_bytes);
    }
    CsvLineParser::LineKind kind;
    ACCELCAL_RETURN_IF_ERROR(parser.ParseLine(line, &kind));
    if (kind == CsvLineParser::LineKind::kRow) {
      batcher.Add(parser.number(0), parser.number(1), parser.number(2));
    }
    return Status::Ok();
  };

  size_t held = 0;  // bytes of an unfinished line at the start of the buffer
  while (true) {
    const ssize_t count = ReadSome(file.get(), buffer.get() + held, chunk_bytes);
    if (count < 0) return Status::Error(std::string("cannot read the file: ") + strerror(errno));
    stats->bytes += count;
    const char* line = buffer.get();
    const char* const end = buffer.get() + held + count;
    while (const char* newline =
               static_cast<const char*>(std::memchr(line, '\n', static_cast<size_t>(end - line)))) {
      ACCELCAL_RETURN_IF_ERROR(parse(std::string_view(line, static_cast<size_t>(newline - line))));
      line = newline + 1;
    }
    held = static_cast<size_t>(end - line);
    if (count == 0) {
      // The last line has no '\n': a copy cut short, most likely inside a number.
      if (held > 0) return parser.UnterminatedLastLine(std::string_view(line, held));
      break;
    }
    if (held > max_line_bytes) {
      return LineTooLong(parser.line_number() + 1, std::string_view(line, held), max_line_bytes);
    }
    std::memmove(buffer.get(), line, held);
  }
  batcher.Flush();
  stats->lines = parser.line_number();
  stats->samples = parser.row_count();
  stats->theta_min_rad = batcher.theta_min_rad();
  stats->theta_max_rad = batcher.theta_max_rad();
  stats->theta_agreement = batcher.agreement().agreement();
  stats->theta_agreement_as_degrees = batcher.agreement().agreement_as_degrees();
  ACCELCAL_RETURN_IF_ERROR(parser.Finish());
  ACCELCAL_RETURN_IF_ERROR(CheckThetaSpan(options.theta_unit, stats->theta_min_rad,
                                          stats->theta_max_rad, stats->samples));
  if (!options.check_theta_agreement) return Status::Ok();
  return batcher.agreement().Check(stats->theta_max_rad - stats->theta_min_rad);
}

}  // namespace

Status StreamCalibrationCsv(const std::string& path, const CalibrationStreamOptions& options,
                            const CalibrationSink& sink, CalibrationStreamStats* stats) {
  CalibrationStreamStats local_stats;
  if (stats == nullptr) stats = &local_stats;
  *stats = CalibrationStreamStats();
  return Stream(path, options, sink, stats).WithContext(path);
}

}  // namespace accelcal
