// What discovery's statements claim, against what was done (issue 45).
//
// When the verdict finds the pose means scatter more than the noise model allows, the
// fit description states the sigmas' understatement as sqrt(chi2/dof) of the fit it describes
// (it once quoted another fit's, 2.3 beside a stated chi2/dof of 364), and the poorly determined
// list judges the sigmas so scaled (it once said "none" on sigmas it had just called understated
// by 19x). A simulated session whose poses' offsets wander by 3 counts (ten times a pose mean's
// white sigma).

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "common/format.h"
#include "estimation/triad/triad_determination.h"
#include "reporting/calibrate_imu_report.h"
#include "reporting/triad_discovery_report.h"
#include "simulation/triad_simulator.h"
#include "triad_test_session.h"

namespace accelcal {
namespace {

TEST(DiscoveryStatements, TheFactorIsTheReportedFitsAndThePoorlyDeterminedListUsesIt) {
  TriadSimulationOptions simulation = testing::TriadTestSimulationOptions();
  simulation.pose_wander_stddev = {3.0, 3.0, 3.0};
  RandomSource random(45, 2);
  const std::vector<std::array<double, 3>> directions = RandomPoseDirections(30, &random);
  TriadSessionCalibration session;
  session.discovery_options = testing::TriadTestDiscovery(0.01);
  ASSERT_TRUE(DiscoverTriad(SimulateTriadPoses(simulation, directions, &random),
                            session.discovery_options, &session.discovery)
                  .ok());
  session.ml = session.discovery.baseline;
  session.ml_options = session.discovery_options.fit;
  CalibrateImuReport report;
  report.unit = TriadOutputUnit::kCount;
  TakeSessionCalibration(session, &report);
  ASSERT_EQ(report.discovery.verdict_code, Verdict::kUnexplained) << report.discovery.verdict;
  const double factor = SigmaUnderstatement(report.ml, report.discovery);
  EXPECT_NEAR(factor, std::sqrt(report.ml.chi2_per_dof), 1e-12);
  EXPECT_GT(factor, 3.0);
  const std::string text = FitDescription(report.ml, false, report.discovery);
  EXPECT_NE(text.find(StringPrintf("sqrt(chi2/dof) = %.2g", factor)), std::string::npos) << text;
  // Unscaled, the sigmas pass every threshold; scaled, some do not, and each says why.
  EXPECT_TRUE(PoorlyDeterminedTriadParameters(report.ml, "count").empty());
  ASSERT_FALSE(report.poorly_determined.empty());
  for (const TriadPoorlyDetermined& entry : report.poorly_determined)
    EXPECT_NE(entry.reason.find("sigma scaled by sqrt(chi2/dof)"), std::string::npos);
}

// A 10-pose session leaves 1 degree of freedom: no candidate can be tested, and the verdict
// says so instead of "no candidate effect is needed".
TEST(DiscoveryStatements, ExplainedSaysWhenNoCandidateCouldBeTested) {
  RandomSource random(46, 3);
  const std::vector<std::array<double, 3>> directions = RandomPoseDirections(10, &random);
  TriadDiscoveryResult result;
  ASSERT_TRUE(
      DiscoverTriad(SimulateTriadPoses(testing::TriadTestSimulationOptions(), directions, &random),
                    testing::TriadTestDiscovery(0.01), &result)
          .ok());
  EXPECT_EQ(result.baseline.degrees_of_freedom, 1);
  ASSERT_EQ(result.verdict_code, Verdict::kExplained) << result.verdict;
  EXPECT_TRUE(result.candidates.empty());
  EXPECT_EQ(result.verdict.find("no candidate effect is needed"), std::string::npos)
      << result.verdict;
  EXPECT_NE(result.verdict.find("no candidate effect could be tested"), std::string::npos)
      << result.verdict;
  EXPECT_NE(result.verdict.find("hold the sensor in more poses"), std::string::npos);
}

}  // namespace
}  // namespace accelcal
