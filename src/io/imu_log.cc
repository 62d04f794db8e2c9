#include "io/imu_log.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <vector>

#include "common/format.h"
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
// its cost. False for anything else (other forms, more digits, not a number), which is then
// left to ParseFiniteNumber, the arbiter of what a number is.
bool ParseShortDecimal(std::string_view text, double* value) {
  static constexpr double kPowersOfTen[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                            1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                            1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
  constexpr int kMaxDigits = 19;  // significant digits: below 10^19 < 2^64
  constexpr uint64_t kMaxExactInteger = uint64_t{1} << 53;
  const char* p = text.data();
  const char* const end = p + text.size();
  bool negative = false;
  if (p < end && (*p == '-' || *p == '+')) negative = *p++ == '-';
  uint64_t mantissa = 0;
  int digits = 0;
  int exponent = 0;
  bool any_digit = false;
  for (; p < end && *p >= '0' && *p <= '9'; ++p) {
    if ((mantissa != 0 || *p != '0') && ++digits > kMaxDigits) return false;
    mantissa = mantissa * 10 + (*p - '0');
    any_digit = true;
  }
  if (p < end && *p == '.') {
    for (++p; p < end && *p >= '0' && *p <= '9'; ++p) {
      if ((mantissa != 0 || *p != '0') && ++digits > kMaxDigits) return false;
      mantissa = mantissa * 10 + (*p - '0');
      --exponent;
      any_digit = true;
    }
  }
  if (!any_digit) return false;
  if (p < end && (*p == 'e' || *p == 'E')) {
    ++p;
    bool negative_exponent = false;
    if (p < end && (*p == '-' || *p == '+')) negative_exponent = *p++ == '-';
    if (p == end) return false;
    int written = 0;
    for (; p < end && *p >= '0' && *p <= '9'; ++p) {
      if (written > 1000) return false;
      written = written * 10 + (*p - '0');
    }
    exponent += negative_exponent ? -written : written;
  }
  if (p != end || mantissa > kMaxExactInteger || exponent < -22 || exponent > 22) return false;
  const double m = static_cast<double>(mantissa);
  const double magnitude = exponent < 0 ? m / kPowersOfTen[-exponent] : m * kPowersOfTen[exponent];
  *value = negative ? -magnitude : magnitude;
  return true;
}

bool LooksNotFinite(std::string_view cell) {
  std::string lowered(cell);
  for (char& c : lowered) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lowered.find("nan") != std::string::npos || lowered.find("inf") != std::string::npos;
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
  // A character loop: string_view::find_first_of calls memchr once per character.
  std::string_view fields[4];
  size_t count = 0;
  const char* p = trimmed.data();
  const char* const end = p + trimmed.size();
  while (p < end) {  // `trimmed` starts and ends with a field
    const char* const field = p;
    while (p < end && *p != ' ' && *p != '\t') ++p;
    if (count < 4) fields[count] = std::string_view(field, p - field);
    ++count;
    while (p < end && (*p == ' ' || *p == '\t')) ++p;
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
  double values[4];
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

Status ParseImuLog(std::string_view text, ImuLogLayout layout, TriadLog* log) {
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
  double step_s = 0.0;
  return CheckLogTime(log->timestamp_s, "t", &step_s);
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

Status ReadImuLog(const std::string& path, TriadLog* log) {
  *log = TriadLog();
  ACCELCAL_RETURN_IF_ERROR(StreamImuLog(path, 1 << 16, [log](const TriadLog& batch) {
    log->timestamp_s.insert(log->timestamp_s.end(), batch.timestamp_s.begin(),
                            batch.timestamp_s.end());
    log->output.insert(log->output.end(), batch.output.begin(), batch.output.end());
  }));
  double step_s = 0.0;
  return CheckLogTime(log->timestamp_s, "t", &step_s).WithContext(path);
}

}  // namespace accelcal
