#ifndef ACCELCAL_IO_CSV_READER_H_
#define ACCELCAL_IO_CSV_READER_H_

// A strict reader for the CSV layout (calibration.csv: theta,ax,ay; trajectory.csv:
// t,ax,ay; landmarks.csv: name,x,y). The header must name the expected columns in
// order; every data row must have exactly that many fields; numeric cells must be
// finite numbers with a decimal point. Any violation fails with the line and column,
// e.g. "line 17, column 'ay': 'abc' is not a number" (the cell quoted through EchoInput,
// io/input_text.h). Blank lines and lines starting with '#' are comments. Every line ends
// in '\n' (or "\r\n"): a last line without one is refused, since a file cut short by an
// interrupted copy most often ends inside a number, and "0.4" cut from "0.4817" reads as a
// valid but wrong sample.

#include <string>
#include <string_view>
#include <vector>

#include "common/status.h"

namespace accelcal {

struct CsvColumn {
  std::string name;
  bool numeric = true;  // false: a text cell (e.g. a landmark's name)
};

struct CsvTable {
  // numbers[c] holds column c when it is numeric, texts[c] when it is text.
  std::vector<std::vector<double>> numbers;
  std::vector<std::vector<std::string>> texts;
  int row_count = 0;
};

// Reads `path` whole (ReadInputFile, io/input_file.h: a regular file of at most
// kMaxCsvFileBytes) and parses it; failures carry no file name (callers add it with
// WithContext).
Status ReadCsvFile(const std::string& path, const std::vector<CsvColumn>& columns, CsvTable* table);

// The same on text already in memory (tests and fuzzing). The table's columns are sized once
// for the rows the text can hold; when that memory cannot be had, it fails saying so rather
// than throwing std::bad_alloc.
Status ParseCsv(const std::string& text, const std::vector<CsvColumn>& columns, CsvTable* table);

// Parses one finite decimal number (leading/trailing blanks allowed); false otherwise.
bool ParseFiniteNumber(std::string_view text, double* value);

// Why ParseFiniteNumber refused a cell, to follow "'<cell>' is ": "not a finite number; remove or
// repair the sample" for NaN, an infinity or a number beyond a double's range (1e999: a number,
// but none a double holds), "too close to zero for a double ..." for 1e-999, else "not a number".
std::string NotAFiniteNumberReason(std::string_view text);

// The rules above applied one line at a time, so that ParseCsv (text in memory) and the
// streaming reader (io/calibration_stream.h) accept the same files and fail with the same
// messages. Nothing is allocated per line once the first data row has been parsed: the
// cells are views into the line, numbers are read with std::from_chars.
class CsvLineParser {
 public:
  enum class LineKind { kSkipped, kHeader, kRow };  // kSkipped: blank or '#' comment

  explicit CsvLineParser(std::vector<CsvColumn> columns);

  // Parses the next line of the file, without its '\n'. After kRow, number(c) holds
  // numeric column c and text(c) text column c, valid until the next call (text(c) views
  // `line`). Failures say "line N..." as ParseCsv does.
  Status ParseLine(std::string_view line, LineKind* kind);
  double number(size_t column) const { return numbers_[column]; }
  std::string_view text(size_t column) const { return texts_[column]; }

  // After the last line: fails when there was no header or no data row.
  Status Finish() const;

  // The refusal of a file whose last line (the next one, line_number() + 1) has no '\n'.
  Status UnterminatedLastLine(std::string_view rest) const;

  long long line_number() const { return line_number_; }  // of the last line parsed
  long long row_count() const { return row_count_; }

 private:
  Status CheckHeader(std::string_view trimmed, size_t field_count) const;
  Status ParseRow();

  std::vector<CsvColumn> columns_;
  std::string expected_header_;  // "theta,ax,ay"
  std::vector<std::string_view> fields_;
  std::vector<double> numbers_;
  std::vector<std::string_view> texts_;
  long long line_number_ = 0;
  long long row_count_ = 0;
  bool header_seen_ = false;
};

}  // namespace accelcal

#endif  // ACCELCAL_IO_CSV_READER_H_
