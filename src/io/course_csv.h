#ifndef ACCELCAL_IO_COURSE_CSV_H_
#define ACCELCAL_IO_COURSE_CSV_H_

// The CSV layout's files, read and written (the layout io/course_data.h sets beside the
// course's .mat files):
//
//   calibration.csv   theta,ax,ay   (read by the streaming reader, io/calibration_stream.h)
//   trajectory.csv    t,ax,ay
//   landmarks.csv     name,x,y
//
// Parsed by the strict reader of io/csv_reader.h; the readers here check only what is
// particular to a file (a landmark's name) and carry no file name: io/course_data.h's loaders
// add the checks that do not depend on the layout and the name. Writers write every number at
// full double precision, atomically.

#include <string>
#include <vector>

#include "common/measurements.h"
#include "common/status.h"

namespace accelcal {

// The times are read, not checked (CheckUniformTime, io/course_data.h).
Status LoadRunCsv(const std::string& path, VehicleRun* run);
// Each name a printable UTF-8 line of at most 100 bytes; the landmarks themselves are not
// checked (CheckLandmarks, common/landmark_checks.h).
Status LoadLandmarksCsv(const std::string& path, std::vector<Landmark>* landmarks);

Status WriteCalibrationCsv(const std::string& path, const CalibrationTest& test);
Status WriteRunCsv(const std::string& path, const VehicleRun& run);
Status WriteLandmarksCsv(const std::string& path, const std::vector<Landmark>& landmarks);

}  // namespace accelcal

#endif  // ACCELCAL_IO_COURSE_CSV_H_
