#ifndef ACCELCAL_TESTS_DISCOVERY_SEED_H_
#define ACCELCAL_TESTS_DISCOVERY_SEED_H_

// Discovery on one simulated seed of a scenario, without cross-validation (the studies of
// discovery at its edges repeat it over many seeds; the folds change no verdict).

#include <gtest/gtest.h>

#include "estimation/tilt_table/discovery.h"
#include "simulation/scenario.h"

namespace accelcal {

inline DiscoveryResult DiscoverSeed(const SimulatedData& data) {
  DiscoveryOptions options;
  options.cross_validation_folds = 0;
  DiscoveryResult result;
  const Status status =
      Discover(data.test, data.run, data.conditions, data.landmarks, options, &result);
  EXPECT_TRUE(status.ok()) << status.message();
  return result;
}

}  // namespace accelcal

#endif  // ACCELCAL_TESTS_DISCOVERY_SEED_H_
