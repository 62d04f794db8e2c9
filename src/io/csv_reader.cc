#include "io/csv_reader.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <new>
#include <utility>

#include "common/format.h"
#include "io/input_file.h"
#include "io/input_text.h"

namespace accelcal {
namespace {

// Blanks around lines and cells; '\r' so that CRLF files read like LF files.
bool IsBlank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

std::string_view Trim(std::string_view text) {
  size_t begin = 0;
  size_t end = text.size();
  while (begin < end && IsBlank(text[begin])) ++begin;
  while (end > begin && IsBlank(text[end - 1])) --end;
  return text.substr(begin, end - begin);
}

bool EqualIgnoringCase(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) ==
                  std::tolower(static_cast<unsigned char>(y));
         });
}

std::string_view Unquote(std::string_view text) {
  if (text.size() >= 2 && text.front() == '"' && text.back() == '"') {
    return text.substr(1, text.size() - 2);
  }
  return text;
}

std::string JoinNames(const std::vector<CsvColumn>& columns) {
  std::string joined;
  for (const CsvColumn& column : columns) joined += (joined.empty() ? "" : ",") + column.name;
  return joined;
}

std::string Where(long long line_number) { return "line " + std::to_string(line_number); }

}  // namespace

bool ParseFiniteNumber(std::string_view text, double* value) {
  std::string_view trimmed = Trim(text);
  // std::from_chars takes no '+' sign (a spreadsheet may write one) and no blanks.
  if (!trimmed.empty() && trimmed.front() == '+') trimmed.remove_prefix(1);
  if (trimmed.empty()) return false;
  const char* begin = trimmed.data();
  const char* end = begin + trimmed.size();
  const auto [pointer, error] = std::from_chars(begin, end, *value);
  return error == std::errc() && pointer == end && std::isfinite(*value);
}

std::string NotAFiniteNumberReason(std::string_view text) {
  const std::string lowered = LowerAscii(text);
  if (lowered.find("nan") != std::string::npos || lowered.find("inf") != std::string::npos)
    return "not a finite number; remove or repair the sample";
  std::string_view trimmed = Trim(text);
  if (!trimmed.empty() && trimmed.front() == '+') trimmed.remove_prefix(1);
  double value = 0.0;
  const char* end = trimmed.data() + trimmed.size();
  const auto [pointer, error] = std::from_chars(trimmed.data(), end, value);
  if (error == std::errc::result_out_of_range && pointer == end) {
    // from_chars leaves the value unset out of range; strtod tells overflow from underflow.
    const double magnitude = std::abs(std::strtod(std::string(trimmed).c_str(), nullptr));
    return magnitude > 1.0 ? "not a finite number (beyond a double's range, about 1.8e308); "
                             "remove or repair the sample"
                           : "too close to zero for a double (below about 2.2e-308); write 0 "
                             "or repair the sample";
  }
  return "not a number";
}

CsvLineParser::CsvLineParser(std::vector<CsvColumn> columns)
    : columns_(std::move(columns)),
      expected_header_(JoinNames(columns_)),
      numbers_(columns_.size(), 0.0),
      texts_(columns_.size()) {
  fields_.reserve(columns_.size());
}

Status CsvLineParser::ParseLine(std::string_view line, LineKind* kind) {
  ++line_number_;
  *kind = LineKind::kSkipped;
  if (line_number_ == 1 && line.substr(0, 3) == "\xEF\xBB\xBF") line.remove_prefix(3);  // BOM
  const std::string_view trimmed = Trim(line);
  if (trimmed.empty() || trimmed.front() == '#') return Status::Ok();
  // Split at every ',' (n commas, n + 1 fields); only the first columns_.size() fields are
  // kept, the others only counted, so a long bad line costs no allocation.
  fields_.clear();
  size_t field_count = 0;
  size_t begin = 0;
  while (true) {
    const size_t comma = trimmed.find(',', begin);
    const size_t end = comma == std::string_view::npos ? trimmed.size() : comma;
    if (fields_.size() < columns_.size()) {
      fields_.push_back(Trim(trimmed.substr(begin, end - begin)));
    }
    ++field_count;
    if (comma == std::string_view::npos) break;
    begin = comma + 1;
  }
  if (!header_seen_) {
    header_seen_ = true;
    ACCELCAL_RETURN_IF_ERROR(CheckHeader(trimmed, field_count));
    *kind = LineKind::kHeader;
    return Status::Ok();
  }
  if (field_count != columns_.size()) {
    std::string hint;
    if (field_count > columns_.size()) {
      hint = "; if the numbers use decimal commas, write them with a point";
    }
    return Status::Error(Where(line_number_) + ": " + std::to_string(field_count) +
                         " fields, expected " + std::to_string(columns_.size()) + " (" +
                         expected_header_ + ")" + hint);
  }
  ACCELCAL_RETURN_IF_ERROR(ParseRow());
  *kind = LineKind::kRow;
  return Status::Ok();
}

Status CsvLineParser::CheckHeader(std::string_view trimmed, size_t field_count) const {
  bool matches = field_count == columns_.size();
  for (size_t c = 0; matches && c < columns_.size(); ++c) {
    matches = EqualIgnoringCase(Unquote(fields_[c]), columns_[c].name);
  }
  if (matches) return Status::Ok();
  const bool semicolons = field_count == 1 && trimmed.find(';') != std::string_view::npos;
  return Status::Error(Where(line_number_) + ": the header is '" + EchoInput(trimmed) +
                       "', expected '" + expected_header_ + "'" +
                       (semicolons ? "; the file separates fields with ';' (a spreadsheet "
                                     "with decimal commas?): export it with ',' between "
                                     "fields and '.' as the decimal point"
                                   : ""));
}

Status CsvLineParser::ParseRow() {
  for (size_t c = 0; c < columns_.size(); ++c) {
    const std::string_view cell = Unquote(fields_[c]);
    if (!columns_[c].numeric) {
      if (cell.empty()) {
        return Status::Error(Where(line_number_) + ", column '" + columns_[c].name +
                             "': the cell is empty");
      }
      texts_[c] = cell;
      continue;
    }
    if (!ParseFiniteNumber(cell, &numbers_[c])) {
      return Status::Error(Where(line_number_) + ", column '" + columns_[c].name + "': '" +
                           EchoInput(cell) + "' is " + NotAFiniteNumberReason(cell));
    }
  }
  ++row_count_;
  return Status::Ok();
}

Status CsvLineParser::Finish() const {
  if (!header_seen_) {
    return Status::Error("the file is empty; expected the header '" + expected_header_ + "'");
  }
  if (row_count_ == 0) return Status::Error("no data rows after the header");
  return Status::Ok();
}

Status CsvLineParser::UnterminatedLastLine(std::string_view rest) const {
  // '\r' inside what is left: lines that end in '\r' alone, not a cut.
  if (rest.find('\r') != std::string_view::npos && rest.find('\r') + 1 < rest.size()) {
    return Status::Error(Where(line_number_ + 1) +
                         " and the lines after it end in '\\r' alone (old Mac line endings); "
                         "convert them to '\\n'");
  }
  return Status::Error(Where(line_number_ + 1) +
                       " has no line end: the file looks cut short; copy it again, or end the "
                       "line if it is complete");
}

namespace {

// An upper bound on the data rows of `text`: its complete lines that are neither blank nor
// comments, less one for the header. One pass at memchr's speed, so that the columns are
// sized once (no doubling, which would hold up to 1.5 times the final size while it copies)
// and a shortage of memory is known, and said, before any row is parsed.
size_t CountDataRows(std::string_view text) {
  size_t rows = 0;
  size_t begin = 0;
  while (begin < text.size()) {
    const size_t end = text.find('\n', begin);
    if (end == std::string_view::npos) break;
    size_t first = begin;
    while (first < end && IsBlank(text[first])) ++first;
    if (first < end && text[first] != '#') ++rows;
    begin = end + 1;
  }
  return rows > 0 ? rows - 1 : 0;
}

std::string Bytes(double bytes) {
  if (bytes >= 1024.0 * 1024.0) return StringPrintf("%.0f MiB", bytes / (1024.0 * 1024.0));
  return StringPrintf("%.0f bytes", bytes);
}

}  // namespace

Status ParseCsv(const std::string& text, const std::vector<CsvColumn>& columns, CsvTable* table) {
  table->numbers.assign(columns.size(), {});
  table->texts.assign(columns.size(), {});
  table->row_count = 0;
  const std::string_view all(text);
  const size_t rows = CountDataRows(all);
  try {
    for (size_t c = 0; c < columns.size(); ++c) {
      if (columns[c].numeric) {
        table->numbers[c].reserve(rows);
      } else {
        table->texts[c].reserve(rows);
      }
    }
  } catch (const std::bad_alloc&) {
    table->numbers.assign(columns.size(), {});
    table->texts.assign(columns.size(), {});
    return Status::Error(
        "not enough memory to hold " + std::to_string(rows) + " rows (" +
        Bytes(static_cast<double>(rows) * static_cast<double>(columns.size()) * sizeof(double)) +
        " as numbers, beside the file's " + Bytes(static_cast<double>(text.size())) +
        "); free memory, raise the limit (ulimit -v) or use less data");
  }
  CsvLineParser parser(columns);
  size_t begin = 0;
  try {
    while (begin < all.size()) {
      const size_t end = all.find('\n', begin);
      if (end == std::string_view::npos) return parser.UnterminatedLastLine(all.substr(begin));
      CsvLineParser::LineKind kind;
      ACCELCAL_RETURN_IF_ERROR(parser.ParseLine(all.substr(begin, end - begin), &kind));
      begin = end + 1;
      if (kind != CsvLineParser::LineKind::kRow) continue;
      for (size_t c = 0; c < columns.size(); ++c) {
        if (columns[c].numeric) {
          table->numbers[c].push_back(parser.number(c));
        } else {
          table->texts[c].emplace_back(parser.text(c));
        }
      }
      ++table->row_count;
    }
  } catch (const std::bad_alloc&) {
    // Only text cells (a landmark's name) still allocate once the columns are reserved.
    const long long held = table->row_count;
    table->numbers.assign(columns.size(), {});
    table->texts.assign(columns.size(), {});
    table->row_count = 0;
    return Status::Error("not enough memory to hold the text cells after " + std::to_string(held) +
                         " rows; free memory, raise the limit (ulimit -v) or use less data");
  }
  return parser.Finish();
}

Status ReadCsvFile(const std::string& path, const std::vector<CsvColumn>& columns,
                   CsvTable* table) {
  std::string text;
  ACCELCAL_RETURN_IF_ERROR(ReadInputText(path, kMaxCsvFileBytes, "a CSV file", &text));
  return ParseCsv(text, columns, table);
}

}  // namespace accelcal
