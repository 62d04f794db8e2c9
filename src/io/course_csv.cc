#include "io/course_csv.h"

#include "common/format.h"
#include "io/atomic_file.h"
#include "io/csv_reader.h"
#include "io/input_text.h"

namespace accelcal {
namespace {

// A landmark's name is shown whole in tables, JSON and messages: it must be a printable
// line of at most kMaxLandmarkNameBytes (a MAT file's names are identifiers of at most 63).
constexpr size_t kMaxLandmarkNameBytes = 100;

Status CheckLandmarkName(const std::string& name, int row) {
  if (IsPrintableUtf8(name) && name.size() <= kMaxLandmarkNameBytes) return Status::Ok();
  return Status::Error("landmark " + std::to_string(row) + "'s name '" + EchoInput(name) + "' (" +
                       std::to_string(name.size()) + " bytes) is not a name: use at most " +
                       std::to_string(kMaxLandmarkNameBytes) +
                       " printable characters, in UTF-8 (save the file as UTF-8, not Latin-1)");
}

const std::vector<CsvColumn> kRunColumns = {{"t"}, {"ax"}, {"ay"}};
const std::vector<CsvColumn> kLandmarkColumns = {{"name", false}, {"x"}, {"y"}};

Status WriteThreeColumnCsv(const std::string& path, const char* header,
                           const std::vector<double>& first, const std::vector<double>& second,
                           const std::vector<double>& third) {
  std::string text = std::string(header) + "\n";
  text.reserve(text.size() + 72 * first.size());
  for (size_t i = 0; i < first.size(); ++i) {
    text += StringPrintf("%.17g,%.17g,%.17g\n", first[i], second[i], third[i]);
  }
  return WriteFileAtomically(path, text);
}

}  // namespace

Status LoadRunCsv(const std::string& path, VehicleRun* run) {
  CsvTable table;
  ACCELCAL_RETURN_IF_ERROR(ReadCsvFile(path, kRunColumns, &table));
  run->timestamp_s = std::move(table.numbers[0]);
  run->measured_x = std::move(table.numbers[1]);
  run->measured_y = std::move(table.numbers[2]);
  return Status::Ok();
}

Status LoadLandmarksCsv(const std::string& path, std::vector<Landmark>* landmarks) {
  CsvTable table;
  Status status = ReadCsvFile(path, kLandmarkColumns, &table);
  for (int i = 0; status.ok() && i < table.row_count; ++i) {
    // Names are quoted whole in the outputs and in CheckLandmarks' messages.
    status = CheckLandmarkName(table.texts[0][i], i + 1);
    if (status.ok()) {
      landmarks->push_back({table.texts[0][i], table.numbers[1][i], table.numbers[2][i]});
    }
  }
  return status;
}

Status WriteCalibrationCsv(const std::string& path, const CalibrationTest& test) {
  return WriteThreeColumnCsv(path, "theta,ax,ay", test.theta_rad, test.measured_x, test.measured_y);
}

Status WriteRunCsv(const std::string& path, const VehicleRun& run) {
  return WriteThreeColumnCsv(path, "t,ax,ay", run.timestamp_s, run.measured_x, run.measured_y);
}

Status WriteLandmarksCsv(const std::string& path, const std::vector<Landmark>& landmarks) {
  std::string text = "name,x,y\n";
  for (const Landmark& landmark : landmarks) {
    text += StringPrintf("%s,%.17g,%.17g\n", landmark.name.c_str(), landmark.x_m, landmark.y_m);
  }
  return WriteFileAtomically(path, text);
}

}  // namespace accelcal
