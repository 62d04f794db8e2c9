#include "io/course_mat.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <utility>

#include "common/format.h"
#include "io/mat_file.h"

namespace accelcal {
namespace {

std::string Shape(const MatMatrix& matrix) {
  return std::to_string(matrix.rows) + "x" + std::to_string(matrix.cols);
}

// A column vector (Nx1) or a row vector (1xN), as MATLAB users write either.
Status ReadVector(MatFileReader* reader, const std::string& name, const std::string& meaning,
                  std::vector<double>* values) {
  MatMatrix matrix;
  ACCELCAL_RETURN_IF_ERROR(reader->ReadMatrix(name, &matrix));
  if (matrix.rows != 1 && matrix.cols != 1) {
    return Status::Error("variable '" + name + "' is " + Shape(matrix) + "; expected Nx1 " +
                         meaning);
  }
  *values = matrix.values;
  for (size_t i = 0; i < values->size(); ++i) {
    if (!std::isfinite((*values)[i])) {
      return Status::Error(name + "(" + std::to_string(i + 1) + ") is " +
                           StringPrintf("%.6g", (*values)[i]) + "; remove or repair the sample");
    }
  }
  return Status::Ok();
}

// An Nx2 matrix (x then y) whose row count must equal `expected_rows`.
// A 2xN matrix (MATLAB users often save [ax; ay]) is read as its transpose and said in
// `notes`; it cannot be confused with Nx2 unless N is 2.
Status ReadTwoColumns(MatFileReader* reader, const std::string& name, int expected_rows,
                      const std::string& row_variable, std::vector<double>* x,
                      std::vector<double>* y, std::vector<std::string>* notes) {
  MatMatrix matrix;
  ACCELCAL_RETURN_IF_ERROR(reader->ReadMatrix(name, &matrix));
  if (matrix.rows == 2 && matrix.cols == expected_rows && expected_rows != 2) {
    MatMatrix transpose{matrix.cols, 2, std::vector<double>(matrix.values.size())};
    for (int row = 0; row < matrix.cols; ++row) {
      transpose.values[row] = matrix(0, row);
      transpose.values[matrix.cols + row] = matrix(1, row);
    }
    notes->push_back("variable '" + name + "' is " + Shape(matrix) + "; read as its transpose (" +
                     Shape(transpose) + ", x then y)");
    matrix = std::move(transpose);
  }
  if (matrix.cols != 2) {
    return Status::Error("variable '" + name + "' is " + Shape(matrix) + "; expected " +
                         std::to_string(expected_rows) + "x2 (x then y, m/s^2)");
  }
  if (matrix.rows != expected_rows) {
    return Status::Error("variable '" + name + "' has " + std::to_string(matrix.rows) +
                         " rows but '" + row_variable + "' has " + std::to_string(expected_rows) +
                         "; they must match sample for sample");
  }
  for (int col = 0; col < 2; ++col) {
    for (int row = 0; row < matrix.rows; ++row) {
      if (!std::isfinite(matrix(row, col))) {
        return Status::Error(name + "(" + std::to_string(row + 1) + "," + std::to_string(col + 1) +
                             ") is " + StringPrintf("%.6g", matrix(row, col)) +
                             "; remove or repair the sample");
      }
    }
  }
  x->assign(matrix.values.begin(), matrix.values.begin() + matrix.rows);
  y->assign(matrix.values.begin() + matrix.rows, matrix.values.end());
  return Status::Ok();
}

bool IsMatlabIdentifier(const std::string& name) {
  if (name.empty() || name.size() > 63 || !std::isalpha(static_cast<unsigned char>(name[0])))
    return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  });
}

MatMatrix Columns(const std::vector<const std::vector<double>*>& columns) {
  MatMatrix matrix;
  matrix.rows = static_cast<int>(columns[0]->size());
  matrix.cols = static_cast<int>(columns.size());
  for (const std::vector<double>* column : columns) {
    matrix.values.insert(matrix.values.end(), column->begin(), column->end());
  }
  return matrix;
}

}  // namespace

Status LoadCalibrationMat(const std::string& path, CalibrationTest* test,
                          std::vector<std::string>* notes) {
  MatFileReader reader;
  ACCELCAL_RETURN_IF_ERROR(reader.Open(path));
  ACCELCAL_RETURN_IF_ERROR(ReadVector(&reader, "tita", "angles (rad)", &test->theta_rad));
  return ReadTwoColumns(&reader, "datos", test->size(), "tita", &test->measured_x,
                        &test->measured_y, notes);
}

Status LoadRunMat(const std::string& path, VehicleRun* run, std::vector<std::string>* notes) {
  MatFileReader reader;
  ACCELCAL_RETURN_IF_ERROR(reader.Open(path));
  ACCELCAL_RETURN_IF_ERROR(ReadVector(&reader, "t", "times (s)", &run->timestamp_s));
  // The assignment calls the matrix `acel`; the course's file names it `Aerr`.
  std::vector<std::string> names;
  ACCELCAL_RETURN_IF_ERROR(reader.ListVariables(&names));
  const bool has_aerr = std::find(names.begin(), names.end(), "Aerr") != names.end();
  const bool has_acel = std::find(names.begin(), names.end(), "acel") != names.end();
  if (has_aerr && has_acel) {
    return Status::Error(
        "the file holds both 'Aerr' (the course's name) and 'acel' (the assignment's) for the "
        "run's accelerations; keep the one that is the run");
  }
  const std::string name = (!has_aerr && has_acel) ? "acel" : "Aerr";
  return ReadTwoColumns(&reader, name, run->size(), "t", &run->measured_x, &run->measured_y, notes);
}

Status LoadLandmarksMat(const std::string& path, std::vector<Landmark>* landmarks) {
  MatFileReader reader;
  ACCELCAL_RETURN_IF_ERROR(reader.Open(path));
  std::vector<std::string> names;
  ACCELCAL_RETURN_IF_ERROR(reader.ListVariables(&names));
  for (const std::string& name : names) {
    // Every variable of puntos.mat is a landmark, so a variable MATLAB saves without being
    // asked (the last unnamed result `ans`, or a hidden one starting with '_') would become a
    // landmark nobody placed. Such a file is refused rather than read with a stray landmark.
    if (name == "ans" || name.empty() || name.front() == '_') {
      return Status::Error(
          "variable '" + name + "' is " +
          (name == "ans" ? "MATLAB's last unnamed result" : "a variable MATLAB hides") +
          ", not a landmark: save the file with the landmarks only, e.g. save "
          "puntos.mat A B C D");
    }
  }
  // All at once: one pass over the file however many landmarks it holds.
  std::vector<std::pair<std::string, MatMatrix>> matrices;
  ACCELCAL_RETURN_IF_ERROR(
      reader.ReadAllMatrices(2, "every landmark must be a 1x2 [x y] in metres", &matrices));
  for (const auto& [name, matrix] : matrices) {
    if (matrix.values.size() != 2) {
      return Status::Error("variable '" + name + "' is " + Shape(matrix) +
                           "; every landmark must be a 1x2 [x y] in metres");
    }
    if (!std::isfinite(matrix.values[0]) || !std::isfinite(matrix.values[1])) {
      return Status::Error("landmark '" + name + "' is not finite");
    }
    landmarks->push_back({name, matrix.values[0], matrix.values[1]});
  }
  return Status::Ok();
}

Status WriteCalibrationMat(const std::string& path, const CalibrationTest& test) {
  return WriteMatFile(path, {{"tita", Columns({&test.theta_rad})},
                             {"datos", Columns({&test.measured_x, &test.measured_y})}});
}

Status WriteRunMat(const std::string& path, const VehicleRun& run) {
  return WriteMatFile(path, {{"t", Columns({&run.timestamp_s})},
                             {"Aerr", Columns({&run.measured_x, &run.measured_y})}});
}

Status WriteLandmarksMat(const std::string& path, const std::vector<Landmark>& landmarks) {
  std::vector<std::pair<std::string, MatMatrix>> points;
  for (const Landmark& landmark : landmarks) {
    if (!IsMatlabIdentifier(landmark.name)) {
      return Status::Error("landmark '" + landmark.name +
                           "' cannot be a MATLAB variable name; use the CSV layout or rename it");
    }
    points.push_back({landmark.name, MatMatrix{1, 2, {landmark.x_m, landmark.y_m}}});
  }
  return WriteMatFile(path, points);
}

}  // namespace accelcal
