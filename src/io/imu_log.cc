#include "io/imu_log.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <vector>

#include "common/format.h"
#include "common/statistics.h"
#include "io/course_data.h"
#include "io/input_file.h"
#include "io/input_text.h"
#include "io/line_stream.h"

namespace accelcal {
namespace {

constexpr char kCsvHeaderHint[] = "t_s,acc_x,acc_y,acc_z";
constexpr char kWhitespaceColumns[] = "t [s], x, y, z";
constexpr size_t kMaxLineBytes = 1 << 16;

std::string Where(long long line_number) { return "line " + std::to_string(line_number); }

std::string_view TrimBlanks(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t' || text.back() == '\r'))
    text.remove_suffix(1);
  return text;
}

// The decimal numbers of a typical log ("3.3108000e+04": at most 19 digits and a small
// exponent) by Clinger's fast path: when the digits form an integer m <= 2^53 and the
// exponent e is within +-22, m and 10^|e| are exact doubles, so m * 10^e (or m / 10^-e) is
// one correctly rounded operation, the very double std::from_chars gives, at a fraction of
// its cost. Reads from `*p` up to the first character that cannot continue the number and
// leaves `*p` there; false for anything else (other forms, more digits, no digits), which
// the caller then leaves to ParseFiniteNumber, the arbiter of what a number is.
bool ReadShortDecimal(const char** p, const char* end, double* value) {
  static constexpr double kPowersOfTen[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                            1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                            1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
  constexpr long kMaxDigits = 19;  // digits, leading zeros included: below 10^19 < 2^64
  constexpr uint64_t kMaxExactInteger = uint64_t{1} << 53;
  auto is_digit = [](char c) { return static_cast<unsigned char>(c - '0') < 10; };
  const char* q = *p;
  bool negative = false;
  if (q < end && (*q == '-' || *q == '+')) negative = *q++ == '-';
  uint64_t mantissa = 0;  // wraps past kMaxDigits digits, which are then refused
  const char* const integer = q;
  for (; q < end && is_digit(*q); ++q) mantissa = mantissa * 10 + (*q - '0');
  long digits = q - integer;
  int exponent = 0;
  if (q < end && *q == '.') {
    const char* const fraction = ++q;
    for (; q < end && is_digit(*q); ++q) mantissa = mantissa * 10 + (*q - '0');
    exponent = -static_cast<int>(q - fraction);
    digits += q - fraction;
  }
  if (digits == 0 || digits > kMaxDigits || mantissa > kMaxExactInteger) return false;
  if (q < end && (*q == 'e' || *q == 'E')) {
    ++q;
    bool negative_exponent = false;
    if (q < end && (*q == '-' || *q == '+')) negative_exponent = *q++ == '-';
    const char* const written = q;
    int magnitude = 0;
    for (; q < end && is_digit(*q) && q - written < 4; ++q) magnitude = magnitude * 10 + (*q - '0');
    if (q == written || (q < end && is_digit(*q))) return false;
    exponent += negative_exponent ? -magnitude : magnitude;
  }
  if (exponent < -22 || exponent > 22) return false;
  const double m = static_cast<double>(mantissa);
  const double magnitude = exponent < 0 ? m / kPowersOfTen[-exponent] : m * kPowersOfTen[exponent];
  *value = negative ? -magnitude : magnitude;
  *p = q;
  return true;
}

// A whole cell by ReadShortDecimal.
bool ParseShortDecimal(std::string_view text, double* value) {
  const char* p = text.data();
  const char* const end = p + text.size();
  return ReadShortDecimal(&p, end, value) && p == end;
}

bool IsBlank(char c) { return c == ' ' || c == '\t'; }

// A row of four short decimals separated by blanks, in one pass; false for anything else,
// which the caller parses field by field (and explains).
bool ReadFourShortDecimals(std::string_view trimmed, double values[4]) {
  const char* p = trimmed.data();
  const char* const end = p + trimmed.size();
  for (int c = 0; c < 4; ++c) {
    if (c > 0) {
      if (p == end || !IsBlank(*p)) return false;
      while (p < end && IsBlank(*p)) ++p;
    }
    if (!ReadShortDecimal(&p, end, &values[c])) return false;
  }
  return p == end;
}

bool LooksNotFinite(std::string_view cell) {
  std::string lowered(cell);
  for (char& c : lowered) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lowered.find("nan") != std::string::npos || lowered.find("inf") != std::string::npos;
}

// ImuLogSpacing::kEven's rule on a time axis whose median step CheckLogTime gave: no step
// above kMaxGapSteps median steps (a gap), and no block of consecutive steps whose median
// step is more than kMaxRateChange from the log's (a change of rate). Jitter and a few lost
// samples pass: a pose's mean and variance are those of the samples it holds.
constexpr double kMaxGapSteps = 10.0;
constexpr double kMaxRateChange = 0.05;
constexpr size_t kMinRateBlock = 100;

Status CheckEvenSpacing(const std::vector<double>& timestamp_s, double median_step_s) {
  const size_t steps = timestamp_s.size() - 1;
  for (size_t j = 1; j <= steps; ++j) {
    const double step_s = timestamp_s[j] - timestamp_s[j - 1];
    if (step_s <= kMaxGapSteps * median_step_s) continue;
    return Status::Error(StringPrintf(
        "sample %zu (t = %.9g s) follows the previous one by %.6g s, %.4g times the log's median "
        "step of %.6g s: the log has a gap (lost samples, a pause, or two recordings joined), "
        "inside which the sensor may have moved; calibrate from the part before or after the "
        "gap, or record the session again",
        j + 1, timestamp_s[j], step_s, step_s / median_step_s, median_step_s));
  }
  // Blocks of a twentieth of the log (at least kMinRateBlock steps); the last one takes the rest.
  const size_t block = std::max(kMinRateBlock, steps / 20);
  std::vector<double> block_steps;
  for (size_t first = 1; first + block / 2 <= steps + 1; first += block) {
    const size_t last = first + block > steps + 1 - block / 2 ? steps : first + block - 1;
    block_steps.clear();
    for (size_t j = first; j <= last; ++j)
      block_steps.push_back(timestamp_s[j] - timestamp_s[j - 1]);
    const double block_median_s = UpperMedian(block_steps);
    if (std::abs(block_median_s - median_step_s) > kMaxRateChange * median_step_s) {
      return Status::Error(StringPrintf(
          "the sampling rate changes within the log: from sample %zu to %zu (t = %.9g to %.9g s) "
          "the median step is %.6g s, against %.6g s over the log; a calibration needs one rate "
          "(its static detector and noise model count samples): resample the log to one rate, "
          "or cut it where the rate changes",
          first, last + 1, timestamp_s[first - 1], timestamp_s[last], block_median_s,
          median_step_s));
    }
    if (last == steps) break;
  }
  return Status::Ok();
}

Status CheckSpacing(const std::vector<double>& timestamp_s, ImuLogSpacing spacing) {
  double step_s = 0.0;
  ACCELCAL_RETURN_IF_ERROR(CheckLogTime(timestamp_s, "t", &step_s));
  return spacing == ImuLogSpacing::kEven ? CheckEvenSpacing(timestamp_s, step_s) : Status::Ok();
}

}  // namespace

ImuLogLayout ImuLogLayoutOf(const std::string& path) {
  if (path.size() < 4) return ImuLogLayout::kWhitespace;
  std::string suffix = path.substr(path.size() - 4);
  for (char& c : suffix) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return suffix == ".csv" ? ImuLogLayout::kCsv : ImuLogLayout::kWhitespace;
}

const char* ImuLogLayoutName(ImuLogLayout layout) {
  return layout == ImuLogLayout::kCsv ? "CSV (t_s,acc_x,acc_y,acc_z)"
                                      : "whitespace ASCII (t [s], x, y, z)";
}

ImuLogLineParser::ImuLogLineParser(ImuLogLayout layout)
    : layout_(layout), csv_({{"t_s"}, {"acc_x"}, {"acc_y"}, {"acc_z"}}) {}

Status ImuLogLineParser::ParseLine(std::string_view line, bool* is_sample) {
  *is_sample = false;
  if (layout_ == ImuLogLayout::kCsv) {
    CsvLineParser::LineKind kind;
    ACCELCAL_RETURN_IF_ERROR(csv_.ParseLine(line, &kind));
    line_number_ = csv_.line_number();
    if (kind != CsvLineParser::LineKind::kRow) return Status::Ok();
    t_s_ = csv_.number(0);
    output_ = {csv_.number(1), csv_.number(2), csv_.number(3)};
  } else {
    ++line_number_;
    if (line_number_ == 1 && line.substr(0, 3) == "\xEF\xBB\xBF") line.remove_prefix(3);
    const std::string_view trimmed = TrimBlanks(line);
    if (trimmed.empty() || trimmed.front() == '#') return Status::Ok();
    ACCELCAL_RETURN_IF_ERROR(ParseWhitespaceLine(trimmed));
  }
  ACCELCAL_RETURN_IF_ERROR(CheckTime());
  ++sample_count_;
  *is_sample = true;
  return Status::Ok();
}

Status ImuLogLineParser::ParseWhitespaceLine(std::string_view trimmed) {
  double values[4];
  if (ReadFourShortDecimals(trimmed, values)) {
    t_s_ = values[0];
    output_ = {values[1], values[2], values[3]};
    return Status::Ok();
  }
  // A character loop: string_view::find_first_of calls memchr once per character.
  std::string_view fields[4];
  size_t count = 0;
  const char* p = trimmed.data();
  const char* const end = p + trimmed.size();
  while (p < end) {  // `trimmed` starts and ends with a field
    const char* const field = p;
    while (p < end && !IsBlank(*p)) ++p;
    if (count < 4) fields[count] = std::string_view(field, p - field);
    ++count;
    while (p < end && IsBlank(*p)) ++p;
  }
  if (count != 4) {
    const bool commas = trimmed.find(',') != std::string_view::npos;
    return Status::Error(
        Where(line_number_) + ": " + std::to_string(count) + " column(s), expected 4 (" +
        kWhitespaceColumns + ") separated by blanks" +
        (commas ? std::string("; a CSV log must be named *.csv and start with the header ") +
                      kCsvHeaderHint
                : std::string("")));
  }
  static const char* const kNames[4] = {"t", "x", "y", "z"};
  for (int c = 0; c < 4; ++c) {
    if (!ParseShortDecimal(fields[c], &values[c]) && !ParseFiniteNumber(fields[c], &values[c])) {
      return Status::Error(Where(line_number_) + ", column " + std::to_string(c + 1) + " (" +
                           kNames[c] + "): '" + EchoInput(fields[c]) + "' is " +
                           (LooksNotFinite(fields[c])
                                ? "not a finite number; remove or repair the sample"
                                : "not a number"));
    }
  }
  t_s_ = values[0];
  output_ = {values[1], values[2], values[3]};
  return Status::Ok();
}

Status ImuLogLineParser::CheckTime() {
  if (sample_count_ > 0 && !(t_s_ > previous_t_s_)) {
    return Status::Error(StringPrintf(
        "%s: time %.9g s does not increase from the previous sample's %.9g s; a log's time "
        "must be strictly increasing (sort it, or drop the repeated sample)",
        Where(line_number_).c_str(), t_s_, previous_t_s_));
  }
  previous_t_s_ = t_s_;
  return Status::Ok();
}

Status ImuLogLineParser::Finish() const {
  if (layout_ == ImuLogLayout::kCsv) return csv_.Finish();
  if (sample_count_ == 0) {
    return Status::Error(std::string("no samples: expected lines of 4 numbers (") +
                         kWhitespaceColumns + ")");
  }
  return Status::Ok();
}

Status ImuLogLineParser::UnterminatedLastLine(std::string_view rest) const {
  if (layout_ == ImuLogLayout::kCsv) return csv_.UnterminatedLastLine(rest);
  return Status::Error(Where(line_number_ + 1) +
                       " has no line end: the file looks cut short; copy it again, or end the "
                       "line if it is complete");
}

Status ParseImuLog(std::string_view text, ImuLogLayout layout, TriadLog* log,
                   ImuLogSpacing spacing) {
  *log = TriadLog();
  ImuLogLineParser parser(layout);
  size_t begin = 0;
  while (begin < text.size()) {
    const size_t end = text.find('\n', begin);
    if (end == std::string_view::npos) return parser.UnterminatedLastLine(text.substr(begin));
    bool is_sample = false;
    ACCELCAL_RETURN_IF_ERROR(parser.ParseLine(text.substr(begin, end - begin), &is_sample));
    if (is_sample) {
      const std::array<double, 3>& v = parser.output();
      log->Add(parser.t_s(), v[0], v[1], v[2]);
    }
    begin = end + 1;
  }
  ACCELCAL_RETURN_IF_ERROR(parser.Finish());
  return CheckSpacing(log->timestamp_s, spacing);
}

Status StreamImuLog(const std::string& path, size_t batch_samples,
                    const std::function<void(const TriadLog& batch)>& on_batch) {
  ImuLogLineParser parser(ImuLogLayoutOf(path));
  TriadLog batch;
  const size_t batch_limit = std::max<size_t>(1, batch_samples);
  ACCELCAL_RETURN_IF_ERROR(StreamTextLines(
      path, "an accelerometer log", kMaxLineBytes,
      [&](std::string_view line) {
        bool is_sample = false;
        ACCELCAL_RETURN_IF_ERROR(parser.ParseLine(line, &is_sample));
        if (!is_sample) return Status::Ok();
        const std::array<double, 3>& v = parser.output();
        batch.Add(parser.t_s(), v[0], v[1], v[2]);
        if (batch.size() >= batch_limit) {
          on_batch(batch);
          batch = TriadLog();
        }
        return Status::Ok();
      },
      [&](std::string_view rest) { return parser.UnterminatedLastLine(rest); }));
  ACCELCAL_RETURN_IF_ERROR(parser.Finish().WithContext(path));
  if (batch.size() > 0) on_batch(batch);
  return Status::Ok();
}

Status ReadImuLog(const std::string& path, TriadLog* log, ImuLogSpacing spacing) {
  *log = TriadLog();
  ACCELCAL_RETURN_IF_ERROR(StreamImuLog(path, 1 << 16, [log](const TriadLog& batch) {
    log->timestamp_s.insert(log->timestamp_s.end(), batch.timestamp_s.begin(),
                            batch.timestamp_s.end());
    log->output.insert(log->output.end(), batch.output.begin(), batch.output.end());
  }));
  return CheckSpacing(log->timestamp_s, spacing).WithContext(path);
}

}  // namespace accelcal
