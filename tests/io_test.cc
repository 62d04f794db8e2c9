// Readers of the course layout and the CSV layout: what they accept, and the one-line
// message they give for each kind of bad input.

#include <gtest/gtest.h>
#include <matio.h>

#include <cmath>
#include <limits>

#include "io/atomic_file.h"
#include "io/course_data.h"
#include "io/csv_reader.h"
#include "io/datos_txt.h"
#include "io/mat_file.h"
#include "io/run_conditions.h"
#include "test_support.h"

namespace accelcal {
namespace {

#define EXPECT_ERROR_CONTAINS(status_expression, fragment)                      \
  do {                                                                          \
    const ::accelcal::Status status_ = (status_expression);                     \
    EXPECT_FALSE(status_.ok()) << "expected an error containing: " << fragment; \
    EXPECT_NE(status_.message().find(fragment), std::string::npos)              \
        << "message: " << status_.message() << "\nexpected: " << fragment;      \
  } while (false)

// ---- datos.txt ---------------------------------------------------------------------

constexpr char kCourseDatos[] =
    "Posici\xC3\xB3n inicial = [0 0]\n"
    "Velocidad inicial = [1 3]\n"
    "varianza del ruido de los aceler\xC3\xB3metros = [0.25 0.64]\n";

TEST(DatosTxt, ParsesTheCourseFile) {
  RunConditions conditions;
  ASSERT_TRUE(ParseDatosTxt(kCourseDatos, &conditions).ok());
  EXPECT_EQ(conditions.initial_velocity_x_mps, 1.0);
  EXPECT_EQ(conditions.initial_velocity_y_mps, 3.0);
  EXPECT_EQ(conditions.noise_variance_x, 0.25);
  EXPECT_EQ(conditions.noise_variance_y, 0.64);
}

TEST(DatosTxt, ToleratesLatin1AccentsSpacingSeparatorsAndOrder) {
  const std::string text =
      "\r\n  VARIANZA  del ruido de los aceler\xF3metros=[ 0.25 ,0.64 ]\r\n"
      "Velocidad   inicial = [1;3]\r\n"
      "posicion inicial = [-2.5e1\t7]\r\n";
  RunConditions conditions;
  const Status status = ParseDatosTxt(text, &conditions);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(conditions.initial_position_x_m, -25.0);
  EXPECT_EQ(conditions.initial_position_y_m, 7.0);
  EXPECT_EQ(conditions.initial_velocity_y_mps, 3.0);
  EXPECT_EQ(conditions.noise_variance_y, 0.64);
}

TEST(DatosTxt, AcceptsEnglishKeys) {
  RunConditions conditions;
  EXPECT_TRUE(ParseDatosTxt("initial position = [1 2]\ninitial velocity = [3 4]\n"
                            "noise variance = [0.1 0.2]\n",
                            &conditions)
                  .ok());
  EXPECT_EQ(conditions.noise_variance_x, 0.1);
}

TEST(DatosTxt, RefusesBadInputWithTheLine) {
  RunConditions conditions;
  EXPECT_ERROR_CONTAINS(
      ParseDatosTxt("Posición inicial = [0 0]\nVelocidad inicial = [1 3]\n", &conditions),
      "missing varianza del ruido");
  EXPECT_ERROR_CONTAINS(ParseDatosTxt("Posición inicial = [0 0\n", &conditions),
                        "line 1: unbalanced brackets");
  EXPECT_ERROR_CONTAINS(ParseDatosTxt("Velocidad inicial = [1]\n", &conditions),
                        "line 1: 'Velocidad inicial' has 1 value, expected 2");
  EXPECT_ERROR_CONTAINS(ParseDatosTxt("Velocidad inicial = [0,5 1,5]\n", &conditions),
                        "decimal commas");
  EXPECT_ERROR_CONTAINS(ParseDatosTxt("Velocidad inicial = [1 x]\n", &conditions),
                        "'x' in 'Velocidad inicial' is not a finite number");
  EXPECT_ERROR_CONTAINS(ParseDatosTxt("\nvarianza del ruido = [0.25 -0.64]\n", &conditions),
                        "line 2: noise variances must be positive");
  EXPECT_ERROR_CONTAINS(
      ParseDatosTxt("Velocidad inicial = [1 3]\nVelocidad inicial = [1 3]\n", &conditions),
      "line 2: 'Velocidad inicial' is given twice");
  EXPECT_ERROR_CONTAINS(ParseDatosTxt("Aceleracion = [1 3]\n", &conditions),
                        "line 1: unknown key 'Aceleracion '");
  EXPECT_ERROR_CONTAINS(ParseDatosTxt("Velocidad inicial [1 3]\n", &conditions),
                        "line 1: expected 'key = [x y]'");
}

TEST(ScenarioJson, RoundTripsAndRefusesTypos) {
  RunConditions conditions;
  conditions.initial_velocity_x_mps = 1.5;
  conditions.noise_variance_x = 0.25;
  conditions.noise_variance_y = 0.64;
  conditions.has_gravity = true;
  conditions.gravity_mps2 = 9.81;
  RunConditions parsed;
  ASSERT_TRUE(ParseScenarioJson(ScenarioJson(conditions), &parsed).ok());
  EXPECT_EQ(parsed.initial_velocity_x_mps, 1.5);
  EXPECT_EQ(parsed.gravity_mps2, 9.81);
  EXPECT_ERROR_CONTAINS(ParseScenarioJson("{\"noise_varaince\": [1, 2]}", &parsed),
                        "unknown key \"noise_varaince\"");
  EXPECT_ERROR_CONTAINS(
      ParseScenarioJson("{\"initial_position\": [0, 0], \"initial_velocity\": [1, 3],"
                        " \"noise_variance\": [0.25]}",
                        &parsed),
      "\"noise_variance\" must be an array of two numbers");
  EXPECT_ERROR_CONTAINS(ParseScenarioJson("{\"initial_position\": [0, 0", &parsed),
                        "not valid JSON");
}

// ---- CSV -----------------------------------------------------------------------------

const std::vector<CsvColumn> kColumns = {{"theta"}, {"ax"}, {"ay"}};

TEST(CsvReader, ReadsCommentsBlankLinesCrlfAndBom) {
  CsvTable table;
  const Status status =
      ParseCsv("\xEF\xBB\xBF# a comment\r\nTheta, ax ,ay\r\n0,1.5,-2e-3\r\n\r\n0.1,+2,3\r\n",
               kColumns, &table);
  ASSERT_TRUE(status.ok()) << status.message();
  ASSERT_EQ(table.row_count, 2);
  EXPECT_EQ(table.numbers[1][0], 1.5);
  EXPECT_EQ(table.numbers[2][0], -2e-3);
  EXPECT_EQ(table.numbers[1][1], 2.0);
}

TEST(CsvReader, RefusesBadInputWithLineAndColumn) {
  CsvTable table;
  EXPECT_ERROR_CONTAINS(ParseCsv("theta,ax\n0,1\n", kColumns, &table),
                        "line 1: the header is 'theta,ax', expected 'theta,ax,ay'");
  EXPECT_ERROR_CONTAINS(ParseCsv("theta,ax,ay\n0,1,2\n0,1,2,3\n", kColumns, &table),
                        "line 3: 4 fields, expected 3 (theta,ax,ay)");
  EXPECT_ERROR_CONTAINS(ParseCsv("theta,ax,ay\n0,1,2\n0,1\n", kColumns, &table),
                        "line 3: 2 fields, expected 3");
  EXPECT_ERROR_CONTAINS(ParseCsv("theta,ax,ay\n0,1,5\n0,1,5,2\n", kColumns, &table),
                        "decimal commas");
  EXPECT_ERROR_CONTAINS(ParseCsv("theta,ax,ay\n0,1,2\n0,abc,2\n", kColumns, &table),
                        "line 3, column 'ax': 'abc' is not a number");
  EXPECT_ERROR_CONTAINS(ParseCsv("theta,ax,ay\n0,1,NaN\n", kColumns, &table),
                        "line 2, column 'ay': 'NaN' is not a finite number");
  EXPECT_ERROR_CONTAINS(ParseCsv("theta,ax,ay\n0,inf,1\n", kColumns, &table),
                        "not a finite number");
  EXPECT_ERROR_CONTAINS(ParseCsv("theta,ax,ay\n0,,1\n", kColumns, &table),
                        "line 2, column 'ax': '' is not a number");
  EXPECT_ERROR_CONTAINS(ParseCsv("theta,ax,ay\n", kColumns, &table),
                        "no data rows after the header");
  EXPECT_ERROR_CONTAINS(ParseCsv("", kColumns, &table), "the file is empty");
}

// ---- .mat files ----------------------------------------------------------------------

MatMatrix Matrix(int rows, int cols, double start = 0.0) {
  MatMatrix matrix;
  matrix.rows = rows;
  matrix.cols = cols;
  for (int i = 0; i < rows * cols; ++i) matrix.values.push_back(start + 0.001 * i);
  return matrix;
}

// A calibration file with `rows` angles and a datos matrix of the given shape.
std::string WriteEnsayo(const testing::ScratchDir& scratch, int rows, int datos_rows,
                        int datos_cols) {
  const std::string path = scratch.File("ensayo.mat");
  EXPECT_TRUE(
      WriteMatFile(path, {{"tita", Matrix(rows, 1)}, {"datos", Matrix(datos_rows, datos_cols)}})
          .ok());
  return path;
}

TEST(MatFile, WrittenFilesReadBackExactly) {
  testing::ScratchDir scratch;
  const std::string path = WriteEnsayo(scratch, 50, 50, 2);
  CalibrationTest test;
  const Status status = LoadCalibrationTest(path, &test);
  ASSERT_TRUE(status.ok()) << status.message();
  ASSERT_EQ(test.size(), 50);
  EXPECT_EQ(test.theta_rad[3], 0.003);
  EXPECT_EQ(test.measured_x[0], 0.0);
  EXPECT_EQ(test.measured_y[0], 0.050);  // column 2 starts after 50 values
}

TEST(MatFile, NamesTheFileAndVariableOfEveryShapeProblem) {
  testing::ScratchDir scratch;
  CalibrationTest test;
  std::string path = WriteEnsayo(scratch, 50, 50, 3);
  EXPECT_ERROR_CONTAINS(LoadCalibrationTest(path, &test),
                        path + ": variable 'datos' is 50x3; expected 50x2 (x then y, m/s^2)");
  path = WriteEnsayo(scratch, 50, 3, 50);
  EXPECT_ERROR_CONTAINS(LoadCalibrationTest(path, &test), "is 3x50; expected 50x2");
  path = WriteEnsayo(scratch, 50, 49, 2);
  EXPECT_ERROR_CONTAINS(LoadCalibrationTest(path, &test),
                        "variable 'datos' has 49 rows but 'tita' has 50; they must match");
  ASSERT_TRUE(WriteMatFile(path, {{"theta", Matrix(5, 1)}, {"datos", Matrix(5, 2)}}).ok());
  EXPECT_ERROR_CONTAINS(LoadCalibrationTest(path, &test),
                        "variable 'tita' not found (the file has: theta, datos)");
  ASSERT_TRUE(WriteMatFile(path, {{"tita", Matrix(5, 2)}, {"datos", Matrix(5, 2)}}).ok());
  EXPECT_ERROR_CONTAINS(LoadCalibrationTest(path, &test),
                        "variable 'tita' is 5x2; expected Nx1 angles (rad)");
  ASSERT_TRUE(WriteMatFile(path, {{"tita", Matrix(0, 1)}, {"datos", Matrix(0, 2)}}).ok());
  EXPECT_ERROR_CONTAINS(LoadCalibrationTest(path, &test), "variable 'tita' is empty (0x1)");
}

TEST(MatFile, ReadsA2xNMatrixAsItsTransposeAndSaysSo) {
  testing::ScratchDir scratch;
  const std::string path = scratch.File("ensayo.mat");
  // datos = [ax; ay]: row 0 holds x, row 1 holds y.
  MatMatrix rows{2, 4, {10, 20, 11, 21, 12, 22, 13, 23}};
  ASSERT_TRUE(WriteMatFile(path, {{"tita", Matrix(4, 1)}, {"datos", rows}}).ok());
  CalibrationTest test;
  std::vector<std::string> notes;
  ASSERT_TRUE(LoadCalibrationTest(path, &test, {}, &notes).ok());
  EXPECT_EQ(test.measured_x, std::vector<double>({10, 11, 12, 13}));
  EXPECT_EQ(test.measured_y, std::vector<double>({20, 21, 22, 23}));
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_EQ(notes[0], path + ": variable 'datos' is 2x4; read as its transpose (4x2, x then y)");
}

TEST(CalibrationTest, RefusesAngleSpansThatLookLikeDegreesUnlessTold) {
  testing::ScratchDir scratch;
  const std::string path = scratch.File("calibration.csv");
  ASSERT_TRUE(WriteFileAtomically(path, "theta,ax,ay\n0,1,2\n90,1,2\n180,1,2\n359,1,2\n").ok());
  CalibrationTest test;
  EXPECT_ERROR_CONTAINS(LoadCalibrationTest(path, &test),
                        path +
                            ": theta spans 359 (from 0 to 359) over 4 samples, more than two "
                            "turns if it were radians: it looks like degrees; pass "
                            "--theta_unit=deg");
  ASSERT_TRUE(LoadCalibrationTest(path, &test, {AngleUnit::kDegree}).ok());
  EXPECT_DOUBLE_EQ(test.theta_rad[1], M_PI / 2);
  EXPECT_DOUBLE_EQ(test.theta_rad[3], 359 * M_PI / 180);
  ASSERT_TRUE(LoadCalibrationTest(path, &test, {AngleUnit::kRadian}).ok());
  EXPECT_EQ(test.theta_rad[3], 359.0);
  // Two full turns in radians are a plausible test and pass.
  ASSERT_TRUE(WriteFileAtomically(path, "theta,ax,ay\n0,1,2\n12.566,1,2\n").ok());
  EXPECT_TRUE(LoadCalibrationTest(path, &test).ok());
  AngleUnit unit;
  EXPECT_ERROR_CONTAINS(ParseAngleUnit("degrees", &unit), "is not one of auto, rad, deg");
}

TEST(MatFile, RefusesNonFiniteSamplesWithTheirIndex) {
  testing::ScratchDir scratch;
  MatMatrix datos = Matrix(20, 2);
  datos.values[20 + 16] = std::numeric_limits<double>::quiet_NaN();  // datos(17,2)
  const std::string path = scratch.File("ensayo.mat");
  ASSERT_TRUE(WriteMatFile(path, {{"tita", Matrix(20, 1)}, {"datos", datos}}).ok());
  CalibrationTest test;
  EXPECT_ERROR_CONTAINS(LoadCalibrationTest(path, &test),
                        "datos(17,2) is nan; remove or repair the sample");
  MatMatrix tita = Matrix(20, 1);
  tita.values[4] = std::numeric_limits<double>::infinity();
  ASSERT_TRUE(WriteMatFile(path, {{"tita", tita}, {"datos", Matrix(20, 2)}}).ok());
  EXPECT_ERROR_CONTAINS(LoadCalibrationTest(path, &test), "tita(5) is inf");
}

TEST(MatFile, RefusesTruncatedEmptyAndForeignFiles) {
  testing::ScratchDir scratch;
  const std::string path = WriteEnsayo(scratch, 2000, 2000, 2);
  const std::string bytes = testing::ReadText(path);
  CalibrationTest test;
  const std::string truncated = scratch.Write("truncated.mat", bytes.substr(0, bytes.size() / 2));
  EXPECT_ERROR_CONTAINS(LoadCalibrationTest(truncated, &test),
                        "truncated.mat: the file is truncated");
  const std::string header_only = scratch.Write("header.mat", bytes.substr(0, 100));
  EXPECT_ERROR_CONTAINS(LoadCalibrationTest(header_only, &test), "the file is truncated");
  const std::string empty = scratch.Write("empty.mat", "");
  EXPECT_ERROR_CONTAINS(LoadCalibrationTest(empty, &test),
                        "empty.mat: the file is empty (0 bytes)");
  const std::string text = scratch.Write("text.mat", "theta,ax,ay\n1,2,3\n");
  EXPECT_ERROR_CONTAINS(LoadCalibrationTest(text, &test), "text.mat: not a readable MAT file");
  EXPECT_ERROR_CONTAINS(LoadCalibrationTest(scratch.File("absent.mat"), &test),
                        "absent.mat: cannot open the file");
}

TEST(MatFile, RefusesIntegerAndCellVariables) {
  testing::ScratchDir scratch;
  const std::string path = scratch.File("ensayo.mat");
  mat_t* mat = Mat_CreateVer(path.c_str(), nullptr, MAT_FT_MAT5);
  ASSERT_NE(mat, nullptr);
  int32_t integers[3] = {1, 2, 3};
  size_t dims[2] = {3, 1};
  matvar_t* tita = Mat_VarCreate("tita", MAT_C_INT32, MAT_T_INT32, 2, dims, integers, 0);
  Mat_VarWrite(mat, tita, MAT_COMPRESSION_NONE);
  Mat_VarFree(tita);
  size_t cell_dims[2] = {1, 1};
  matvar_t* cell = Mat_VarCreate("datos", MAT_C_CELL, MAT_T_CELL, 2, cell_dims, nullptr, 0);
  double one = 1.0;
  size_t one_dims[2] = {1, 1};
  Mat_VarSetCell(cell, 0, Mat_VarCreate(nullptr, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, one_dims, &one, 0));
  Mat_VarWrite(mat, cell, MAT_COMPRESSION_NONE);
  Mat_VarFree(cell);
  Mat_Close(mat);
  MatFileReader reader;
  ASSERT_TRUE(reader.Open(path).ok());
  MatMatrix matrix;
  EXPECT_ERROR_CONTAINS(reader.ReadMatrix("tita", &matrix),
                        "variable 'tita' is int32; expected a real double matrix");
  EXPECT_ERROR_CONTAINS(reader.ReadMatrix("datos", &matrix), "variable 'datos' is a cell array");
}

TEST(MatFile, ReadsAnyNumberOfLandmarksByVariableName) {
  testing::ScratchDir scratch;
  const std::string path = scratch.File("puntos.mat");
  std::vector<std::pair<std::string, MatMatrix>> variables;
  double start = 10.0;
  for (const char* name : {"P1", "Q", "north_gate", "B", "Z9"}) {
    variables.push_back({name, Matrix(1, 2, start)});
    start += 5.0;
  }
  ASSERT_TRUE(WriteMatFile(path, variables).ok());
  std::vector<Landmark> landmarks;
  ASSERT_TRUE(LoadLandmarks(path, &landmarks).ok());
  ASSERT_EQ(landmarks.size(), 5u);
  EXPECT_EQ(landmarks[2].name, "north_gate");
  EXPECT_EQ(landmarks[2].x_m, 20.0);
  EXPECT_EQ(landmarks[2].y_m, 20.001);
  // Two landmarks at one place cannot be told apart.
  ASSERT_TRUE(WriteMatFile(path, {{"A", Matrix(1, 2)}, {"B", Matrix(1, 2)}}).ok());
  EXPECT_ERROR_CONTAINS(LoadLandmarks(path, &landmarks),
                        "landmarks 'A' and 'B' are both at (0, 0.001) m, so no data can tell them "
                        "apart");
  ASSERT_TRUE(WriteMatFile(path, {{"A", Matrix(1, 2)}, {"E", Matrix(3, 1)}}).ok());
  EXPECT_ERROR_CONTAINS(LoadLandmarks(path, &landmarks),
                        "variable 'E' is 3x1; every landmark must be a 1x2");
}

TEST(VehicleRun, RefusesTimeThatIsNotUniformlyIncreasing) {
  testing::ScratchDir scratch;
  VehicleRun run;
  const std::string path =
      scratch.Write("trajectory.csv", "t,ax,ay\n0,1,1\n0.01,1,1\n0.03,1,1\n0.04,1,1\n0.05,1,1\n");
  EXPECT_ERROR_CONTAINS(LoadVehicleRun(path, &run),
                        "t is not uniformly spaced: t(3) - t(2) = 0.02 s");
  scratch.Write("trajectory.csv", "t,ax,ay\n0,1,1\n0.01,1,1\n0.01,1,1\n0.03,1,1\n");
  EXPECT_ERROR_CONTAINS(LoadVehicleRun(path, &run), "t is not strictly increasing: t(3) = 0.01 s");
  scratch.Write("trajectory.csv", "t,ax,ay\n0,1,1\n");
  EXPECT_ERROR_CONTAINS(LoadVehicleRun(path, &run),
                        "the run has 1 sample(s); at least 2 are needed");
  const std::string mat_path = scratch.File("acel.mat");
  MatMatrix t = Matrix(10, 1);
  t.values[6] = t.values[5];
  ASSERT_TRUE(WriteMatFile(mat_path, {{"t", t}, {"Aerr", Matrix(10, 2)}}).ok());
  EXPECT_ERROR_CONTAINS(LoadVehicleRun(mat_path, &run), "acel.mat: t is not strictly increasing");
  // The assignment's name for the matrix is accepted when Aerr is absent.
  ASSERT_TRUE(WriteMatFile(mat_path, {{"t", Matrix(10, 1)}, {"acel", Matrix(10, 2)}}).ok());
  EXPECT_TRUE(LoadVehicleRun(mat_path, &run).ok());
}

TEST(DataFiles, ResolvesEitherLayoutAndExplainsAnEmptyFolder) {
  testing::ScratchDir scratch;
  DataFiles files;
  EXPECT_ERROR_CONTAINS(
      ResolveDataFiles(scratch.path(), &files),
      "no course data here: expected ensayo.mat (course layout) or calibration.csv");
  EXPECT_ERROR_CONTAINS(ResolveDataFiles(scratch.File("nope"), &files), "no such directory");
  scratch.Write("calibration.csv", "theta,ax,ay\n");
  ASSERT_TRUE(ResolveDataFiles(scratch.path(), &files).ok());
  EXPECT_EQ(files.conditions, scratch.File("scenario.json"));
  EXPECT_EQ(files.landmarks, scratch.File("landmarks.csv"));
}

TEST(AtomicFile, ReplacesWholeOrLeavesNothing) {
  testing::ScratchDir scratch;
  const std::string path = scratch.File("out.json");
  ASSERT_TRUE(WriteFileAtomically(path, "first").ok());
  ASSERT_TRUE(WriteFileAtomically(path, "second").ok());
  EXPECT_EQ(testing::ReadText(path), "second");
  EXPECT_ERROR_CONTAINS(WriteFileAtomically(scratch.File("missing/out.json"), "x"),
                        "check that the directory exists");
  EXPECT_EQ(testing::RunCommand("ls -A '" + scratch.path() + "'").stdout_text, "out.json\n");
}

}  // namespace
}  // namespace accelcal
