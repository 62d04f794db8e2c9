#ifndef ACCELCAL_REPORTING_PROGRESS_PRINTER_H_
#define ACCELCAL_REPORTING_PROGRESS_PRINTER_H_

// What a long run shows while it works, on stderr only (stdout and the output files are the
// same whether it is shown or not):
//
//   power: 120/480 trials (25%), 35 s elapsed, about 1 min 45 s left
//   power: 480/480 trials (100%), done in 2 min 20 s
//
// The time left assumes the remaining units take as long as the finished ones did on
// average: elapsed * (total - done) / done. On a terminal one line is rewritten in place
// ('\r'); into a file or a pipe each update is a line of its own, less often.

#include <cstdint>
#include <functional>
#include <ostream>
#include <string>

#include "common/progress.h"
#include "common/status.h"

namespace accelcal {

// "4.2 s", "35 s", "1 min 45 s", "2 h 5 min": tenths under 10 s, else whole seconds in the
// two largest units.
std::string FormatDuration(double seconds);

// One line without its end: "power: 120/480 trials (25%), 35 s elapsed, about 1 min 45 s
// left", or "power: 480/480 trials (100%), done in 2 min 20 s" when done == total.
std::string ProgressLine(const std::string& label, const std::string& unit, int64_t done,
                         int64_t total, double elapsed_s);

struct ProgressStyle {
  bool show = true;           // false: the printer prints nothing and asks for no counts
  bool terminal = false;      // rewrite one line with '\r' instead of writing full lines
  double first_line_s = 1.0;  // the first update once this long has passed: an early estimate
  double interval_s = 5.0;    // then at least this long between two (the last one aside)
};

// The style a binary's --progress asks for on stderr: "auto" shows it only on a terminal,
// "always" also into a file or a pipe, "never" not at all. A terminal is rewritten every
// 2 s; a file or a pipe gets a line every 5 s. Anything else is an error.
[[nodiscard]] Status ProgressStyleFor(const std::string& mode, bool stderr_is_terminal,
                                      ProgressStyle* style);

class ProgressPrinter {
 public:
  // Seconds on a monotonic clock; a test injects its own.
  using Clock = std::function<double()>;
  static double SteadySeconds();

  // `label` starts every line ("power"); `unit` names what is counted ("trials"). The
  // elapsed time counts from here.
  ProgressPrinter(std::string label, std::string unit, ProgressStyle style, std::ostream* out,
                  Clock clock = &ProgressPrinter::SteadySeconds);
  ProgressPrinter(const ProgressPrinter&) = delete;
  ProgressPrinter& operator=(const ProgressPrinter&) = delete;
  ~ProgressPrinter() { Close(); }

  // Ends a line a terminal was left on (a run that stopped early), so that what follows on
  // stderr, an error, starts on a line of its own.
  void Close();

  // `done` of `total`: a line once first_line_s has passed since the start and interval_s
  // since the last line, and always the last (done == total), once.
  void Update(int64_t done, int64_t total);

  // Update as a ProgressFn for a study (empty when nothing is shown, so the study does not
  // even count); the printer must outlive the study's run.
  ProgressFn Callback();

  // A stage of a run made of steps ("analyze: step 3/5 discovery ..."), and its end
  // ("done in 4.2 s"): on a terminal both on one line, else a line each.
  void StartStep(int step, int steps, const std::string& name);
  void EndStep();

 private:
  void Write(const std::string& line, bool final_line);

  const std::string label_;
  const std::string unit_;
  const ProgressStyle style_;
  std::ostream* const out_;
  const Clock clock_;
  const double start_s_;
  double next_line_s_;  // no update before then
  bool finished_ = false;
  size_t open_line_length_ = 0;  // a terminal line written without its end (0: none)
  std::string step_name_;        // "analyze: step 3/5 discovery"
  double step_start_s_ = 0.0;
};

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_PROGRESS_PRINTER_H_
