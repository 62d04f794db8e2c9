#ifndef ACCELCAL_IO_MAT_FILE_H_
#define ACCELCAL_IO_MAT_FILE_H_

// MATLAB .mat files through libmatio, with the checks matio does not make. matio returns
// a damaged variable at its declared size without any error (a truncated file, a compressed
// variable that inflates short, data shorter than its dimensions: the gap as zeros or the
// next variable's bytes), so Open() first validates the whole file against what it
// declares: a version 5 file element by element, each compressed variable inflated whole
// and exactly to its declared length, each numeric variable holding one value per element,
// no name twice; a version 4 file matrix by matrix; a version 7.3 (HDF5) file against the
// length HDF5 recorded, then read in a child process (HDF5 on a damaged file may crash).
// Every failure is a one-line Status naming the variable or the byte; callers add the file
// name with Status::WithContext.

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "common/status.h"

namespace accelcal {

// A real matrix, column-major as MATLAB stores it.
struct MatMatrix {
  int rows = 0;
  int cols = 0;
  std::vector<double> values;  // rows * cols, column-major

  double operator()(int row, int col) const { return values[col * rows + row]; }
};

// A variable as MATLAB's `whos` describes it.
struct MatVariableDescription {
  std::string name;
  std::string class_name;  // "double", "int16", "logical", "char", "struct", "cell", ...
  std::vector<uint64_t> dims;
  std::vector<std::string> fields;  // a struct's, the first few
};

class MatFileReader {
 public:
  MatFileReader();
  ~MatFileReader();
  MatFileReader(const MatFileReader&) = delete;
  MatFileReader& operator=(const MatFileReader&) = delete;

  // Opens `path` for reading; fails for a missing, empty, truncated, damaged or non-MAT file,
  // and for anything but a regular file of at most kMaxMatFileBytes (io/input_file.h). A
  // version 7.3 file is read whole here, by a child process.
  Status Open(const std::string& path);

  // The names of the file's variables, in file order.
  Status ListVariables(std::vector<std::string>* names);

  // The file's variables in file order, each with its class and dimensions.
  Status DescribeVariables(std::vector<MatVariableDescription>* variables);

  // Reads a real, non-empty, two-dimensional numeric variable (double, or single
  // widened to double). Integer, complex, sparse, cell, struct and character
  // variables are refused with their class in the message.
  Status ReadMatrix(const std::string& variable, MatMatrix* matrix);

  // Reads as ReadMatrix does, and integer variables (int8 ... uint64, a logger's raw counts)
  // too, widened to double exactly: a 64-bit value a double cannot hold (beyond 2^53) is
  // refused. For IMU logs (io/imu_log.cc); the course's files keep ReadMatrix, whose
  // variables are doubles.
  Status ReadNumericMatrix(const std::string& variable, MatMatrix* matrix);

  // Every variable of the file in file order, each checked as ReadMatrix checks it, and each
  // of at most `max_values` values (a larger one is refused before any data is read, by name
  // and shape, followed by `oversize_advice`). Two passes over the file whatever the number of
  // variables: ReadMatrix looks a variable up from the start of the file, so reading n variables
  // one by one takes n^2/2 element reads (2,001 landmarks: 1.5 minutes).
  Status ReadAllMatrices(uint64_t max_values, const std::string& oversize_advice,
                         std::vector<std::pair<std::string, MatMatrix>>* matrices);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  Status Read(const std::string& variable, bool integers, MatMatrix* matrix);
};

// Writes real double matrices as an uncompressed MATLAB v5 file (the layout FreeMat
// and MATLAB use for the course files), atomically: a temporary file in the same
// directory is renamed into place only when every variable is written.
Status WriteMatFile(const std::string& path,
                    const std::vector<std::pair<std::string, MatMatrix>>& variables);

}  // namespace accelcal

#endif  // ACCELCAL_IO_MAT_FILE_H_
