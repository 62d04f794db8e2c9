#ifndef ACCELCAL_IO_MAT_FILE_H_
#define ACCELCAL_IO_MAT_FILE_H_

// MATLAB .mat files through libmatio, with the checks matio does not make. matio
// returns a truncated variable at its declared size without any error, so Open()
// first walks the top-level elements of a version 5 file and refuses one whose
// elements run past the end of the file. Every failure is a Status naming the
// variable; callers add the file name with Status::WithContext.

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

class MatFileReader {
 public:
  MatFileReader();
  ~MatFileReader();
  MatFileReader(const MatFileReader&) = delete;
  MatFileReader& operator=(const MatFileReader&) = delete;

  // Opens `path` for reading; fails for a missing, empty, truncated or non-MAT file.
  Status Open(const std::string& path);

  // The names of the file's variables, in file order.
  Status ListVariables(std::vector<std::string>* names);

  // Reads a real, non-empty, two-dimensional numeric variable (double, or single
  // widened to double). Integer, complex, sparse, cell, struct and character
  // variables are refused with their class in the message.
  Status ReadMatrix(const std::string& variable, MatMatrix* matrix);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Writes real double matrices as an uncompressed MATLAB v5 file (the layout FreeMat
// and MATLAB use for the course files), atomically: a temporary file in the same
// directory is renamed into place only when every variable is written.
Status WriteMatFile(const std::string& path,
                    const std::vector<std::pair<std::string, MatMatrix>>& variables);

}  // namespace accelcal

#endif  // ACCELCAL_IO_MAT_FILE_H_
