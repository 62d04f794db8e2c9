// The gyroscope's poorly determined unknowns (estimation/gyroscope/gyroscope_determination.h,
// issue 44, item 6), on simulated sessions (studies/gyroscope_monte_carlo.h): a session whose
// turns go almost all about the sensor's x axis names the unknowns that turns about y and z
// determine, each with its axis and the share the session turned about it, and none that turns
// about x determine; well-spread sessions name none; and the rule is the accelerometer's
// (estimation/statistics/parameter_determination.h).

#include "estimation/gyroscope/gyroscope_determination.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "common/format.h"
#include "gyroscope_one_axis_session.h"
#include "models/gyroscope.h"
#include "studies/gyroscope_monte_carlo.h"

namespace accelcal {
namespace {

using testing::MostlyAboutXHolds;
using testing::NoisyGyroscopeDesign;

std::set<std::string> Named(const std::vector<PoorlyDeterminedParameter>& list) {
  std::set<std::string> names;
  for (const PoorlyDeterminedParameter& entry : list) names.insert(entry.parameter);
  return names;
}

// Turns about x (85% of the session's turning) determine gain_x and the x column (xz, xy) to
// 1e-4 of the gain and 0.2 mrad; the y and z columns get 7% and 8% and sigmas of 1.3 mrad:
// misalignment_yz and _yx (y), _zy and _zx (z) are named, each with its axis and share; the
// gains y and z reach 6.6e-4 of the gain, within the threshold, and are not named.
TEST(GyroscopeDetermination, TurnsAboutOneAxisNameTheOtherAxesUnknownsWithTheirAxis) {
  const GyroscopeSessionDesign design = NoisyGyroscopeDesign();
  GyroscopeSessionFit fit;
  const Status status =
      SimulateAndCalibrateGyroscope(design, MostlyAboutXHolds(design.hold_s), 3, {}, &fit);
  ASSERT_TRUE(status.ok()) << status.message();
  const GyroscopeMlResult& g = fit.gyroscope;
  const std::array<double, 3> shares = GyroscopeTurnShares(g);
  EXPECT_GT(shares[0], 0.8);
  EXPECT_LT(shares[1], 0.1);
  EXPECT_LT(shares[2], 0.1);
  const std::vector<PoorlyDeterminedParameter> list =
      PoorlyDeterminedGyroscopeParameters(g, "count");
  const std::set<std::string> expected = {"gyroscope_misalignment_yz", "gyroscope_misalignment_zy",
                                          "gyroscope_misalignment_zx", "gyroscope_misalignment_yx"};
  EXPECT_EQ(Named(list), expected) << PoorlyDeterminedNames(list);
  for (const PoorlyDeterminedParameter& entry : list) {
    const std::string axis = GyroscopeTurnAxisOf(entry.index, {});
    ASSERT_FALSE(axis.empty()) << entry.parameter;
    EXPECT_NE(entry.suggestion.find("turns about the sensor's " + axis + " axis"),
              std::string::npos)
        << entry.parameter << ": " << entry.suggestion;
    const int k = axis[0] - 'x';
    EXPECT_NE(entry.suggestion.find(
                  StringPrintf("went %.0f%% about %s", 100.0 * shares[k], axis.c_str())),
              std::string::npos)
        << entry.suggestion;
    EXPECT_TRUE(entry.sigma_over_threshold) << entry.parameter;
    EXPECT_DOUBLE_EQ(entry.threshold, DeterminationThresholds().angle_sigma_rad);
    EXPECT_NE(entry.reason.find("sigma"), std::string::npos) << entry.reason;
  }
  // Nothing that turns about x determine is named.
  for (const PoorlyDeterminedParameter& entry : list)
    EXPECT_STRNE(GyroscopeTurnAxisOf(entry.index, {}), "x") << entry.parameter;
}

// The same gyroscope in well-spread sessions (the default design's poses and yaws, drawn afresh
// for each session): 100 sessions name nothing (measured: 0 of 100; and 0 of 100 at the design's
// own 3 counts). The one-axis session's flags come from its turns, not from the noise.
TEST(GyroscopeDetermination, WellSpreadSessionsNameNone) {
  for (const bool noisy : {true, false}) {
    GyroscopeSessionDesign design = noisy ? NoisyGyroscopeDesign() : GyroscopeSessionDesign();
    int flagged = 0;
    std::string first;
    for (int session = 0; session < 100; ++session) {
      GyroscopeSessionFit fit;
      const Status status = SimulateAndCalibrateGyroscope(
          design, GyroscopeDesignHolds(design, 100 + session), 1000 + session, {}, &fit);
      ASSERT_TRUE(status.ok()) << status.message();
      const std::vector<PoorlyDeterminedParameter> list =
          PoorlyDeterminedGyroscopeParameters(fit.gyroscope, "count");
      if (list.empty()) continue;
      ++flagged;
      if (first.empty()) first = StringPrintf("session %d: ", session) + list.front().reason;
    }
    EXPECT_EQ(flagged, 0) << (noisy ? "27 counts: " : "3 counts: ") << first;
  }
}

// The gyroscope's list and the accelerometer's are one rule: a parameter whose |correlation|
// with another exceeds 0.99 is named for it, whatever its sigma; and a sigma beyond the
// threshold is named with both numbers.
TEST(ParameterDetermination, NamesASigmaBeyondItsThresholdAndAConfoundedPair) {
  Eigen::MatrixXd covariance(3, 3);
  covariance << 1e-8, 0.995e-8, 0.0,  //
      0.995e-8, 1e-8, 0.0,            //
      0.0, 0.0, 4e-6;
  const std::vector<std::string> names = {"a", "b", "c"};
  PoorlyDeterminedParameter entry;
  ASSERT_TRUE(JudgeParameterDetermination(0, names, covariance, 1e-3, "1e-3 rad", 0.99, &entry));
  EXPECT_FALSE(entry.sigma_over_threshold);
  ASSERT_EQ(entry.correlated_with.size(), 1u);
  EXPECT_EQ(entry.correlated_with[0].parameter, "b");
  EXPECT_NEAR(entry.correlated_with[0].correlation, 0.995, 1e-12);
  ASSERT_TRUE(JudgeParameterDetermination(2, names, covariance, 1e-3, "1e-3 rad", 0.99, &entry));
  EXPECT_TRUE(entry.sigma_over_threshold);
  EXPECT_EQ(entry.reason, "sigma 0.002 > 0.001 (1e-3 rad)");
  covariance(0, 1) = covariance(1, 0) = 0.5e-8;
  EXPECT_FALSE(JudgeParameterDetermination(0, names, covariance, 1e-3, "1e-3 rad", 0.99, &entry));
}

}  // namespace
}  // namespace accelcal
