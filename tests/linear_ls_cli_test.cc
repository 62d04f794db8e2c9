// The linear_ls binary as a user runs it: real output on the course data, JSON with the
// documented fields, and for every kind of bad input one line on stderr naming the file
// (or flag), exit status 2, and no output file.

#include <gtest/gtest.h>
#include <matio.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

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

constexpr char kDatos[] =
    "Posici\xC3\xB3n inicial = [0 0]\nVelocidad inicial = [1 3]\n"
    "varianza del ruido de los aceler\xC3\xB3metros = [0.25 0.64]\n";

CommandResult RunLinearLs(const std::string& arguments) {
  return testing::RunBinary("linear_ls", arguments);
}

// A course-layout folder with a simulated test; `edit` may spoil it.
std::string MakeDataDir(const ScratchDir& scratch, int samples = 400) {
  TiltSchedule design;
  design.sample_count = samples;
  const CalibrationTest test = SimulateTiltTest(design, CourseTableOneTruth(), 8);
  MatMatrix tita{samples, 1, test.theta_rad};
  MatMatrix datos{samples, 2, test.measured_x};
  datos.values.insert(datos.values.end(), test.measured_y.begin(), test.measured_y.end());
  EXPECT_TRUE(WriteMatFile(scratch.File("ensayo.mat"), {{"tita", tita}, {"datos", datos}}).ok());
  scratch.Write("datos.txt", kDatos);
  return scratch.path();
}

// The contract for bad input: status 2, exactly one line on stderr containing
// `fragment`, nothing on stdout, and no JSON file.
void ExpectRefused(const std::string& arguments, const std::string& fragment) {
  ScratchDir out;
  const std::string json = out.File("out.json");
  testing::ExpectBadInputContract(RunLinearLs(arguments + " --json='" + json + "'"), "linear_ls",
                                  fragment);
  EXPECT_EQ(RunCommand("ls -A '" + out.path() + "'").stdout_text, "") << "partial output left";
}

TEST(LinearLsBinary, ReproducesTableOneOnTheCourseDataAndWritesJson) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  ScratchDir out;
  const CommandResult result =
      RunLinearLs("--data_dir='" + dir + "' --json='" + out.File("linear_ls.json") + "'");
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  EXPECT_EQ(result.stderr_text, "");
  EXPECT_NE(result.stdout_text.find("bias_x     +7.6664e-02  3.5354e-03  m/s^2"), std::string::npos)
      << result.stdout_text;
  EXPECT_NE(result.stdout_text.find("scale_y    +1.0042e-02  8.1629e-04  1"), std::string::npos);
  EXPECT_NE(result.stdout_text.find("Termination: CONVERGENCE"), std::string::npos);

  const nlohmann::json json = nlohmann::json::parse(testing::ReadText(out.File("linear_ls.json")));
  EXPECT_NEAR(json["parameters"]["bias_x"].get<double>(), 7.667e-2, 1e-5);
  EXPECT_NEAR(json["parameters"]["scale_x"].get<double>(), -3.014e-2, 0.5e-5);
  EXPECT_NEAR(json["parameters"]["bias_y"].get<double>(), -1.751e-2, 0.5e-5);
  EXPECT_NEAR(json["parameters"]["scale_y"].get<double>(), 1.004e-2, 0.5e-5);
  EXPECT_NEAR(json["stddev"]["scale_x"].get<double>(), std::sqrt(2.603e-7), 1e-7);
  ASSERT_EQ(json["covariance"].size(), 4u);
  ASSERT_EQ(json["covariance"][0].size(), 4u);
  EXPECT_NEAR(json["covariance"][3][3].get<double>(), 6.663e-7, 0.5e-10);
  EXPECT_EQ(json["parameter_order"], nlohmann::json({"bias_x", "scale_x", "bias_y", "scale_y"}));
  EXPECT_NEAR(json["chi2"]["x"].get<double>(), 19847.931, 1e-3);
  EXPECT_NEAR(json["chi2"]["y"].get<double>(), 19964.104, 1e-3);
  EXPECT_EQ(json["n_samples"].get<int>(), 20001);
  EXPECT_EQ(json["input_files"]["calibration"]["path"].get<std::string>(), dir + "/ensayo.mat");
  EXPECT_EQ(json["input_files"]["conditions"]["path"].get<std::string>(), dir + "/datos.txt");
  EXPECT_LT(json["solvers"]["max_relative_difference"]["parameters"].get<double>(), 1e-9);
  EXPECT_LT(json["solvers"]["max_relative_difference"]["covariance"].get<double>(), 1e-9);

  // The pinned figures above are the reference report's (Table 1, its variances) or numpy's;
  // here every written figure is recomputed from the data by the plain normal equations of
  // test_support.h, and the printed rows are formatted from those.
  DataFiles files;
  ASSERT_TRUE(ResolveDataFiles(dir, &files).ok());
  CalibrationTest test;
  ASSERT_TRUE(LoadCalibrationTest(files.calibration, &test).ok());
  const testing::PlainAxisFit axes[2] = {testing::PlainBaselineFit(test, 0, 0.25),
                                         testing::PlainBaselineFit(test, 1, 0.64)};
  const char* names[2] = {"x", "y"};
  for (int axis = 0; axis < 2; ++axis) {
    const testing::PlainAxisFit& plain = axes[axis];
    const std::string bias = std::string("bias_") + names[axis];
    const std::string scale = std::string("scale_") + names[axis];
    EXPECT_NEAR(json["parameters"][bias].get<double>(), plain.bias, 1e-12);
    EXPECT_NEAR(json["parameters"][scale].get<double>(), plain.scale, 1e-12);
    EXPECT_NEAR(json["stddev"][bias].get<double>(), std::sqrt(plain.var_bias),
                1e-9 * std::sqrt(plain.var_bias));
    EXPECT_NEAR(json["stddev"][scale].get<double>(), std::sqrt(plain.var_scale),
                1e-9 * std::sqrt(plain.var_scale));
    const int b = 2 * axis;
    EXPECT_NEAR(json["covariance"][b][b].get<double>(), plain.var_bias, 1e-9 * plain.var_bias);
    EXPECT_NEAR(json["covariance"][b + 1][b + 1].get<double>(), plain.var_scale,
                1e-9 * plain.var_scale);
    EXPECT_NEAR(json["covariance"][b][b + 1].get<double>(), plain.cov_bias_scale,
                1e-9 * std::sqrt(plain.var_bias * plain.var_scale));
    EXPECT_NEAR(json["chi2"][names[axis]].get<double>(), plain.chi2, 1e-6 * plain.chi2);
    char row[96];
    std::snprintf(row, sizeof(row), "%-10s %+.4e  %.4e  m/s^2", bias.c_str(), plain.bias,
                  std::sqrt(plain.var_bias));
    EXPECT_NE(result.stdout_text.find(row), std::string::npos) << "expected: " << row;
    std::snprintf(row, sizeof(row), "%-10s %+.4e  %.4e  1", scale.c_str(), plain.scale,
                  std::sqrt(plain.var_scale));
    EXPECT_NE(result.stdout_text.find(row), std::string::npos) << "expected: " << row;
  }
  // The two axes' parameters are uncorrelated: separate problems.
  EXPECT_NEAR(json["covariance"][0][2].get<double>(), 0.0,
              1e-9 * std::sqrt(axes[0].var_bias * axes[1].var_bias));
}

TEST(LinearLsBinary, RunsTheEmbeddedDefaultWithoutData) {
  const CommandResult result = RunLinearLs("");
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  EXPECT_NE(
      result.stdout_text.find("simulated in-process: scenario tp2-2018, seed 1, 20001 samples"),
      std::string::npos)
      << result.stdout_text;
  EXPECT_NE(result.stdout_text.find("(est-truth)/sigma"), std::string::npos);
}

TEST(LinearLsBinary, HelpExplainsUnitsAndExitsZero) {
  const CommandResult result = RunLinearLs("--help");
  EXPECT_EQ(result.exit_status, 0);
  for (const char* fragment :
       {"--data_dir", "--g", "m/s^2", "radians", "(m/s^2)^2", "Exit status"}) {
    EXPECT_TRUE(result.stdout_text.find(fragment) != std::string::npos ||
                result.stderr_text.find(fragment) != std::string::npos)
        << fragment;
  }
  // Only the binary's own flags, not glog's dozens.
  EXPECT_EQ(result.stdout_text.find("--log_dir"), std::string::npos);
}

TEST(LinearLsBinary, RefusesBadFlags) {
  ExpectRefused("--no_such_flag=1", "unknown flag or argument '--no_such_flag=1'");
  ExpectRefused("stray", "unknown flag or argument 'stray'");
  ExpectRefused("--g=-9.8", "--g='-9.8' is not a valid double in [1, 100]");
  ExpectRefused("--g=abc", "--g='abc' is not a valid double");
  ExpectRefused("--seed=2.5", "--seed='2.5' is not a valid uint64");
  ExpectRefused("--set=angle=1", "--set: 'angle' is neither a parameter");
  ExpectRefused("--calibration_file=x.csv", "--calibration_file needs --conditions_file");
}

TEST(LinearLsBinary, RefusesMissingFolderFilesAndVariables) {
  ScratchDir scratch;
  ExpectRefused("--data_dir='" + scratch.File("absent") + "'", "absent: no such directory");
  ExpectRefused("--data_dir='" + scratch.path() + "'", "no course data here");
  const std::string dir = MakeDataDir(scratch);
  std::remove(scratch.File("datos.txt").c_str());
  ExpectRefused("--data_dir='" + dir + "'",
                scratch.File("datos.txt") + ": no such file; check the path");
  ASSERT_TRUE(
      WriteMatFile(scratch.File("ensayo.mat"), {{"tita", MatMatrix{3, 1, {0, 1, 2}}}}).ok());
  scratch.Write("datos.txt", kDatos);
  ExpectRefused("--data_dir='" + dir + "'",
                scratch.File("ensayo.mat") + ": variable 'datos' not found (the file has: tita)");
}

TEST(LinearLsBinary, RefusesWrongShapesNonFiniteValuesAndLengthMismatch) {
  ScratchDir scratch;
  const std::string dir = MakeDataDir(scratch);
  const std::string ensayo = scratch.File("ensayo.mat");
  MatMatrix tita{4, 1, {0, 1, 2, 3}};
  ASSERT_TRUE(WriteMatFile(ensayo, {{"tita", tita},
                                    {"datos", MatMatrix{4, 3, std::vector<double>(12, 1.0)}}})
                  .ok());
  ExpectRefused("--data_dir='" + dir + "'", ensayo + ": variable 'datos' is 4x3; expected 4x2");
  ASSERT_TRUE(WriteMatFile(
                  ensayo, {{"tita", tita}, {"datos", MatMatrix{3, 2, std::vector<double>(6, 1.0)}}})
                  .ok());
  ExpectRefused("--data_dir='" + dir + "'", "variable 'datos' has 3 rows but 'tita' has 4");
  std::vector<double> values(8, 1.0);
  values[5] = NAN;
  ASSERT_TRUE(WriteMatFile(ensayo, {{"tita", tita}, {"datos", MatMatrix{4, 2, values}}}).ok());
  ExpectRefused("--data_dir='" + dir + "'", ensayo + ": datos(2,2) is nan");
  ASSERT_TRUE(
      WriteMatFile(ensayo, {{"tita", MatMatrix{0, 1, {}}}, {"datos", MatMatrix{0, 2, {}}}}).ok());
  ExpectRefused("--data_dir='" + dir + "'", ensayo + ": variable 'tita' is empty");
}

TEST(LinearLsBinary, RefusesAVariableOfTheWrongType) {
  ScratchDir scratch;
  const std::string dir = MakeDataDir(scratch);
  const std::string ensayo = scratch.File("ensayo.mat");
  mat_t* mat = Mat_CreateVer(ensayo.c_str(), nullptr, MAT_FT_MAT5);
  ASSERT_NE(mat, nullptr);
  int32_t angles[3] = {0, 1, 2};
  double values[6] = {1, 2, 3, 4, 5, 6};
  size_t angle_dims[2] = {3, 1};
  size_t value_dims[2] = {3, 2};
  matvar_t* tita = Mat_VarCreate("tita", MAT_C_INT32, MAT_T_INT32, 2, angle_dims, angles, 0);
  matvar_t* datos = Mat_VarCreate("datos", MAT_C_DOUBLE, MAT_T_DOUBLE, 2, value_dims, values, 0);
  Mat_VarWrite(mat, tita, MAT_COMPRESSION_NONE);
  Mat_VarWrite(mat, datos, MAT_COMPRESSION_NONE);
  Mat_VarFree(tita);
  Mat_VarFree(datos);
  Mat_Close(mat);
  ExpectRefused("--data_dir='" + dir + "'",
                ensayo + ": variable 'tita' is int32; expected a real double matrix");
}

TEST(LinearLsBinary, RefusesTruncatedAndEmptyMatFiles) {
  ScratchDir scratch;
  const std::string dir = MakeDataDir(scratch, 3000);
  const std::string ensayo = scratch.File("ensayo.mat");
  const std::string bytes = testing::ReadText(ensayo);
  scratch.Write("ensayo.mat", bytes.substr(0, bytes.size() - 1000));
  ExpectRefused("--data_dir='" + dir + "'", ensayo + ": the file is truncated");
  scratch.Write("ensayo.mat", "");
  ExpectRefused("--data_dir='" + dir + "'", ensayo + ": the file is empty (0 bytes)");
}

TEST(LinearLsBinary, RefusesBadConditions) {
  ScratchDir scratch;
  const std::string dir = MakeDataDir(scratch);
  const std::string datos = scratch.File("datos.txt");
  scratch.Write(
      "datos.txt",
      "Posición inicial = [0 0]\nVelocidad inicial = [1 3]\nvarianza del ruido = [0 0.64]\n");
  ExpectRefused("--data_dir='" + dir + "'", datos + ": line 3: noise variances must be positive");
  scratch.Write("datos.txt", "Posición inicial = [0 0]\nVelocidad inicial = [1 3]\n");
  ExpectRefused("--data_dir='" + dir + "'",
                datos + ": missing varianza del ruido de los acelerómetros");
}

TEST(LinearLsBinary, RefusesATestThatCannotSeparateBiasFromScale) {
  ScratchDir scratch;
  TiltSchedule design;
  design.sample_count = 500;
  design.theta_end_rad = 0.02;
  const CalibrationTest test = SimulateTiltTest(design, CourseTableOneTruth(), 4);
  ASSERT_TRUE(WriteCalibrationCsv(scratch.File("calibration.csv"), test).ok());
  scratch.Write("scenario.json",
                "{\"initial_position\": [0, 0], \"initial_velocity\": [1, 3], \"noise_variance\": "
                "[0.25, 0.64]}");
  ExpectRefused("--data_dir='" + scratch.path() + "'",
                scratch.File("calibration.csv") + ": the x axis' specific force varies by only");
}

TEST(LinearLsBinary, RefusesBadCsvCellsWithLineAndColumn) {
  ScratchDir scratch;
  scratch.Write("calibration.csv", "theta,ax,ay\n0,1,2\n0.5,1,2\n1.0,oops,2\n");
  scratch.Write("scenario.json",
                "{\"initial_position\": [0, 0], \"initial_velocity\": [1, 3], \"noise_variance\": "
                "[0.25, 0.64]}");
  ExpectRefused("--data_dir='" + scratch.path() + "'",
                scratch.File("calibration.csv") + ": line 4, column 'ax': 'oops' is not a number");
}

TEST(LinearLsBinary, SingleFileFlagsOverrideTheFolder) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  const CommandResult result = RunLinearLs(
      "--calibration_file='" + dir + "/ensayo.mat' --conditions_file='" + dir + "/datos.txt'");
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  EXPECT_NE(result.stdout_text.find("+7.6664e-02"), std::string::npos);
}

TEST(LinearLsBinary, RefusesAJsonPathInAMissingFolderAfterPrintingNothingPartial) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  ScratchDir out;
  const CommandResult result =
      RunLinearLs("--data_dir='" + dir + "' --json='" + out.File("no/such/dir/out.json") + "'");
  EXPECT_EQ(result.exit_status, 2);
  EXPECT_NE(result.stderr_text.find("/no/such/dir does not exist; create it first"),
            std::string::npos)
      << result.stderr_text;
}

TEST(LinearLsBinary, UsesTheScenariosGravityUnlessTheFlagIsGiven) {
  ScratchDir scratch;
  TiltSchedule design;
  design.sample_count = 300;
  ASSERT_TRUE(WriteCalibrationCsv(scratch.File("calibration.csv"),
                                  SimulateTiltTest(design, CourseTableOneTruth(), 6))
                  .ok());
  scratch.Write("scenario.json",
                "{\"initial_position\": [0, 0], \"initial_velocity\": [1, 3], "
                "\"noise_variance\": [0.25, 0.64], \"gravity\": 9.81}");
  ScratchDir outputs;  // outside the data folder, where outputs may not go
  auto gravity_used = [&](const std::string& flags) {
    const std::string json = outputs.File("out.json");
    const CommandResult result =
        RunLinearLs("--data_dir='" + scratch.path() + "' --json='" + json + "' " + flags);
    EXPECT_EQ(result.exit_status, 0) << result.stderr_text;
    return nlohmann::json::parse(testing::ReadText(json))["gravity_mps2"].get<double>();
  };
  EXPECT_EQ(gravity_used(""), 9.81);
  EXPECT_EQ(gravity_used("--g=9.8"), 9.8);
  EXPECT_EQ(gravity_used("--g=9.7"), 9.7);
}

}  // namespace
}  // namespace accelcal
