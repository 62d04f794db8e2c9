#include "reporting/progress_printer.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "common/format.h"

namespace accelcal {

std::string FormatDuration(double seconds) {
  // Tenths under 10 s: a step of analyze may take a fraction of a second.
  if (seconds < 9.95) return StringPrintf("%.1f s", std::max(0.0, seconds));
  const long long whole = std::llround(seconds);
  if (whole < 60) return StringPrintf("%lld s", whole);
  if (whole < 3600) {
    return whole % 60 == 0 ? StringPrintf("%lld min", whole / 60)
                           : StringPrintf("%lld min %lld s", whole / 60, whole % 60);
  }
  const long long minutes = (whole % 3600) / 60;
  return minutes == 0 ? StringPrintf("%lld h", whole / 3600)
                      : StringPrintf("%lld h %lld min", whole / 3600, minutes);
}

std::string ProgressLine(const std::string& label, const std::string& unit, int64_t done,
                         int64_t total, double elapsed_s) {
  // Rounded down, so that 100% means finished.
  const int percent = total > 0 ? static_cast<int>(100 * std::min(done, total) / total) : 100;
  const std::string count =
      StringPrintf("%s: %lld/%lld %s (%d%%), ", label.c_str(), static_cast<long long>(done),
                   static_cast<long long>(total), unit.c_str(), percent);
  if (done >= total) return count + "done in " + FormatDuration(elapsed_s);
  const std::string elapsed = FormatDuration(elapsed_s) + " elapsed";
  if (done <= 0) return count + elapsed + ", time left not known yet";
  const double left_s = elapsed_s * static_cast<double>(total - done) / static_cast<double>(done);
  return count + elapsed + ", about " + FormatDuration(left_s) + " left";
}

Status ProgressStyleFor(const std::string& mode, bool stderr_is_terminal, ProgressStyle* style) {
  if (mode != "auto" && mode != "always" && mode != "never") {
    return Status::Error("--progress must be auto, always or never, got '" + mode.substr(0, 40) +
                         "'");
  }
  style->show = mode == "always" || (mode == "auto" && stderr_is_terminal);
  style->terminal = stderr_is_terminal;
  // A line rewritten in place costs nothing to read; a log file should not fill up.
  style->interval_s = stderr_is_terminal ? 2.0 : 5.0;
  return Status::Ok();
}

double ProgressPrinter::SteadySeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

ProgressPrinter::ProgressPrinter(std::string label, std::string unit, ProgressStyle style,
                                 std::ostream* out, Clock clock)
    : label_(std::move(label)),
      unit_(std::move(unit)),
      style_(style),
      out_(out),
      clock_(std::move(clock)),
      start_s_(clock_()),
      next_line_s_(start_s_ + style_.first_line_s) {}

void ProgressPrinter::Close() {
  if (open_line_length_ > 0) *out_ << '\n' << std::flush;
  open_line_length_ = 0;
}

void ProgressPrinter::Update(int64_t done, int64_t total) {
  if (!style_.show || finished_) return;
  const double now_s = clock_();
  if (done >= total) {
    finished_ = true;
  } else if (now_s < next_line_s_) {
    return;
  }
  next_line_s_ = now_s + style_.interval_s;
  Write(ProgressLine(label_, unit_, done, total, now_s - start_s_), finished_);
}

ProgressFn ProgressPrinter::Callback() {
  if (!style_.show) return ProgressFn();
  return [this](int64_t done, int64_t total) { Update(done, total); };
}

void ProgressPrinter::StartStep(int step, int steps, const std::string& name) {
  if (!style_.show) return;
  step_name_ = StringPrintf("%s: step %d/%d %s", label_.c_str(), step, steps, name.c_str());
  step_start_s_ = clock_();
  Write(step_name_ + " ...", false);
}

void ProgressPrinter::EndStep() {
  if (!style_.show) return;
  Write(step_name_ + ", done in " + FormatDuration(clock_() - step_start_s_), true);
}

void ProgressPrinter::Write(const std::string& line, bool final_line) {
  if (!style_.terminal) {
    *out_ << line << '\n' << std::flush;
    return;
  }
  // Blanks over what a longer earlier line leaves on the screen.
  const size_t blanks = open_line_length_ > line.size() ? open_line_length_ - line.size() : 0;
  *out_ << '\r' << line << std::string(blanks, ' ');
  if (final_line) *out_ << '\n';
  open_line_length_ = final_line ? 0 : line.size();
  *out_ << std::flush;
}

}  // namespace accelcal
