#ifndef ACCELCAL_COMMON_FERRARIS_SESSION_H_
#define ACCELCAL_COMMON_FERRARIS_SESSION_H_

// A Ferraris calibration session as imucal (MaD-Lab, FAU) records it: an IMU held still with
// each sensing axis up and down (six holds), then turned once about each axis (three turns),
// every sample labelled with its section (docs/imucal.md). What the calibration needs of each
// section is its sample count, and the mean and sample variance of its accelerometer and
// gyroscope outputs: the holds' means fix the accelerometer, the turns' sums (N times the
// mean) integrate the gyroscope, the variances weight the least-squares fit. So a section is
// kept as those statistics, never as its rows, whatever the log's length.

#include <array>

#include "common/triad_log.h"

namespace accelcal {

// In imucal's order. "_p": the axis points up (its accelerometer reads +g), "_a": down.
enum FerrarisSection : int { kXp, kXa, kYp, kYa, kZp, kZa, kXRot, kYRot, kZRot };
constexpr int kFerrarisSectionCount = 9;
constexpr int kFerrarisHoldCount = 6;  // the first six sections

// The labels imucal writes in its `part` column.
constexpr std::array<const char*, kFerrarisSectionCount> kFerrarisSectionLabels = {
    "x_p", "x_a", "y_p", "y_a", "z_p", "z_a", "x_rot", "y_rot", "z_rot"};

// The holds of each axis k (0 = x): pointing up, and down.
constexpr FerrarisSection FerrarisHoldUp(int axis) { return FerrarisSection(2 * axis); }
constexpr FerrarisSection FerrarisHoldDown(int axis) { return FerrarisSection(2 * axis + 1); }
constexpr FerrarisSection FerrarisTurn(int axis) { return FerrarisSection(kXRot + axis); }

struct FerrarisSectionData {
  TriadPoseMean accelerometer;  // in the log's unit (counts for imucal's example)
  TriadPoseMean gyroscope;      // same sample count
  long long first_line = 0;     // where the section's rows are, for messages
  long long last_line = 0;
};

struct FerrarisSession {
  std::array<FerrarisSectionData, kFerrarisSectionCount> sections;
  const FerrarisSectionData& operator[](FerrarisSection section) const { return sections[section]; }
};

}  // namespace accelcal

#endif  // ACCELCAL_COMMON_FERRARIS_SESSION_H_
