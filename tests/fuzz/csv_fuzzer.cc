// libFuzzer target: the CSV reader on arbitrary bytes, with each of the three layouts'
// columns (calibration, run, landmarks). It must return a Status for every input; a crash,
// a sanitizer report or a table whose columns disagree in length is a finding.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "io/csv_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  static const std::vector<std::vector<accelcal::CsvColumn>> kLayouts = {
      {{"theta"}, {"ax"}, {"ay"}}, {{"t"}, {"ax"}, {"ay"}}, {{"name", false}, {"x"}, {"y"}}};
  for (const auto& columns : kLayouts) {
    accelcal::CsvTable table;
    if (!accelcal::ParseCsv(text, columns, &table).ok()) continue;
    for (size_t c = 0; c < columns.size(); ++c) {
      const size_t rows = columns[c].numeric ? table.numbers[c].size() : table.texts[c].size();
      if (rows != static_cast<size_t>(table.row_count)) std::abort();
    }
  }
  return 0;
}
