#include "io/sample_spool.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <string>

#include "io/cleanup.h"

namespace accelcal {
namespace {

constexpr size_t kValuesPerSample = 4;  // t, x, y, z
constexpr size_t kBufferValues = (size_t{1} << 20) / sizeof(double);

Status SpoolError(const std::string& what) {
  return Status::Error("the temporary file of the log's samples: " + what + " (" +
                       std::strerror(errno) + "); set TMPDIR to a folder with room");
}

}  // namespace

SampleSpool::~SampleSpool() {
  if (fd_ >= 0) close(fd_);
}

Status SampleSpool::Open() {
  const char* tmpdir = std::getenv("TMPDIR");
  std::string name =
      std::string(tmpdir != nullptr && *tmpdir ? tmpdir : "/tmp") + "/accelcal_samples.XXXXXX";
  bool created = false;
  // Created and unlinked with the cleanup held: an interruption leaves no file either way.
  WithCleanupHeld([&] {
    fd_ = mkstemp(name.data());
    if (fd_ >= 0) {
      created = true;
      unlink(name.c_str());
    }
  });
  if (!created) return SpoolError("cannot create " + name);
  buffer_.reserve(kBufferValues);
  return Status::Ok();
}

Status SampleSpool::Flush() {
  const char* data = reinterpret_cast<const char*>(buffer_.data());
  size_t left = buffer_.size() * sizeof(double);
  while (left > 0) {
    const ssize_t written = write(fd_, data, left);
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) return SpoolError("cannot write");
    data += written;
    left -= static_cast<size_t>(written);
  }
  buffer_.clear();
  return Status::Ok();
}

Status SampleSpool::Append(double t_s, const std::array<double, 3>& output) {
  buffer_.insert(buffer_.end(), {t_s, output[0], output[1], output[2]});
  ++size_;
  return buffer_.size() + kValuesPerSample > kBufferValues ? Flush() : Status::Ok();
}

Status SampleSpool::Finish() {
  ACCELCAL_RETURN_IF_ERROR(Flush());
  buffer_.shrink_to_fit();
  return Status::Ok();
}

Status SampleSpool::Read(size_t first, size_t count, TriadLog* batch) const {
  read_buffer_.resize(count * kValuesPerSample);
  char* data = reinterpret_cast<char*>(read_buffer_.data());
  size_t left = read_buffer_.size() * sizeof(double);
  off_t offset = static_cast<off_t>(first * kValuesPerSample * sizeof(double));
  while (left > 0) {
    const ssize_t got = pread(fd_, data, left, offset);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) return SpoolError("cannot read back");
    data += got;
    left -= static_cast<size_t>(got);
    offset += got;
  }
  batch->timestamp_s.resize(count);
  batch->output.resize(count);
  for (size_t j = 0; j < count; ++j) {
    const double* row = &read_buffer_[j * kValuesPerSample];
    batch->timestamp_s[j] = row[0];
    batch->output[j] = {row[1], row[2], row[3]};
  }
  return Status::Ok();
}

}  // namespace accelcal
