#ifndef ACCELCAL_IO_COURSE_DATA_H_
#define ACCELCAL_IO_COURSE_DATA_H_

// Loaders for the course's data, read as is (../shared/spec/error-model.md, "The course
// data layout"), and for the equivalent CSV layout:
//
//   quantity        course layout                       CSV layout
//   tilt test       ensayo.mat: tita (Nx1, rad),         calibration.csv: theta,ax,ay
//                   datos (Nx2, m/s^2, x then y)
//   vehicle run     acel.mat: t (Mx1, s), Aerr (Mx2)     trajectory.csv: t,ax,ay
//   landmarks       puntos.mat: one 1x2 [x y] (m) per    landmarks.csv: name,x,y
//                   variable, named by the variable
//   conditions      datos.txt                            scenario.json
//
// This file says which files make a dataset, how they are found and loaded; each layout's
// files are read and written by io/course_mat.h (.mat), io/course_csv.h and
// io/calibration_stream.h (CSV), io/run_conditions.h and io/datos_txt.h (conditions).
//
// The file type is chosen by extension, in any case (.csv, .CSV: CSV; anything else, e.g.
// .mat or .MAT, MAT), so single files of either kind can be named directly. Every loader
// first checks that the path is a regular file (CheckInputFile, io/input_file.h: a folder,
// a pipe such as bash's <(...) or a device is refused by name), then validates what it
// reads (shape, finiteness, lengths, time uniformly increasing, angles that follow the
// outputs' direction) and fails with the file name first.

#include <map>
#include <string>
#include <vector>

#include "common/measurements.h"
#include "common/status.h"

namespace accelcal {

enum class DataLayout { kCourseMat, kCsv };

// Where each input of a data directory is.
struct DataFiles {
  DataLayout layout = DataLayout::kCourseMat;
  std::string calibration;  // ensayo.mat or calibration.csv
  std::string run;          // acel.mat or trajectory.csv
  std::string landmarks;    // puntos.mat or landmarks.csv
  std::string conditions;   // datos.txt or scenario.json
};

// Finds the layout of `data_dir`: the course layout when ensayo.mat is there, the CSV
// layout when calibration.csv is. Files are not opened here.
Status ResolveDataFiles(const std::string& data_dir, DataFiles* files);

// The same, then every non-empty path of `overrides` replaces the folder's file (the
// binaries' --calibration_file, --run_file, ... flags). With an empty `data_dir` the
// files are the overrides alone.
Status ResolveDataFiles(const std::string& data_dir, const DataFiles& overrides, DataFiles* files);

// What the files cannot say about themselves.
// Whatever the unit, a test whose outputs' direction does not follow theta is refused
// (io/theta_agreement.h).
enum class AngleUnit {
  kAuto,    // radians, but a span of theta over two turns, or angles that follow the
            // outputs' direction only when read as degrees, are refused as likely degrees
  kRadian,  // radians, whatever the span
  kDegree,  // degrees, converted to radians on reading
};

// "auto", "rad" or "deg" (the binaries' --theta_unit).
Status ParseAngleUnit(const std::string& text, AngleUnit* unit);

struct LoadOptions {
  AngleUnit theta_unit = AngleUnit::kAuto;
};

// What kAuto refuses in a test's angles, from their extremes (for readers that see the
// angles once, in a stream): a span of more than two turns, as likely degrees. Other units
// pass.
Status CheckThetaSpan(AngleUnit unit, double theta_min, double theta_max, long long sample_count);

// Whether the loaders read `path` as CSV (it ends in ".csv" in any case); anything else is
// read as .mat.
bool IsCsvPath(const std::string& path);

// The time step of a run, in s: 1 Hz to 100 kHz (CheckUniformTime and the scenarios).
constexpr double kMinRunStepS = 1e-5;
constexpr double kMaxRunStepS = 1.0;

// Whether the timestamps `timestamp_s` are strictly increasing and uniformly spaced, as the
// integration's single dt needs; `name` is the variable's name in messages ("t"). A step may
// differ from the median step by 1e-6 of it plus 4 ulp of the largest |t|, the resolution of
// the timestamps themselves: at Unix times (t ~ 1.7e9 s, ulp 2.4e-7 s) the steps of an exact
// 100 Hz clock differ by up to an ulp, far more than 1e-6 dt = 1e-8 s. Timestamps too coarse
// to resolve the step (4 ulp >= dt / 2) are refused. The integration takes
// dt = (t_last - t_first) / (N - 1), accurate to an ulp of t over N - 1.
Status CheckUniformTime(const std::vector<double>& timestamp_s, const std::string& name);
// What any log's time must be, uniform or not: at least 2 samples, strictly increasing, its
// median step (`median_step_s`) within [kMinRunStepS, kMaxRunStepS] (a time in milliseconds
// is refused as such). CheckUniformTime applies it first.
Status CheckLogTime(const std::vector<double>& timestamp_s, const std::string& name,
                    double* median_step_s);

// Each loader refuses what it cannot read correctly. What it reads correctly but a person
// should hear about (a 2xN matrix read as its transpose) goes to `notes`, one line each
// starting with the file name, when `notes` is not null.
Status LoadCalibrationTest(const std::string& path, CalibrationTest* test,
                           const LoadOptions& options = {},
                           std::vector<std::string>* notes = nullptr);
Status LoadVehicleRun(const std::string& path, VehicleRun* run,
                      std::vector<std::string>* notes = nullptr);
// A log of measured accelerations in the run's layout (t,ax,ay CSV or t and Aerr in .mat)
// to be corrected, not integrated: its time must pass CheckLogTime, not be uniform.
Status LoadMeasuredLog(const std::string& path, VehicleRun* run,
                       std::vector<std::string>* notes = nullptr);
// At least one landmark, unique names, no two at one place (common/landmark_checks.h).
Status LoadLandmarks(const std::string& path, std::vector<Landmark>* landmarks);

// Everything a data folder holds, read from resolved files.
struct CourseData {
  CalibrationTest test;
  VehicleRun run;
  std::vector<Landmark> landmarks;
  RunConditions conditions;
  std::vector<std::string> notes;  // the loaders' notes, to be shown to the user
};

// The files by role ("calibration", "run", "landmarks", "conditions"), as outputs name them.
std::map<std::string, std::string> FileRoles(const DataFiles& files);

// Reads the four files of `files` (each with its own checks and messages); without a
// calibration path (a calibration file stands in for the tilt test) the test stays empty.
Status LoadDataFiles(const DataFiles& files, CourseData* data, const LoadOptions& options = {});

// Writes the four files of a layout into the existing folder `dir`, each atomically and
// at full double precision: ensayo.mat, acel.mat, puntos.mat (landmark names must be
// MATLAB identifiers) and datos.txt; or calibration.csv, trajectory.csv, landmarks.csv
// and scenario.json. Returns the paths written.
Status WriteDataDirectory(const std::string& dir, DataLayout layout, const CalibrationTest& test,
                          const VehicleRun& run, const std::vector<Landmark>& landmarks,
                          const RunConditions& conditions, std::vector<std::string>* written);

}  // namespace accelcal

#endif  // ACCELCAL_IO_COURSE_DATA_H_
