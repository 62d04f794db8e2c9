#ifndef ACCELCAL_IO_IMU_TK_CALIB_FILE_H_
#define ACCELCAL_IO_IMU_TK_CALIB_FILE_H_

// imu_tk's calibration file, the text its CalibratedTriad_::save writes and its load reads
// (imu_tk's include/imu_tk/calibration.h), for an accelerometer or a gyroscope:
//
//   the misalignment matrix T (3 x 3, one row per line), an empty line,
//   the scale matrix K (3 x 3, the gains on its diagonal), an empty line,
//   the bias vector b (3 x 1, one entry per line), an empty line,
//
// each matrix as Eigen's operator<< prints it on a stream of default precision (6 significant
// digits, every entry right-aligned to the width of the matrix's widest), so that the file is the
// one imu_tk writes for the same parameters. load reads the 21 numbers in that order with >>,
// whatever the spacing. The calibrated reading is T K (u - b) (models/triad.h,
// models/gyroscope.h: the same model, in imu_tk's convention).
//
// imu_tk's example writes test_imu_acc.calib and test_imu_gyro.calib; calibrate_imu
// --imu_tk_calib_out=PREFIX writes PREFIX_acc.calib and PREFIX_gyro.calib.

#include <array>
#include <string>
#include <vector>

#include "models/gyroscope.h"
#include "models/triad.h"

namespace accelcal {

struct ImuTkCalibratedTriad {
  std::array<double, 9> misalignment{};  // T, row-major
  std::array<double, 3> scale{};         // the diagonal of K
  std::array<double, 3> bias{};          // b, in the output's unit
};

// The accelerometer's, as imu_tk builds it from its 9 parameters: CalibratedTriad_(yz, zy, zx,
// 0, 0, 0, gains, offsets), so T's lower triangle holds -0 at (2, 0), as imu_tk prints it.
ImuTkCalibratedTriad ImuTkAccelerometerTriad(const TriadParameters& parameters);
// The gyroscope's: the 9 parameters and the offset (not estimated: the initial rest's mean).
ImuTkCalibratedTriad ImuTkGyroscopeTriad(const GyroscopeParameters& parameters,
                                         const GyroscopeOffset& offset);

// The misalignment matrix, the scale matrix and the bias vector, each as Eigen's operator<<
// prints it at the default precision (no final newline): what imu_tk's save writes and what its
// operator<< of a CalibratedTriad prints under "Misalignment Matrix", "Scale Matrix" and "Bias
// Vector".
std::array<std::string, 3> ImuTkTriadMatrices(const ImuTkCalibratedTriad& triad);

// The file's text, byte for byte what imu_tk's save writes.
std::string ImuTkCalibText(const ImuTkCalibratedTriad& triad);

// The same layout with every number at full precision (17 significant digits, so that the
// numbers read back are the doubles written: save's 6 digits move a corrected value by up to
// 1e-6 relative), one matrix row per line, the entries separated by one blank; then, after the
// final empty line, `trailing_comments`, each on a line of its own starting with "# ". imu_tk's
// load reads the first 21 numbers with >> and stops, so the lines after them are never read:
// what calibration_export --format=imu_tk writes (docs/calibration.md, "Exports").
std::string ImuTkCalibTextFullPrecision(const ImuTkCalibratedTriad& triad,
                                        const std::vector<std::string>& trailing_comments);

}  // namespace accelcal

#endif  // ACCELCAL_IO_IMU_TK_CALIB_FILE_H_
