// The joint binary as a user runs it: on the course data with the effects the issue
// names, its JSON (linear and joint objects keyed by the spec's names), and its errors.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "test_support.h"

namespace accelcal {
namespace {

using testing::CommandResult;
using testing::RunBinary;
using testing::ScratchDir;

TEST(JointBinary, RunsOnTheCourseDataWithAngleOffsetAndNonOrthogonality) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  ScratchDir out;
  const CommandResult result =
      RunBinary("joint", "--data_dir='" + dir +
                             "' --effects=angle_offset,nonorthogonality --landmark=auto --json='" +
                             out.File("joint.json") + "'");
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  EXPECT_NE(result.stdout_text.find("landmark hypotheses"), std::string::npos)
      << result.stdout_text;
  const nlohmann::json json = nlohmann::json::parse(testing::ReadText(out.File("joint.json")));
  for (const char* side : {"linear", "joint"}) {
    for (const char* name : {"bias_x", "scale_x", "bias_y", "scale_y"}) {
      EXPECT_TRUE(json[side]["parameters"].contains(name)) << side << " " << name;
      EXPECT_GT(json[side]["stddev"][name].get<double>(), 0.0) << side << " " << name;
    }
    EXPECT_TRUE(json[side].contains("covariance"));
    EXPECT_TRUE(json[side]["chi2"].contains("x"));
    EXPECT_TRUE(json[side]["endpoint"].contains("x"));
    EXPECT_EQ(json[side]["landmarks"].size(), 4u);
  }
  EXPECT_TRUE(json["joint"]["parameters"].contains("angle_offset"));
  EXPECT_TRUE(json["joint"]["parameters"].contains("nonorthogonality"));
  EXPECT_EQ(json["joint"]["parameter_order"].size(), 6u);
  EXPECT_EQ(json["joint"]["covariance"].size(), 6u);
  // The data do not support either effect: each within 3 sigma of zero. The run, tied to
  // each landmark in turn, picks C.
  for (const char* effect : {"angle_offset", "nonorthogonality"}) {
    EXPECT_LT(std::abs(json["joint"]["parameters"][effect].get<double>()),
              3 * json["joint"]["stddev"][effect].get<double>())
        << effect;
  }
  EXPECT_EQ(json["tied_landmark"], "C");
  double posterior_c = 0.0;
  for (const auto& hypothesis : json["hypotheses"]) {
    if (hypothesis["name"] == "C") posterior_c = hypothesis["posterior"].get<double>();
  }
  EXPECT_GT(posterior_c, 0.999);
}

TEST(JointBinary, NoEffectsNoLandmarkEqualsTheLinearSolution) {
  ScratchDir out;
  const CommandResult result = RunBinary(
      "joint", "--landmark=none --set=tilt_samples=3001 --json='" + out.File("j.json") + "'");
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  const nlohmann::json json = nlohmann::json::parse(testing::ReadText(out.File("j.json")));
  for (const char* name : {"bias_x", "scale_x", "bias_y", "scale_y"}) {
    const double linear = json["linear"]["parameters"][name].get<double>();
    EXPECT_NEAR(json["joint"]["parameters"][name].get<double>(), linear, 1e-8 * std::abs(linear))
        << name;
    const double sigma = json["linear"]["stddev"][name].get<double>();
    EXPECT_NEAR(json["joint"]["stddev"][name].get<double>(), sigma, 1e-8 * sigma) << name;
  }
}

TEST(JointBinary, RefusesUnknownEffectsUnidentifiableProblemsAndBadLandmarks) {
  auto refused = [](const std::string& arguments, const std::string& fragment) {
    testing::ExpectBadInputContract(RunBinary("joint", arguments), "joint", fragment);
  };
  refused("--effects=angle", "--effects: 'angle' is not an effect the joint model estimates");
  refused("--effects=run_bias_shift_y --landmark=none",
          "not identifiable: run_bias_shift_y is observable only through the run's endpoint");
  refused("--landmark=Z", "--landmark=Z is not one of the landmarks (A, B, C, D)");
  refused("--loss=l1", "--loss must be none, huber or cauchy");
}

}  // namespace
}  // namespace accelcal
