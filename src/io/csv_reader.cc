#include "io/csv_reader.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

namespace accelcal {
namespace {

std::string Trim(const std::string& text) {
  const size_t begin = text.find_first_not_of(" \t\r");
  if (begin == std::string::npos) return "";
  const size_t end = text.find_last_not_of(" \t\r");
  return text.substr(begin, end - begin + 1);
}

std::string Lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

std::vector<std::string> SplitFields(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream stream(line);
  while (std::getline(stream, field, ',')) fields.push_back(Trim(field));
  if (!line.empty() && line.back() == ',') fields.push_back("");
  return fields;
}

std::string Unquote(const std::string& text) {
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

}  // namespace

bool ParseFiniteNumber(const std::string& text, double* value) {
  std::string trimmed = Trim(text);
  if (!trimmed.empty() && trimmed.front() == '+') trimmed.erase(0, 1);
  if (trimmed.empty()) return false;
  const char* begin = trimmed.data();
  const char* end = begin + trimmed.size();
  const auto [pointer, error] = std::from_chars(begin, end, *value);
  return error == std::errc() && pointer == end && std::isfinite(*value);
}

Status ParseCsv(const std::string& text, const std::vector<CsvColumn>& columns, CsvTable* table) {
  table->numbers.assign(columns.size(), {});
  table->texts.assign(columns.size(), {});
  table->row_count = 0;
  std::istringstream stream(text);
  std::string line;
  int line_number = 0;
  bool header_seen = false;
  const std::string expected = JoinNames(columns);
  while (std::getline(stream, line)) {
    ++line_number;
    if (line_number == 1 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);  // BOM
    const std::string trimmed = Trim(line);
    if (trimmed.empty() || trimmed.front() == '#') continue;
    const std::string where = "line " + std::to_string(line_number);
    const std::vector<std::string> fields = SplitFields(trimmed);
    if (!header_seen) {
      header_seen = true;
      bool matches = fields.size() == columns.size();
      for (size_t c = 0; matches && c < columns.size(); ++c) {
        matches = Lower(Unquote(fields[c])) == Lower(columns[c].name);
      }
      if (!matches) {
        const bool semicolons = fields.size() == 1 && trimmed.find(';') != std::string::npos;
        return Status::Error(where + ": the header is '" + trimmed + "', expected '" + expected +
                             "'" +
                             (semicolons ? "; the file separates fields with ';' (a spreadsheet "
                                           "with decimal commas?): export it with ',' between "
                                           "fields and '.' as the decimal point"
                                         : ""));
      }
      continue;
    }
    if (fields.size() != columns.size()) {
      std::string hint;
      if (fields.size() > columns.size()) {
        hint = "; if the numbers use decimal commas, write them with a point";
      }
      return Status::Error(where + ": " + std::to_string(fields.size()) + " fields, expected " +
                           std::to_string(columns.size()) + " (" + expected + ")" + hint);
    }
    for (size_t c = 0; c < columns.size(); ++c) {
      const std::string cell = Unquote(fields[c]);
      if (!columns[c].numeric) {
        if (cell.empty()) {
          return Status::Error(where + ", column '" + columns[c].name + "': the cell is empty");
        }
        table->texts[c].push_back(cell);
        continue;
      }
      double value;
      if (!ParseFiniteNumber(cell, &value)) {
        const std::string lowered = Lower(cell);
        const bool not_finite =
            lowered.find("nan") != std::string::npos || lowered.find("inf") != std::string::npos;
        return Status::Error(
            where + ", column '" + columns[c].name + "': '" + cell + "' is " +
            (not_finite ? "not a finite number; remove or repair the sample" : "not a number"));
      }
      table->numbers[c].push_back(value);
    }
    ++table->row_count;
  }
  if (!header_seen)
    return Status::Error("the file is empty; expected the header '" + expected + "'");
  if (table->row_count == 0) return Status::Error("no data rows after the header");
  return Status::Ok();
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
