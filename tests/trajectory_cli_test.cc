// The trajectory binary as a user runs it: the decision and figures on the course data,
// the JSON and path CSV it writes, and the bad-input contract for the run, landmarks
// and initial conditions (one line on stderr naming the file, exit 2, nothing written).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <vector>

#include "io/course_csv.h"
#include "io/course_data.h"
#include "io/mat_file.h"
#include "simulation/simulator.h"
#include "test_support.h"

namespace accelcal {
namespace {

using testing::CommandResult;
using testing::RunCommand;
using testing::ScratchDir;

CommandResult RunTrajectory(const std::string& arguments) {
  return testing::RunBinary("trajectory", arguments);
}

// A CSV-layout folder with a simulated test, a 200-sample run and two landmarks.
void MakeCsvDataDir(const ScratchDir& scratch) {
  TiltSchedule design;
  design.sample_count = 500;
  ASSERT_TRUE(WriteCalibrationCsv(scratch.File("calibration.csv"),
                                  SimulateTiltTest(design, CourseTableOneTruth(), 1))
                  .ok());
  std::string run = "t,ax,ay\n";
  for (int j = 0; j < 200; ++j) run += std::to_string(0.01 * j) + ",0.1,-0.2\n";
  scratch.Write("trajectory.csv", run);
  scratch.Write("landmarks.csv", "name,x,y\nA,2,6\nB,40,-3\n");
  scratch.Write("scenario.json",
                "{\"initial_position\": [0, 0], \"initial_velocity\": [1, 3], \"noise_variance\": "
                "[0.25, 0.64]}");
}

void ExpectRefused(const std::string& arguments, const std::string& fragment) {
  ScratchDir out;
  testing::ExpectBadInputContract(RunTrajectory(arguments + " --json='" + out.File("t.json") +
                                                "' --path_csv='" + out.File("path.csv") + "'"),
                                  "trajectory", fragment);
  EXPECT_EQ(RunCommand("ls -A '" + out.path() + "'").stdout_text, "") << "partial output left";
}

TEST(TrajectoryBinary, DecidesCOnTheCourseDataAndWritesJsonAndPath) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  ScratchDir out;
  const CommandResult result =
      RunTrajectory("--data_dir='" + dir + "' --json='" + out.File("t.json") + "' --path_csv='" +
                    out.File("path.csv") + "'");
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  EXPECT_NE(result.stdout_text.find("verdict: the vehicle reached C"), std::string::npos)
      << result.stdout_text;
  EXPECT_NE(result.stdout_text.find("corrected         468.685     42.140"), std::string::npos);
  EXPECT_NE(result.stdout_text.find("is 27.7 times too small"), std::string::npos);

  const nlohmann::json json = nlohmann::json::parse(testing::ReadText(out.File("t.json")));
  EXPECT_EQ(json["reached"], "C");
  EXPECT_NEAR(json["endpoint"]["x"].get<double>(), 468.685, 1e-3);
  EXPECT_NEAR(json["endpoint"]["y"].get<double>(), 42.140, 1e-3);
  EXPECT_NEAR(json["raw_endpoint"]["x"].get<double>(), 594.315, 1e-3);
  EXPECT_NEAR(json["p_value"].get<double>(), 0.634, 1e-3);
  const auto& total = json["endpoint_covariance"];
  const auto& parameter = json["parameter_part"];
  const auto& noise = json["noise_part"];
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 2; ++j) {
      EXPECT_NEAR(total[i][j].get<double>(),
                  parameter[i][j].get<double>() + noise[i][j].get<double>(), 1e-9);
    }
  }
  ASSERT_EQ(json["landmarks"].size(), 4u);
  double posterior_sum = 0.0;
  for (const auto& landmark : json["landmarks"])
    posterior_sum += landmark["posterior"].get<double>();
  EXPECT_NEAR(posterior_sum, 1.0, 1e-12);
  EXPECT_EQ(json["landmarks"][2]["name"], "C");
  EXPECT_NEAR(json["landmarks"][2]["mahalanobis2"].get<double>(), 0.910, 1e-3);

  // The pinned figures above are the README's; here each is recomputed from the data in the
  // test: the fit by plain normal equations, the endpoints by a plain trapezoidal loop over
  // (m - b) / (1 + s), the covariance from the derivatives of the corrected accelerations and
  // the endpoint's impulse responses (sum w_j^2 sigma^2 / (1 + s)^2), C's distance from those.
  DataFiles files;
  ASSERT_TRUE(ResolveDataFiles(dir, &files).ok());
  CourseData course;
  ASSERT_TRUE(LoadDataFiles(files, &course).ok());
  const double dt = course.run.timestamp_s[1] - course.run.timestamp_s[0];
  const int samples = course.run.size();
  const double v0[2] = {course.conditions.initial_velocity_x_mps,
                        course.conditions.initial_velocity_y_mps};
  const double p0[2] = {course.conditions.initial_position_x_m,
                        course.conditions.initial_position_y_m};
  const double variance[2] = {course.conditions.noise_variance_x,
                              course.conditions.noise_variance_y};
  const std::vector<double>* measured[2] = {&course.run.measured_x, &course.run.measured_y};
  double endpoint[2];
  double raw_endpoint[2];
  double total_variance[2];
  double noise_variance_part[2];
  for (int axis = 0; axis < 2; ++axis) {
    const testing::PlainAxisFit fit = testing::PlainBaselineFit(course.test, axis, variance[axis]);
    const double one_plus_s = 1 + fit.scale;
    std::vector<double> corrected(samples);
    std::vector<double> d_bias(samples, -1.0 / one_plus_s);
    std::vector<double> d_scale(samples);
    for (int j = 0; j < samples; ++j) {
      corrected[j] = ((*measured[axis])[j] - fit.bias) / one_plus_s;
      d_scale[j] = -corrected[j] / one_plus_s;
    }
    endpoint[axis] = p0[axis] + testing::PlainTrapezoidEndpoint(corrected, dt, v0[axis]);
    raw_endpoint[axis] = p0[axis] + testing::PlainTrapezoidEndpoint(*measured[axis], dt, v0[axis]);
    const double jb = testing::PlainTrapezoidEndpoint(d_bias, dt, 0.0);
    const double js = testing::PlainTrapezoidEndpoint(d_scale, dt, 0.0);
    const double parameter_part =
        jb * jb * fit.var_bias + 2 * jb * js * fit.cov_bias_scale + js * js * fit.var_scale;
    double sum_w2 = 0.0;
    std::vector<double> impulse(samples, 0.0);
    for (int j = 0; j < samples; ++j) {
      impulse[j] = 1.0;
      const double w = testing::PlainTrapezoidEndpoint(impulse, dt, 0.0);
      impulse[j] = 0.0;
      sum_w2 += w * w;
    }
    noise_variance_part[axis] = sum_w2 * variance[axis] / (one_plus_s * one_plus_s);
    total_variance[axis] = parameter_part + noise_variance_part[axis];
  }
  EXPECT_NEAR(json["endpoint"]["x"].get<double>(), endpoint[0], 1e-6);
  EXPECT_NEAR(json["endpoint"]["y"].get<double>(), endpoint[1], 1e-6);
  EXPECT_NEAR(json["raw_endpoint"]["x"].get<double>(), raw_endpoint[0], 1e-6);
  EXPECT_NEAR(json["raw_endpoint"]["y"].get<double>(), raw_endpoint[1], 1e-6);
  EXPECT_NEAR(total[0][0].get<double>(), total_variance[0], 1e-9 * total_variance[0]);
  EXPECT_NEAR(total[1][1].get<double>(), total_variance[1], 1e-9 * total_variance[1]);
  // x's endpoint depends on x's parameters only, y's on y's, and the fit's x-y covariance is
  // zero: the cross term vanishes (to 1e-3 m^2 of 234 and 553).
  EXPECT_NEAR(total[0][1].get<double>(), 0.0, 1e-3);
  const double dx = course.landmarks[2].x_m - endpoint[0];
  const double dy = course.landmarks[2].y_m - endpoint[1];
  const double c_distance2 = dx * dx / total_variance[0] + dy * dy / total_variance[1];
  EXPECT_NEAR(json["landmarks"][2]["mahalanobis2"].get<double>(), c_distance2, 1e-4 * c_distance2);
  EXPECT_NEAR(json["p_value"].get<double>(), std::exp(-c_distance2 / 2), 1e-4);  // chi^2, 2 dof
  char line[96];
  std::snprintf(line, sizeof(line), "corrected      %10.3f %10.3f   %.2f, %.2f", endpoint[0],
                endpoint[1], std::sqrt(total_variance[0]), std::sqrt(total_variance[1]));
  EXPECT_NE(result.stdout_text.find(line), std::string::npos) << "expected: " << line;
  std::snprintf(line, sizeof(line), "raw            %10.3f %10.3f", raw_endpoint[0],
                raw_endpoint[1]);
  EXPECT_NE(result.stdout_text.find(line), std::string::npos) << "expected: " << line;
  // The report's noise term is 3 sigma of one sample; the run's is 3 sqrt(noise part).
  std::snprintf(line, sizeof(line), "is %.1f times too small",
                std::sqrt(noise_variance_part[0] / variance[0]));
  EXPECT_NE(result.stdout_text.find(line), std::string::npos) << "expected: " << line;

  const std::string path = testing::ReadText(out.File("path.csv"));
  EXPECT_EQ(path.rfind("t_s,x_m,y_m,raw_x_m,raw_y_m,cov_xx", 0), 0u);
  EXPECT_EQ(testing::CountLines(path), 1 + 600 + 1);  // header, samples 0, 10, ..., 5990, and 5999
}

TEST(TrajectoryBinary, RunsOnTheCsvLayout) {
  ScratchDir scratch;
  MakeCsvDataDir(scratch);
  const CommandResult result = RunTrajectory("--data_dir='" + scratch.path() + "'");
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  EXPECT_NE(result.stdout_text.find("verdict:"), std::string::npos);
}

TEST(TrajectoryBinary, RefusesARunWhoseTimeIsNotUniformlyIncreasing) {
  ScratchDir scratch;
  MakeCsvDataDir(scratch);
  const std::string run = scratch.File("trajectory.csv");
  scratch.Write("trajectory.csv", "t,ax,ay\n0,1,1\n0.01,1,1\n0.03,1,1\n0.04,1,1\n0.05,1,1\n");
  ExpectRefused("--data_dir='" + scratch.path() + "'",
                run + ": t is not uniformly spaced: t(3) - t(2) = 0.02 s");
  scratch.Write("trajectory.csv", "t,ax,ay\n0,1,1\n0.01,1,1\n0.005,1,1\n");
  ExpectRefused("--data_dir='" + scratch.path() + "'",
                run + ": t is not strictly increasing: t(3) = 0.005 s");
  scratch.Write("trajectory.csv", "t,ax,ay\n0,1,1\n");
  ExpectRefused("--data_dir='" + scratch.path() + "'",
                run + ": the run has 1 sample(s); at least 2 are needed");
}

TEST(TrajectoryBinary, RefusesAMatRunWithBadTime) {
  ScratchDir scratch;
  MakeCsvDataDir(scratch);
  const std::string acel = scratch.File("acel.mat");
  ASSERT_TRUE(WriteMatFile(acel, {{"t", MatMatrix{4, 1, {0, 0.01, 0.01, 0.03}}},
                                  {"Aerr", MatMatrix{4, 2, std::vector<double>(8, 0.0)}}})
                  .ok());
  ExpectRefused("--data_dir='" + scratch.path() + "' --run_file='" + acel + "'",
                acel + ": t is not strictly increasing: t(3) = 0.01 s after 0.01 s");
}

TEST(TrajectoryBinary, RefusesMissingInitialVelocityAndBadLandmarks) {
  ScratchDir scratch;
  MakeCsvDataDir(scratch);
  scratch.Write("scenario.json",
                "{\"initial_position\": [0, 0], \"noise_variance\": [0.25, 0.64]}");
  ExpectRefused("--data_dir='" + scratch.path() + "'",
                scratch.File("scenario.json") + ": missing \"initial_velocity\"");
  MakeCsvDataDir(scratch);
  scratch.Write("landmarks.csv", "name,x,y\nA,2,6\nA,40,-3\n");
  ExpectRefused("--data_dir='" + scratch.path() + "'",
                scratch.File("landmarks.csv") + ": landmark 'A' is listed twice");
  scratch.Write("landmarks.csv", "name,x,y\n");
  ExpectRefused("--data_dir='" + scratch.path() + "'",
                scratch.File("landmarks.csv") + ": no data rows after the header");
  std::remove(scratch.File("landmarks.csv").c_str());
  ExpectRefused("--data_dir='" + scratch.path() + "'",
                scratch.File("landmarks.csv") + ": no such file; check the path");
}

TEST(TrajectoryBinary, RefusesBadFlags) {
  ExpectRefused("", "give --data_dir, or all of --calibration_file");
  ExpectRefused("--data_dir=. --landmark_alpha=1.5",
                "--landmark_alpha='1.5' is not a valid double in (0, 1)");
  ExpectRefused("--data_dir=. --alpha=0.05", "--alpha was renamed --landmark_alpha");
  ExpectRefused("--data_dir=. --path_stride=0",
                "--path_stride='0' is not a valid int32 in [1, 1000000000]");
}

}  // namespace
}  // namespace accelcal
