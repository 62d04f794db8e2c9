#ifndef ACCELCAL_TESTS_GYROSCOPE_ONE_AXIS_SESSION_H_
#define ACCELCAL_TESTS_GYROSCOPE_ONE_AXIS_SESSION_H_

// A simulated session whose turns go almost all about the sensor's x axis, with poses spread
// enough for the accelerometer (issue 44, item 6), for the tests of the gyroscope's poorly
// determined unknowns (gyroscope_determination_test.cc, gyroscope_cli_test.cc).

#include <array>
#include <cmath>
#include <vector>

#include "simulation/triad_log_simulator.h"
#include "studies/gyroscope_monte_carlo.h"

namespace accelcal {
namespace testing {

inline std::array<double, 3> Unit(double x, double y, double z) {
  const double norm = std::sqrt(x * x + y * y + z * z);
  return {x / norm, y / norm, z / norm};
}

// A session whose consecutive poses differ by rotations about the sensor's x axis: gravity on the
// great circle normal to x, 133 degrees further each time, but for two excursions out of it that
// the accelerometer needs (its x axis must see g at two levels on each side for its gain and
// offset, and gravity between x and y, x and z for the angles coupling x): from gravity along
// +y, tilted 45 degrees towards +x twice (about z), then 45 degrees towards +z twice (about y),
// back on the circle; later the same on the -x side. Those 8 turns of 45 degrees are all the
// session turns about y and z: 7% and 8% of its turning, x 85% (measured, with 3 s turns).
inline std::vector<TriadHold> MostlyAboutXHolds(double hold_s, int poses = 30) {
  std::vector<std::array<double, 3>> directions;
  for (int p = 0; static_cast<int>(directions.size()) < poses; ++p) {
    if (p == 8 || p == 16) {
      const double sign = p == 8 ? 1.0 : -1.0;
      directions.push_back(Unit(0.0, sign, 0.0));
      directions.push_back(Unit(sign, sign, 0.0));
      directions.push_back(Unit(sign, 0.0, 0.0));
      directions.push_back(Unit(sign, 0.0, sign));
      directions.push_back(Unit(0.0, 0.0, sign));
      continue;
    }
    const double angle = 2.0 * M_PI * 0.37 * p;
    directions.push_back(Unit(0.0, std::cos(angle), std::sin(angle)));
  }
  std::vector<TriadHold> holds;
  for (const auto& direction : directions) holds.push_back({direction, hold_s});
  return holds;
}

// Xsens's gyroscope white noise (27 counts per sample, docs/gyroscope.md) on the Xsens-like
// unit, turned by hand in 3 s turns.
inline GyroscopeSessionDesign NoisyGyroscopeDesign() {
  GyroscopeSessionDesign design;
  design.gyroscope_noise = {27.0, 27.0, 27.0};
  design.turn_s = 3.0;
  return design;
}

}  // namespace testing
}  // namespace accelcal

#endif  // ACCELCAL_TESTS_GYROSCOPE_ONE_AXIS_SESSION_H_
