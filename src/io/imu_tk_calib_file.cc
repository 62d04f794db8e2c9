#include "io/imu_tk_calib_file.h"

#include <Eigen/Core>
#include <sstream>

#include "common/format.h"
#include "common/line_text.h"

namespace accelcal {

ImuTkCalibratedTriad ImuTkAccelerometerTriad(const TriadParameters& parameters) {
  // imu_tk's acc_calib_: the gyroscope's general matrix with the three lower angles 0.
  GyroscopeParameters general{};
  general[kGyroscopeMisalignmentYz] = parameters[kTriadMisalignmentYz];
  general[kGyroscopeMisalignmentZy] = parameters[kTriadMisalignmentZy];
  general[kGyroscopeMisalignmentZx] = parameters[kTriadMisalignmentZx];
  ImuTkCalibratedTriad triad;
  GyroscopeMisalignmentMatrix(general.data(), triad.misalignment.data());
  for (int k = 0; k < 3; ++k) {
    triad.scale[k] = parameters[kTriadGainX + k];
    triad.bias[k] = parameters[kTriadOffsetX + k];
  }
  return triad;
}

ImuTkCalibratedTriad ImuTkGyroscopeTriad(const GyroscopeParameters& parameters,
                                         const GyroscopeOffset& offset) {
  ImuTkCalibratedTriad triad;
  GyroscopeMisalignmentMatrix(parameters.data(), triad.misalignment.data());
  for (int k = 0; k < 3; ++k) {
    triad.scale[k] = parameters[kGyroscopeGainX + k];
    triad.bias[k] = offset[k];
  }
  return triad;
}

std::array<std::string, 3> ImuTkTriadMatrices(const ImuTkCalibratedTriad& triad) {
  const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> misalignment(
      triad.misalignment.data());
  Eigen::Matrix3d scale = Eigen::Matrix3d::Zero();
  for (int k = 0; k < 3; ++k) scale(k, k) = triad.scale[k];
  const Eigen::Map<const Eigen::Vector3d> bias(triad.bias.data());
  std::array<std::ostringstream, 3> text;  // default precision, as imu_tk's streams
  text[0] << misalignment;
  text[1] << scale;
  text[2] << bias;
  return {text[0].str(), text[1].str(), text[2].str()};
}

std::string ImuTkCalibText(const ImuTkCalibratedTriad& triad) {
  // imu_tk: file << mis_mat_ << endl << endl << scale_mat_ << endl << endl << bias_vec_ << endl
  // << endl.
  const std::array<std::string, 3> matrices = ImuTkTriadMatrices(triad);
  return matrices[0] + "\n\n" + matrices[1] + "\n\n" + matrices[2] + "\n\n";
}

std::string ImuTkCalibTextFullPrecision(const ImuTkCalibratedTriad& triad,
                                        const std::vector<std::string>& trailing_comments) {
  std::string text;
  for (int row = 0; row < 3; ++row) {
    text += StringPrintf("%.17g %.17g %.17g\n", triad.misalignment[3 * row],
                         triad.misalignment[3 * row + 1], triad.misalignment[3 * row + 2]);
  }
  text += "\n";
  for (int row = 0; row < 3; ++row) {
    double entries[3] = {0.0, 0.0, 0.0};
    entries[row] = triad.scale[row];
    text += StringPrintf("%.17g %.17g %.17g\n", entries[0], entries[1], entries[2]);
  }
  text += "\n";
  for (int row = 0; row < 3; ++row) text += StringPrintf("%.17g\n", triad.bias[row]);
  text += "\n";
  for (const std::string& comment : trailing_comments)
    text += "# " + EscapeForLine(comment) + "\n";  // one line each (common/line_text.h)
  return text;
}

}  // namespace accelcal
