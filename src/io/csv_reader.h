#ifndef ACCELCAL_IO_CSV_READER_H_
#define ACCELCAL_IO_CSV_READER_H_

// A strict reader for the CSV layout (calibration.csv: theta,ax,ay; trajectory.csv:
// t,ax,ay; landmarks.csv: name,x,y). The header must name the expected columns in
// order; every data row must have exactly that many fields; numeric cells must be
// finite numbers with a decimal point. Any violation fails with the line and column,
// e.g. "line 17, column 'ay': 'abc' is not a number". Blank lines and lines starting
// with '#' are comments.

#include <string>
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

// Reads `path`; failures carry no file name (callers add it with WithContext).
Status ReadCsvFile(const std::string& path, const std::vector<CsvColumn>& columns, CsvTable* table);

// The same on text already in memory (tests and fuzzing).
Status ParseCsv(const std::string& text, const std::vector<CsvColumn>& columns, CsvTable* table);

// Parses one finite decimal number (leading/trailing blanks allowed); false otherwise.
bool ParseFiniteNumber(const std::string& text, double* value);

}  // namespace accelcal

#endif  // ACCELCAL_IO_CSV_READER_H_
