#ifndef ACCELCAL_TESTS_TRIAD_TEST_SESSION_H_
#define ACCELCAL_TESTS_TRIAD_TEST_SESSION_H_

// The simulated static session and the fit's start that the triad's maximum-likelihood tests
// share (triad_ml_calibration_test, triad_identifiability_test): an Xsens-like triad (the study's
// default truth), 100 samples per pose with noise (3, 2.5, 3.5) counts, imu_tk's g; the fit
// started from the datasheet's nominal values (angles 0, 415 counts per m/s^2, offsets 33000).
// And discovery on that session, as its tests run it (triad_discovery_test, triad_shapes_test,
// triad_partners_test): started from the study's guess, without cross-validation (the tests
// repeat it over many sessions; the folds change no verdict).

#include "estimation/triad/triad_discovery.h"
#include "estimation/triad/triad_ml_calibration.h"
#include "models/triad.h"
#include "simulation/triad_simulator.h"
#include "studies/triad_monte_carlo.h"

namespace accelcal {
namespace testing {

constexpr double kTriadTestGravity = 9.81744;

inline TriadSimulationOptions TriadTestSimulationOptions() {
  TriadSimulationOptions options;
  options.truth = XsensLikeTriad();
  options.gravity_mps2 = kTriadTestGravity;
  options.samples_per_pose = 100;
  options.noise_stddev = {3.0, 2.5, 3.5};
  return options;
}

inline TriadMlOptions TriadTestMlOptions() {
  TriadMlOptions options;
  options.gravity_mps2 = kTriadTestGravity;
  options.initial = TriadParametersWithOffset(33000.0, 33000.0, 33000.0);
  for (int k = 0; k < 3; ++k) options.initial[kTriadGainX + k] = 1.0 / 415.0;
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

}  // namespace testing
}  // namespace accelcal

#endif  // ACCELCAL_TESTS_TRIAD_TEST_SESSION_H_
