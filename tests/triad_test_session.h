#ifndef ACCELCAL_TESTS_TRIAD_TEST_SESSION_H_
#define ACCELCAL_TESTS_TRIAD_TEST_SESSION_H_

// The simulated triad session the discovery tests share: the Xsens-like truth, 100 samples a
// pose of (3, 2.5, 3.5) counts of white noise, a pose every 10 s; and discovery on it at `alpha`
// without cross-validation (the studies repeat it over many sessions; the folds change no
// verdict).

#include "estimation/triad/triad_discovery.h"
#include "simulation/triad_simulator.h"
#include "studies/triad_monte_carlo.h"

namespace accelcal {

constexpr double kTriadTestGravity = 9.81744;

inline TriadSimulationOptions TriadTestSession() {
  TriadSimulationOptions options;
  options.truth = XsensLikeTriad();
  options.gravity_mps2 = kTriadTestGravity;
  options.samples_per_pose = 100;
  options.noise_stddev = {3.0, 2.5, 3.5};
  options.pose_spacing_s = 10.0;
  return options;
}

inline TriadDiscoveryOptions TriadTestDiscovery(double alpha) {
  TriadDiscoveryOptions options;
  options.alpha = alpha;
  options.fit.gravity_mps2 = kTriadTestGravity;
  options.fit.initial = TriadStudyInitialGuess(XsensLikeTriad());
  options.cross_validation_folds = 0;
  return options;
}

}  // namespace accelcal

#endif  // ACCELCAL_TESTS_TRIAD_TEST_SESSION_H_
