#ifndef ACCELCAL_COMMON_STATUS_H_
#define ACCELCAL_COMMON_STATUS_H_

#include <string>
#include <utility>

namespace accelcal {

// The outcome of an operation that can fail because of its input (a file, a flag,
// a degenerate design). Programmer errors are CHECKs instead; input errors come back
// as a Status whose message is one line a user can act on: where (file and line,
// or variable), what is wrong, and what to do. Problem binaries print it on stderr
// and exit with status 2. [[nodiscard]]: a Status dropped on the floor is an error the
// user never hears of (the build makes it a compile error, -Werror=unused-result).
class [[nodiscard]] Status {
 public:
  Status() = default;  // OK.
  static Status Ok() { return Status(); }
  static Status Error(std::string message) { return Status(std::move(message)); }

  bool ok() const { return !failed_; }
  const std::string& message() const { return message_; }

  // Returns a copy whose message starts with `context: ` (e.g. the file name),
  // so low-level readers need not know which file they are reading.
  Status WithContext(const std::string& context) const;

 private:
  explicit Status(std::string message) : failed_(true), message_(std::move(message)) {}
  bool failed_ = false;
  std::string message_;
};

}  // namespace accelcal

// Returns early from the enclosing function when `expr` yields a failed Status.
#define ACCELCAL_RETURN_IF_ERROR(expr)                   \
  do {                                                   \
    ::accelcal::Status accelcal_status_ = (expr);        \
    if (!accelcal_status_.ok()) return accelcal_status_; \
  } while (false)

#endif  // ACCELCAL_COMMON_STATUS_H_
