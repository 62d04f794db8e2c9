#include "io/csv_reader.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <utility>

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

std::string Lower(std::string_view text) {
  std::string lowered(text);
  std::transform(lowered.begin(), lowered.end(), lowered.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return lowered;
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
  return Status::Error(Where(line_number_) + ": the header is '" + std::string(trimmed) +
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
      const std::string lowered = Lower(cell);
      const bool not_finite =
          lowered.find("nan") != std::string::npos || lowered.find("inf") != std::string::npos;
      return Status::Error(
          Where(line_number_) + ", column '" + columns_[c].name + "': '" + std::string(cell) +
          "' is " +
          (not_finite ? "not a finite number; remove or repair the sample" : "not a number"));
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

Status ParseCsv(const std::string& text, const std::vector<CsvColumn>& columns, CsvTable* table) {
  table->numbers.assign(columns.size(), {});
  table->texts.assign(columns.size(), {});
  table->row_count = 0;
  CsvLineParser parser(columns);
  const std::string_view all(text);
  size_t begin = 0;
  while (begin < all.size()) {
    size_t end = all.find('\n', begin);
    if (end == std::string_view::npos) end = all.size();
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
  return parser.Finish();
}

Status ReadCsvFile(const std::string& path, const std::vector<CsvColumn>& columns,
                   CsvTable* table) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return Status::Error("cannot open the file; check the path and permissions");
  std::ostringstream buffer;
  buffer << file.rdbuf();
  return ParseCsv(buffer.str(), columns, table);
}

}  // namespace accelcal
