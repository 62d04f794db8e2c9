#include "io/line_stream.h"

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <vector>

#include "common/format.h"
#include "common/sha256.h"
#include "io/input_file.h"

namespace accelcal {
namespace {

constexpr size_t kChunkBytes = 1 << 20;

Status LineTooLong(long long line_number, size_t max_line_bytes, const std::string& what) {
  return Status::Error(StringPrintf("line %lld is longer than %zu bytes: not %s", line_number,
                                    max_line_bytes, what.c_str()));
}

Status Stream(const std::string& path, const std::string& what, size_t max_line_bytes,
              const std::function<Status(std::string_view line)>& on_line,
              const std::function<Status(std::string_view rest)>& on_unterminated) {
  uint64_t size = 0;
  ACCELCAL_RETURN_IF_ERROR(CheckInputFile(path, std::numeric_limits<uint64_t>::max(), what, &size));
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"),
                                                       &std::fclose);
  if (!file) return Status::Error(std::string("cannot open: ") + std::strerror(errno));
  FileIdentity before;
  ACCELCAL_RETURN_IF_ERROR(IdentifyOpenFile(fileno(file.get()), &before));
  // The checksum of the very bytes parsed, when the run records them (io/input_file.h).
  const bool recording = RecordingInputReads();
  Sha256 hash;
  uint64_t total = 0;
  long long line_number = 0;
  std::string carried;  // the start of a line whose end is in the next chunk
  std::vector<char> chunk(kChunkBytes);
  while (true) {
    const size_t count = std::fread(chunk.data(), 1, chunk.size(), file.get());
    if (count == 0) {
      if (std::ferror(file.get()))
        return Status::Error(std::string("cannot read: ") + std::strerror(errno));
      break;
    }
    if (recording) hash.Update(chunk.data(), count);
    total += count;
    const std::string_view data(chunk.data(), count);
    size_t begin = 0;
    while (true) {
      const size_t end = data.find('\n', begin);
      if (end == std::string_view::npos) {
        carried.append(data.substr(begin));
        if (carried.size() > max_line_bytes) {
          return LineTooLong(line_number + 1, max_line_bytes, what);
        }
        break;
      }
      std::string_view line = data.substr(begin, end - begin);
      if (!carried.empty()) {
        carried.append(line);
        line = carried;
      }
      ++line_number;
      if (line.size() > max_line_bytes) return LineTooLong(line_number, max_line_bytes, what);
      ACCELCAL_RETURN_IF_ERROR(on_line(line));
      carried.clear();
      begin = end + 1;
    }
  }
  // A logger still appending: the lines parsed are not the file's, whatever its end looks like.
  FileIdentity after;
  ACCELCAL_RETURN_IF_ERROR(IdentifyOpenFile(fileno(file.get()), &after));
  if (after != before || total != after.size) return FileChangedWhileRead(before, after);
  if (!carried.empty()) return on_unterminated(carried);
  if (recording) return RecordInputRead(path, InputRead{total, hash.HexDigest(), after});
  return Status::Ok();
}

}  // namespace

Status StreamTextLines(const std::string& path, const std::string& what, size_t max_line_bytes,
                       const std::function<Status(std::string_view line)>& on_line,
                       const std::function<Status(std::string_view rest)>& on_unterminated) {
  return Stream(path, what, max_line_bytes, on_line, on_unterminated).WithContext(path);
}

}  // namespace accelcal
