// Readers of the course layout and the CSV layout: what they accept, and the one-line
// message they give for each kind of bad input.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <matio.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <thread>

#include "common/format.h"
#include "io/atomic_file.h"
#include "io/course_data.h"
#include "io/csv_reader.h"
#include "io/datos_txt.h"
#include "io/input_file.h"
#include "io/input_text.h"
#include "io/json_file.h"
#include "io/mat_file.h"
#include "io/run_conditions.h"
#include "io/scenario_json.h"
#include "simulation/scenario.h"
#include "test_support.h"

namespace accelcal {
namespace {

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
                        "line 1: unknown key 'Aceleracion'");
  EXPECT_ERROR_CONTAINS(ParseDatosTxt("Velocidad inicial [1 3]\n", &conditions),
                        "line 1: expected 'key = [x y]'");
}

// Keys are whole keys: a word of one inside another key is not that key.
TEST(DatosTxt, MatchesWholeKeysOnly) {
  RunConditions conditions;
  const std::string variance = "varianza del ruido de los aceler\xC3\xB3metros = [0.25 0.64]\n";
  EXPECT_ERROR_CONTAINS(
      ParseDatosTxt(
          "Posici\xC3\xB3n final = [459.84 59.99]\nVelocidad inicial = [1 3]\n" + variance,
          &conditions),
      "line 1: unknown key 'Posici\xC3\xB3n final'; expected Posici\xC3\xB3n inicial, Velocidad "
      "inicial or varianza del ruido de los aceler\xC3\xB3metros");
  EXPECT_ERROR_CONTAINS(
      ParseDatosTxt("Posici\xC3\xB3n inicial = [0 0]\nVelocidad final = [1 3]\n" + variance,
                    &conditions),
      "line 2: unknown key 'Velocidad final'");
  EXPECT_ERROR_CONTAINS(ParseDatosTxt("Posici\xC3\xB3n inicial = [0 0]\nVelocidad inicial = [1 3]\n"
                                      "varianza estimada = [0.25 0.64]\n",
                                      &conditions),
                        "line 3: unknown key 'varianza estimada'");
  EXPECT_ERROR_CONTAINS(ParseDatosTxt("final position = [1 2]\n", &conditions),
                        "line 1: unknown key 'final position'");
  // Every form accepted before, whole: accents and case folded, any spacing, '_' as ' '.
  for (const char* text :
       {"POSICION  INICIAL = [1 2]\nvelocidad inicial = [3 4]\nVarianza del ruido = [0.1 0.2]\n",
        "initial_position = [1 2]\nInitial Velocity = [3 4]\nnoise variance = [0.1 0.2]\n",
        "Posici\xF3n inicial = [1 2]\nVelocidad inicial = [3 4]\n"
        "varianza del ruido de los aceler\xF3metros = [0.1 0.2]"}) {
    SCOPED_TRACE(text);
    const Status status = ParseDatosTxt(text, &conditions);
    ASSERT_TRUE(status.ok()) << status.message();
    EXPECT_EQ(conditions.initial_position_x_m, 1.0);
    EXPECT_EQ(conditions.initial_velocity_y_mps, 4.0);
    EXPECT_EQ(conditions.noise_variance_y, 0.2);
  }
}

// What a message quotes of the file is at most 40 characters, printable, on one line.
TEST(DatosTxt, QuotesAtMost40PrintableCharactersOfTheFile) {
  RunConditions conditions;
  const Status status = ParseDatosTxt(std::string(5 << 20, 'k') + " = [1 2]\n", &conditions);
  EXPECT_EQ(status.message(), "line 1: unknown key '" + std::string(40, 'k') +
                                  "...'; expected Posici\xC3\xB3n inicial, Velocidad inicial or "
                                  "varianza del ruido de los aceler\xC3\xB3metros (or initial "
                                  "position, initial velocity, noise variance)");
  EXPECT_ERROR_CONTAINS(ParseDatosTxt("Velocidad inicial = [1 \x01\x7F\xE9]\n", &conditions),
                        "line 1: '\\x01\\x7F\\xE9' in 'Velocidad inicial' is not a finite number");
}

TEST(EchoInput, CutsLongTextAndEscapesWhatDoesNotPrint) {
  EXPECT_EQ(EchoInput("abc"), "abc");
  EXPECT_EQ(EchoInput(""), "");
  EXPECT_EQ(EchoInput(std::string(40, 'x')), std::string(40, 'x'));
  EXPECT_EQ(EchoInput(std::string(41, 'x')), std::string(40, 'x') + "...");
  // UTF-8 is kept and counted by characters; Latin-1, controls and broken UTF-8 are escaped.
  EXPECT_EQ(EchoInput("Posici\xC3\xB3n"), "Posici\xC3\xB3n");
  EXPECT_EQ(EchoInput("Posici\xF3n"), "Posici\\xF3n");
  EXPECT_EQ(EchoInput(std::string("a\0b\r\n\t\x1B", 7)), "a\\x00b\\x0D\\x0A\\x09\\x1B");
  EXPECT_EQ(EchoInput("\xC2\x85\xC3"), "\\xC2\\x85\\xC3");
  EXPECT_EQ(EchoInput("\xE2\x82\xAC 5"), "\xE2\x82\xAC 5");
  std::string accents;
  for (int i = 0; i < 50; ++i) accents += "\xC3\xB3";
  std::string expected;
  for (int i = 0; i < 40; ++i) expected += "\xC3\xB3";
  EXPECT_EQ(EchoInput(accents), expected + "...");
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

// nlohmann::json keeps the last of two values for one key; the readers refuse the file.
TEST(ScenarioJson, RefusesAKeyGivenTwice) {
  RunConditions parsed;
  EXPECT_EQ(ParseScenarioJson("{\"initial_position\": [0, 0], \"initial_velocity\": [1, 3],\n"
                              " \"noise_variance\": [0.25, 0.64], \"noise_variance\": [25, 64]}",
                              &parsed)
                .message(),
            "key \"noise_variance\" is given twice in one object, at /noise_variance; a JSON "
            "reader would keep only one of the two values: remove the other");
}

TEST(ParseJsonStrict, NamesADuplicateKeyByItsJsonPointer) {
  nlohmann::json document;
  ASSERT_TRUE(ParseJsonStrict("{\"a\": [1, {\"b\": 2}], \"c\": {\"b\": 3}}", &document).ok());
  EXPECT_EQ(document["c"]["b"], 3);
  EXPECT_ERROR_CONTAINS(
      ParseJsonStrict(R"({"run": {"dt": 0.01, "profile": {}, "dt": 0.02}})", &document),
      "key \"dt\" is given twice in one object, at /run/dt;");
  EXPECT_TRUE(document.is_null());
  EXPECT_ERROR_CONTAINS(
      ParseJsonStrict(R"({"x": [0, [1], {"y": 1}, {"a/b~": 1, "a/b~": 2}]})", &document),
      "key \"a/b~\" is given twice in one object, at /x/3/a~1b~0;");
  EXPECT_ERROR_CONTAINS(ParseJsonStrict(R"([{"k": 1}, {"k": 1, "k": 1}])", &document), "at /1/k;");
  // The parser's message quotes at most 40 characters of the file.
  const Status unterminated =
      ParseJsonStrict("{\"name\": \"" + std::string(1 << 20, 'n'), &document);
  EXPECT_ERROR_CONTAINS(unterminated, "not valid JSON (");
  EXPECT_ERROR_CONTAINS(unterminated, "last read: '\"nnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnn...'");
  EXPECT_LT(unterminated.message().size(), 300u) << unterminated.message();
  // Messages that quote nothing of the file are kept whole.
  EXPECT_ERROR_CONTAINS(ParseJsonStrict("{\"a\": [1, 2", &document),
                        "syntax error while parsing array - unexpected end of input; expected ']'");
  EXPECT_ERROR_CONTAINS(ParseJsonStrict("{\"a\": tru\x01"
                                        "e}",
                                        &document),
                        "invalid literal; last read: '\"a\": tru<U+0001>')");
}

// The scenario files of the simulator go through the same strict parse.
TEST(ParseJsonStrict, RefusesADuplicateKeyInAScenarioFile) {
  testing::ScratchDir scratch;
  scratch.Write("s.json", R"({"run": {"dt": 0.01, "duration": 3, "dt": 0.1,
                             "profile": {"segments": [{"duration": 3, "acceleration": [0, 0]}]}},
                             "landmarks": {"listed": [{"name": "A", "position": [0, 0]}]}})");
  Scenario scenario;
  EXPECT_ERROR_CONTAINS(LoadScenario(scratch.File("s.json"), &scenario),
                        scratch.File("s.json") +
                            ": key \"dt\" is given twice in one object, at "
                            "/run/dt;");
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

// An interrupted copy most often ends inside a number, which still parses: refused.
TEST(CsvReader, RefusesALastLineWithoutLineEnd) {
  CsvTable table;
  EXPECT_EQ(ParseCsv("theta,ax,ay\n0,1,2\n0.1,1,2.0", kColumns, &table).message(),
            "line 3 has no line end: the file looks cut short; copy it again, or end the line if "
            "it is complete");
  EXPECT_ERROR_CONTAINS(ParseCsv("theta,ax,ay\r\n0,1,2\r\n\r\n0.1,1,", kColumns, &table),
                        "line 4 has no line end");
  EXPECT_ERROR_CONTAINS(ParseCsv("theta,ax,ay", kColumns, &table), "line 1 has no line end");
  // An earlier bad line is still reported first, as the stream reports it.
  EXPECT_ERROR_CONTAINS(ParseCsv("theta,ax,ay\n0,x,2\n0.1,1,2", kColumns, &table),
                        "line 2, column 'ax': 'x' is not a number");
  EXPECT_TRUE(ParseCsv("theta,ax,ay\n0,1,2\n", kColumns, &table).ok());
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
  // A huge cell or a header of binary junk is quoted cut and escaped, on one line.
  const Status huge =
      ParseCsv("theta,ax,ay\n0," + std::string(5 << 20, '9') + "e,1\n", kColumns, &table);
  EXPECT_EQ(huge.message(),
            "line 2, column 'ax': '" + std::string(40, '9') + "...' is not a number");
  EXPECT_ERROR_CONTAINS(ParseCsv(std::string("\x7F"
                                             "ELF\x02\x01\x01\0\0\n",
                                             10),
                                 kColumns, &table),
                        "line 1: the header is '\\x7FELF\\x02\\x01\\x01\\x00\\x00', expected");
}

// ---- .mat files ----------------------------------------------------------------------

MatMatrix Matrix(int rows, int cols, double start = 0.0) {
  MatMatrix matrix;
  matrix.rows = rows;
  matrix.cols = cols;
  for (int i = 0; i < rows * cols; ++i) matrix.values.push_back(start + 0.001 * i);
  return matrix;
}

// The spec's outputs for the angles `tita` (f_x = -g sin(theta), f_y = -g cos(theta)), as a
// datos matrix: the angles then follow the outputs' direction (io/theta_agreement.h).
MatMatrix TiltOutputs(const MatMatrix& tita) {
  MatMatrix datos{tita.rows, 2, std::vector<double>(2 * tita.values.size())};
  for (size_t i = 0; i < tita.values.size(); ++i) {
    datos.values[i] = -9.8 * std::sin(tita.values[i]);
    datos.values[tita.values.size() + i] = -9.8 * std::cos(tita.values[i]);
  }
  return datos;
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
  const std::string path = scratch.File("ensayo.mat");
  ASSERT_TRUE(
      WriteMatFile(path, {{"tita", Matrix(50, 1)}, {"datos", TiltOutputs(Matrix(50, 1))}}).ok());
  CalibrationTest test;
  const Status status = LoadCalibrationTest(path, &test);
  ASSERT_TRUE(status.ok()) << status.message();
  ASSERT_EQ(test.size(), 50);
  EXPECT_EQ(test.theta_rad[3], 0.003);
  EXPECT_EQ(test.measured_x[3], -9.8 * std::sin(0.003));
  EXPECT_EQ(test.measured_y[0], -9.8);  // column 2 starts after 50 values
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
  MatMatrix rows{2, 4, {0.1, -9.8, 0.2, -9.7, 0.3, -9.6, 0.4, -9.5}};
  ASSERT_TRUE(WriteMatFile(path, {{"tita", Matrix(4, 1)}, {"datos", rows}}).ok());
  CalibrationTest test;
  std::vector<std::string> notes;
  ASSERT_TRUE(LoadCalibrationTest(path, &test, {}, &notes).ok());
  EXPECT_EQ(test.measured_x, std::vector<double>({0.1, 0.2, 0.3, 0.4}));
  EXPECT_EQ(test.measured_y, std::vector<double>({-9.8, -9.7, -9.6, -9.5}));
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_EQ(notes[0], path + ": variable 'datos' is 2x4; read as its transpose (4x2, x then y)");
}

TEST(CalibrationTest, RefusesAngleSpansThatLookLikeDegreesUnlessTold) {
  testing::ScratchDir scratch;
  const std::string path = scratch.File("calibration.csv");
  // The spec's outputs (f_x = -g sin(theta), f_y = -g cos(theta)) for the angles in degrees.
  std::string text = "theta,ax,ay\n";
  for (int degrees = 0; degrees <= 350; degrees += 10) {
    text += StringPrintf("%d,%.4f,%.4f\n", degrees, -9.8 * std::sin(degrees * M_PI / 180),
                         -9.8 * std::cos(degrees * M_PI / 180));
  }
  ASSERT_TRUE(WriteFileAtomically(path, text).ok());
  CalibrationTest test;
  EXPECT_ERROR_CONTAINS(LoadCalibrationTest(path, &test),
                        path +
                            ": theta spans 350 (from 0 to 350) over 36 samples, more than two "
                            "turns if it were radians: it looks like degrees; pass "
                            "--theta_unit=deg");
  ASSERT_TRUE(LoadCalibrationTest(path, &test, {AngleUnit::kDegree}).ok());
  EXPECT_DOUBLE_EQ(test.theta_rad[9], M_PI / 2);
  EXPECT_DOUBLE_EQ(test.theta_rad[35], 350 * M_PI / 180);
  // Told radians, the span passes, but the angles do not follow the outputs' direction.
  EXPECT_ERROR_CONTAINS(LoadCalibrationTest(path, &test, {AngleUnit::kRadian}),
                        path +
                            ": theta read as radians does not follow the direction of the "
                            "outputs: agreement R = ");
  // Two full turns in radians are a plausible test and pass.
  ASSERT_TRUE(WriteFileAtomically(path, "theta,ax,ay\n0,0,-9.8\n12.566,0.006,-9.8\n").ok());
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
                        "absent.mat: no such file; check the path");
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

// A 100 Hz logger stamping Unix time: near 1.7e9 s a double resolves 2.4e-7 s, so the steps
// of an exact clock differ by that much, 24 times more than 1e-6 dt. Accepted, with the dt
// the integration takes (estimation/tilt_table/trajectory.cc, joint_estimator.cc: (t_last -
// t_first) / (N - 1)) right to 1e-9 s; a glitch of two samples by 20 us is still refused.
TEST(VehicleRun, AcceptsUnixTimeAndStillFindsAGlitch) {
  testing::ScratchDir scratch;
  const double start_s = 1700000000.0;
  const int count = 6000;
  auto write = [&](int glitch_at, double glitch_s) {
    std::string text = "t,ax,ay\n";
    for (int j = 0; j < count; ++j) {
      const bool late = j == glitch_at || j == glitch_at + 1;
      text += late ? StringPrintf("%.5f", start_s + 0.01 * j + glitch_s)
                   : StringPrintf("%.2f", start_s + 0.01 * j);
      text += ",0.1,-0.2\n";
    }
    return scratch.Write("unix.csv", text);
  };
  const std::string path = write(-10, 0.0);
  VehicleRun run;
  const Status status = LoadVehicleRun(path, &run);
  ASSERT_TRUE(status.ok()) << status.message();
  ASSERT_EQ(run.size(), count);
  const double dt = (run.timestamp_s.back() - run.timestamp_s.front()) / (run.size() - 1);
  EXPECT_NEAR(dt, 0.01, 1e-9);
  // Samples 3001 and 3002 stamped 20 us late: a step of 0.01002 s, then 0.01 s, then 0.00998 s.
  write(3000, 2e-5);
  EXPECT_ERROR_CONTAINS(LoadVehicleRun(path, &run),
                        "t is not uniformly spaced: t(3001) - t(3000) = 0.01002 s, expected dt = "
                        "0.01 s; resample the run");
  // Time so coarse that it cannot resolve the step at all.
  std::vector<double> coarse = {1e15, 1e15 + 0.25, 1e15 + 0.5, 1e15 + 0.75};
  EXPECT_ERROR_CONTAINS(CheckUniformTime(coarse, "t"),
                        "s is resolved to 0.125 s only, too coarse for its step dt = 0.25 s; store "
                        "the time since the start of the run");
}

TEST(VehicleRun, RefusesARunFileCutShort) {
  testing::ScratchDir scratch;
  const std::string path =
      scratch.Write("trajectory.csv", "t,ax,ay\n0,1,1\n0.01,1,1\n0.02,1,1\n0.03,1,0.4");
  VehicleRun run;
  EXPECT_EQ(LoadVehicleRun(path, &run).message(),
            path +
                ": line 5 has no line end: the file looks cut short; copy it again, or end the "
                "line if it is complete");
  EXPECT_EQ(run.size(), 0);
}

// The reader is chosen by the extension in any case; a folder or a pipe is named as such.
TEST(DataFiles, ChoosesTheReaderByExtensionInAnyCaseAndRefusesFoldersAndPipes) {
  testing::ScratchDir scratch;
  VehicleRun run;
  for (const char* name : {"run.CSV", "run.Csv"}) {
    const std::string path = scratch.Write(name, "t,ax,ay\n0,1,1\n0.01,1,1\n0.02,1,1\n");
    const Status status = LoadVehicleRun(path, &run);
    ASSERT_TRUE(status.ok()) << status.message();
    EXPECT_EQ(run.size(), 3);
  }
  EXPECT_TRUE(IsCsvPath("a/B.CSV"));
  EXPECT_FALSE(IsCsvPath("a/csv"));
  const std::string calibration =
      scratch.Write("calibration.CSV", "theta,ax,ay\n0,0,-9.8\n1.5708,-9.8,0\n3.1416,0,9.8\n");
  CalibrationTest test;
  const Status test_status = LoadCalibrationTest(calibration, &test);
  ASSERT_TRUE(test_status.ok()) << test_status.message();
  EXPECT_EQ(test.size(), 3);
  const std::string scenario = scratch.Write(
      "scenario.JSON",
      R"({"initial_position": [0, 0], "initial_velocity": [1, 3], "noise_variance": [0.25, 0.64]})");
  RunConditions conditions;
  EXPECT_TRUE(LoadRunConditions(scenario, &conditions).ok());

  const std::string folder = scratch.File("trajectory.csv");
  ASSERT_EQ(mkdir(folder.c_str(), 0700), 0);
  EXPECT_EQ(LoadVehicleRun(folder, &run).message(),
            folder + ": is a folder, not a CSV file; name the file itself");
  std::vector<Landmark> landmarks;
  EXPECT_ERROR_CONTAINS(LoadLandmarks(folder, &landmarks), "is a folder, not a CSV file");
  const std::string datos = scratch.File("datos.txt");
  ASSERT_EQ(mkdir(datos.c_str(), 0700), 0);
  EXPECT_EQ(LoadRunConditions(datos, &conditions).message(),
            datos + ": is a folder, not a datos.txt file; name the file itself");

  // A pipe (what bash's <(...) names) is refused before it is opened. A writer would feed a
  // valid run to a reader that opened it; the test opens it itself afterwards, without
  // blocking, so that the writer never waits forever.
  const std::string pipe = scratch.File("pipe.csv");
  ASSERT_EQ(mkfifo(pipe.c_str(), 0600), 0);
  std::thread writer([&pipe] {
    const int fd = open(pipe.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0) return;
    const std::string text = "t,ax,ay\n0,1,1\n0.01,1,1\n";
    EXPECT_EQ(write(fd, text.data(), text.size()), static_cast<ssize_t>(text.size()));
    close(fd);
  });
  const Status piped = LoadVehicleRun(pipe, &run);
  const int release = open(pipe.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  writer.join();
  if (release >= 0) close(release);
  EXPECT_EQ(piped.message(),
            pipe + ": is a pipe (FIFO), not a CSV file; save the stream to a file and name that");
}

TEST(RunConditions, RefusesAFileLargerThanAConditionsFileCanBe) {
  testing::ScratchDir scratch;
  const std::string path = scratch.Write(
      "datos.txt", std::string(kMaxConditionsFileBytes, '\n') + "Velocidad inicial = [1 3]\n");
  RunConditions conditions;
  EXPECT_ERROR_CONTAINS(LoadRunConditions(path, &conditions),
                        path +
                            ": the file is 1 MiB, more than the 1 MiB that a datos.txt file "
                            "can sensibly be");
}

TEST(Landmarks, RefusesANameThatIsNotAPrintableLine) {
  testing::ScratchDir scratch;
  std::vector<Landmark> landmarks;
  const std::string path =
      scratch.Write("landmarks.csv", "name,x,y\nA,1,2\n" + std::string(5 << 20, 'B') + ",3,4\n");
  EXPECT_EQ(LoadLandmarks(path, &landmarks).message(),
            path + ": landmark 2's name '" + std::string(40, 'B') +
                "...' (5242880 bytes) is not a name: use at most 100 printable characters, in "
                "UTF-8 (save the file as UTF-8, not Latin-1)");
  scratch.Write("landmarks.csv", "name,x,y\nA,1,2\nB\x1B[31m,3,4\n");
  EXPECT_ERROR_CONTAINS(LoadLandmarks(path, &landmarks), "landmark 2's name 'B\\x1B[31m'");
  EXPECT_TRUE(landmarks.empty());
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
