#ifndef ACCELCAL_IO_COURSE_MAT_H_
#define ACCELCAL_IO_COURSE_MAT_H_

// The course layout's .mat files (../shared/spec/error-model.md, "The course data layout"),
// read and written:
//
//   ensayo.mat   tita (Nx1, rad), datos (Nx2, m/s^2, x then y)
//   acel.mat     t (Mx1, s), Aerr (Mx2; the assignment calls it acel, which is read too)
//   puntos.mat   one 1x2 [x y] (m) per landmark, named by the variable
//
// The readers check shapes, lengths and finiteness only; io/course_data.h's loaders add the
// checks that do not depend on the layout (time, angles, landmarks) and the file name. A
// vector may be a row or a column, and a 2xN matrix is read as its transpose with a note.

#include <string>
#include <vector>

#include "common/measurements.h"
#include "common/status.h"

namespace accelcal {

// Each reader appends what it read correctly but a person should hear about (a 2xN matrix
// read as its transpose) to `notes`, one line each without the file name.
Status LoadCalibrationMat(const std::string& path, CalibrationTest* test,
                          std::vector<std::string>* notes);
// The times are read, not checked (CheckUniformTime, io/course_data.h).
Status LoadRunMat(const std::string& path, VehicleRun* run, std::vector<std::string>* notes);
// Every variable is a landmark; MATLAB's own (ans, _hidden) are refused.
Status LoadLandmarksMat(const std::string& path, std::vector<Landmark>* landmarks);

// Uncompressed MATLAB v5 files at full double precision, each written atomically
// (WriteMatFile, io/mat_file.h).
Status WriteCalibrationMat(const std::string& path, const CalibrationTest& test);
Status WriteRunMat(const std::string& path, const VehicleRun& run);
// Landmark names must be MATLAB identifiers; nothing is written otherwise.
Status WriteLandmarksMat(const std::string& path, const std::vector<Landmark>& landmarks);

}  // namespace accelcal

#endif  // ACCELCAL_IO_COURSE_MAT_H_
