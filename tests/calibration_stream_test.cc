// The streaming reader of calibration.csv (io/calibration_stream.h): it must read exactly
// what ParseCsv reads, and refuse exactly what it refuses with the same message, wherever the
// reads split the lines; its accumulator must equal the one of the test held in memory; and
// linear_ls, which streams CSV files, skips only the Ceres cross-check above its limit.

#include "io/calibration_stream.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "common/format.h"
#include "estimation/tilt_table/linear_ls.h"
#include "io/course_csv.h"
#include "io/course_data.h"
#include "io/csv_reader.h"
#include "io/mat_file.h"
#include "io/theta_agreement.h"
#include "simulation/simulator.h"
#include "test_support.h"

namespace accelcal {
namespace {

using testing::ScratchDir;

const std::vector<CsvColumn> kColumns = {{"theta"}, {"ax"}, {"ay"}};

void Discard(const CalibrationTest&) {}

// Chunk sizes down to one byte, so that every line is split by a read somewhere, and the
// default.
const std::vector<size_t> kChunkBytes = {1, 2, 3, 7, 64, 4096, size_t{4} << 20};

struct Streamed {
  Status status;
  CalibrationTest test;
  CalibrationStreamStats stats;
  int batches = 0;
};

// `check_theta_agreement` false: the numbers are only parsed, as ParseCsv does, whatever
// they say about the physics.
Streamed Stream(const std::string& path, size_t chunk_bytes, size_t batch_samples = 4096,
                AngleUnit theta_unit = AngleUnit::kRadian, bool check_theta_agreement = true) {
  CalibrationStreamOptions options;
  options.chunk_bytes = chunk_bytes;
  options.batch_samples = batch_samples;
  options.theta_unit = theta_unit;
  options.check_theta_agreement = check_theta_agreement;
  Streamed result;
  result.status = StreamCalibrationCsv(
      path, options,
      [&](const CalibrationTest& batch) {
        EXPECT_LE(batch.theta_rad.size(), batch_samples);
        ++result.batches;
        for (int i = 0; i < batch.size(); ++i) {
          result.test.theta_rad.push_back(batch.theta_rad[i]);
          result.test.measured_x.push_back(batch.measured_x[i]);
          result.test.measured_y.push_back(batch.measured_y[i]);
        }
      },
      &result.stats);
  return result;
}

void ExpectSameAxis(const AxisRegressionAccumulator& a, const AxisRegressionAccumulator& b) {
  EXPECT_EQ(a.count(), b.count());
  EXPECT_EQ(a.MeanForce(), b.MeanForce());
  EXPECT_EQ(a.MeanResponse(), b.MeanResponse());
  EXPECT_EQ(a.CenteredForceForce(), b.CenteredForceForce());
  EXPECT_EQ(a.CenteredForceResponse(), b.CenteredForceResponse());
  EXPECT_EQ(a.CenteredResponseResponse(), b.CenteredResponseResponse());
}

// The same to `tolerance`, relative to the larger of the two.
void ExpectNearAxis(const AxisRegressionAccumulator& a, const AxisRegressionAccumulator& b,
                    double tolerance) {
  auto near = [tolerance](double u, double v) {
    return std::abs(u - v) <= tolerance * std::max(std::abs(u), std::abs(v));
  };
  EXPECT_EQ(a.count(), b.count());
  EXPECT_TRUE(near(a.CenteredForceForce(), b.CenteredForceForce()));
  EXPECT_TRUE(near(a.CenteredForceResponse(), b.CenteredForceResponse()));
  EXPECT_TRUE(near(a.CenteredResponseResponse(), b.CenteredResponseResponse()));
  EXPECT_TRUE(near(a.MeanResponse(), b.MeanResponse()));
}

// A simulated test written at full precision, with what real files carry: a BOM, comments,
// blank lines, CRLF on some lines and blanks around cells. (A last line without its line end
// is refused, as a file cut short: RefusesBadInputWithParseCsvsMessages.)
std::string AwkwardCsv(const CalibrationTest& test) {
  std::string text = "\xEF\xBB\xBF# tilt test, simulated\r\n\r\ntheta , AX,\"ay\"\r\n";
  for (int i = 0; i < test.size(); ++i) {
    if (i % 97 == 0) text += "# a comment between samples\n";
    text += StringPrintf("%.17g,%s%.17g, %.17g", test.theta_rad[i], i % 3 == 0 ? "+" : "",
                         test.measured_x[i], test.measured_y[i]);
    text += i % 2 == 0 ? "\r\n" : "\n";
  }
  return text;
}

// CalibrationAccumulator::AddTest works in blocks (a power of two of samples) whose sums
// depend on where the blocks start. The stream's batches are a larger power of two, so they
// split the test where AddTest's blocks do, and the streamed statistics are the in-memory
// ones bit for bit, wherever the reads split the lines.
TEST(CalibrationStream, StreamedAccumulatorEqualsTheInMemoryOneExactly) {
  TiltSchedule schedule;
  schedule.sample_count = 10001;
  const CalibrationTest test = SimulateTiltTest(schedule, CourseTableOneTruth(), 5);
  ScratchDir scratch;
  const std::string path = scratch.Write("calibration.csv", AwkwardCsv(test));

  CalibrationAccumulator in_memory(9.8);
  in_memory.AddTest(test);
  LinearLsOptions options;
  options.noise_variance_x = 0.25;
  options.noise_variance_y = 0.64;
  BaselineFit in_memory_fit;
  ASSERT_TRUE(SolveLinearLs(in_memory, options, &in_memory_fit).ok());

  for (const size_t chunk_bytes : kChunkBytes) {
    for (const size_t batch_samples : {CalibrationStreamOptions().batch_samples, size_t{8192}}) {
      SCOPED_TRACE("chunk " + std::to_string(chunk_bytes) + " B, batch " +
                   std::to_string(batch_samples));
      CalibrationStreamOptions stream_options;
      stream_options.chunk_bytes = chunk_bytes;
      stream_options.batch_samples = batch_samples;
      CalibrationAccumulator streamed(9.8);
      CalibrationStreamStats stats;
      const Status status = StreamCalibrationCsv(
          path, stream_options, [&](const CalibrationTest& batch) { streamed.AddTest(batch); },
          &stats);
      ASSERT_TRUE(status.ok()) << status.message();
      ExpectSameAxis(streamed.x(), in_memory.x());
      ExpectSameAxis(streamed.y(), in_memory.y());
      EXPECT_EQ(streamed.theta_min_rad(), in_memory.theta_min_rad());
      EXPECT_EQ(streamed.theta_max_rad(), in_memory.theta_max_rad());
      BaselineFit streamed_fit;
      ASSERT_TRUE(SolveLinearLs(streamed, options, &streamed_fit).ok());
      EXPECT_EQ(streamed_fit.parameters, in_memory_fit.parameters);
      EXPECT_EQ(streamed_fit.covariance, in_memory_fit.covariance);
      EXPECT_EQ(stats.samples, test.size());
      EXPECT_EQ(stats.theta_min_rad, in_memory.theta_min_rad());
      EXPECT_EQ(stats.theta_max_rad, in_memory.theta_max_rad());
    }
  }
  // Batches of any other size give the same statistics to rounding.
  for (const size_t batch_samples : {size_t{1}, size_t{5}, size_t{1000}}) {
    SCOPED_TRACE("batch " + std::to_string(batch_samples));
    CalibrationStreamOptions stream_options;
    stream_options.chunk_bytes = 7;
    stream_options.batch_samples = batch_samples;
    CalibrationAccumulator streamed(9.8);
    ASSERT_TRUE(StreamCalibrationCsv(
                    path, stream_options,
                    [&](const CalibrationTest& batch) { streamed.AddTest(batch); }, nullptr)
                    .ok());
    ExpectNearAxis(streamed.x(), in_memory.x(), 1e-12);
    ExpectNearAxis(streamed.y(), in_memory.y(), 1e-12);
  }
}

TEST(CalibrationStream, ReadsTheSamplesParseCsvReads) {
  TiltSchedule schedule;
  schedule.sample_count = 500;
  const CalibrationTest test = SimulateTiltTest(schedule, CourseTableOneTruth(), 6);
  ScratchDir scratch;
  const std::string text = AwkwardCsv(test);
  const std::string path = scratch.Write("calibration.csv", text);
  CsvTable table;
  ASSERT_TRUE(ParseCsv(text, kColumns, &table).ok());
  for (const size_t chunk_bytes : kChunkBytes) {
    const Streamed streamed = Stream(path, chunk_bytes, 5);
    ASSERT_TRUE(streamed.status.ok()) << streamed.status.message();
    EXPECT_EQ(streamed.test.theta_rad, table.numbers[0]);
    EXPECT_EQ(streamed.test.measured_x, table.numbers[1]);
    EXPECT_EQ(streamed.test.measured_y, table.numbers[2]);
    EXPECT_EQ(streamed.test.theta_rad, test.theta_rad);  // %.17g round-trips
    EXPECT_EQ(streamed.batches, 100);
    EXPECT_EQ(streamed.stats.bytes, static_cast<long long>(text.size()));
    EXPECT_EQ(streamed.stats.lines, 3 + 500 + 6);  // BOM comment, blank, header; 6 comments
  }
}

TEST(CalibrationStream, ReadsCommentsBlankLinesCrlfAndBom) {
  ScratchDir scratch;
  const std::string path = scratch.Write(
      "c.csv", "\xEF\xBB\xBF# a comment\r\nTheta, ax ,ay\r\n0,1.5,-2e-3\r\n\r\n0.1,+2,3\r\n");
  for (const size_t chunk_bytes : kChunkBytes) {
    const Streamed streamed = Stream(path, chunk_bytes, 4096, AngleUnit::kRadian, false);
    ASSERT_TRUE(streamed.status.ok()) << streamed.status.message();
    EXPECT_EQ(streamed.test.theta_rad, std::vector<double>({0.0, 0.1}));
    EXPECT_EQ(streamed.test.measured_x, std::vector<double>({1.5, 2.0}));
    EXPECT_EQ(streamed.test.measured_y, std::vector<double>({-2e-3, 3.0}));
  }
}

// Every refusal is ParseCsv's, word for word, after the file name.
TEST(CalibrationStream, RefusesBadInputWithParseCsvsMessages) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"theta,ax\n0,1\n", "line 1: the header is 'theta,ax', expected 'theta,ax,ay'"},
      {"theta,ax,ay\n0,1,2\n0,1,2,3\n", "line 3: 4 fields, expected 3 (theta,ax,ay)"},
      {"theta,ax,ay\n0,1,2\n0,1\n", "line 3: 2 fields, expected 3"},
      {"theta,ax,ay\n0,1,5\n0,1,5,2\n", "decimal commas"},
      {"theta,ax,ay\r\n0,1,2\r\n0,abc,2\r\n", "line 3, column 'ax': 'abc' is not a number"},
      {"theta,ax,ay\n0,1,NaN\n", "line 2, column 'ay': 'NaN' is not a finite number"},
      {"theta,ax,ay\n0,inf,1\n", "not a finite number"},
      // A number, but beyond a double (issue 35, 6): not finite, rather than "not a number".
      {"theta,ax,ay\n0,1,-1e999\n",
       "line 2, column 'ay': '-1e999' is not a finite number (beyond a double's range"},
      {"theta,ax,ay\n0,1e-999,1\n", "'1e-999' is too close to zero for a double"},
      {"theta,ax,ay\n0,,1\n", "line 2, column 'ax': '' is not a number"},
      {"theta,ax,ay\n# only a comment\n\n", "no data rows after the header"},
      {"theta;ax;ay\n0;1;2\n", "export it with ',' between fields"},
      {"\n# nothing\n", "the file is empty; expected the header 'theta,ax,ay'"},
      {"", "the file is empty"},
      // Cut short by an interrupted copy: "-9.7" of "-9.7012", or a whole line lost.
      {"theta,ax,ay\n0,-0.1,-9.8\n0.1,-0.9,-9.7",
       "line 3 has no line end: the file looks cut short; copy it again, or end the line if it "
       "is complete"},
      {"theta,ax,ay\r\n0,-0.1,-9.8\r\n# end", "line 3 has no line end"},
      {"theta,ax,ay", "line 1 has no line end"},
      // Echoed cells are cut and their control characters escaped: one readable line.
      {"theta,ax,ay\n0," + std::string(100000, '7') + "x,1\n",
       "line 2, column 'ax': '7777777777777777777777777777777777777777...' is not a number"},
      {"theta,ax,ay\n0,\x01\x1B[2J\xFF,1\n",
       "line 2, column 'ax': '\\x01\\x1B[2J\\xFF' is not a number"},
  };
  ScratchDir scratch;
  for (const auto& [text, fragment] : cases) {
    SCOPED_TRACE(text);
    CsvTable table;
    const Status expected = ParseCsv(text, kColumns, &table);
    ASSERT_FALSE(expected.ok());
    ASSERT_NE(expected.message().find(fragment), std::string::npos) << expected.message();
    const std::string path = scratch.Write("bad.csv", text);
    for (const size_t chunk_bytes : kChunkBytes) {
      const Streamed streamed = Stream(path, chunk_bytes);
      EXPECT_FALSE(streamed.status.ok());
      EXPECT_EQ(streamed.status.message(), path + ": " + expected.message());
    }
  }
}

// A differential check over many small mutations of valid files (the cases a fuzzer finds
// first): the stream and ParseCsv agree on success, values and every message.
TEST(CalibrationStream, AgreesWithParseCsvOnMutatedFiles) {
  const std::vector<std::string> seeds = {
      "theta,ax,ay\n0,1.5,-2e-3\n0.1,+2,3\n",
      "\xEF\xBB\xBF# c\r\nTheta, ax ,ay\r\n0,1.5,-2e-3\r\n\r\n0.1,+2,3",
      "\"theta\",\"ax\",\"ay\"\n\" 1\",\"+2\",\"-3e5\"\n# end\n",
  };
  const std::string alphabet = ",,\r\n\n#;+-.e0123456789 \t\"nai\xEF\xBB\xBF";
  std::mt19937_64 random(7);
  ScratchDir scratch;
  const std::string path = scratch.File("mutated.csv");
  int parsed = 0;
  for (int round = 0; round < 2000; ++round) {
    std::string text = seeds[random() % seeds.size()];
    for (int edit = 1 + random() % 4; edit > 0; --edit) {
      const size_t position = random() % (text.size() + 1);
      const char c = alphabet[random() % alphabet.size()];
      switch (random() % 3) {
        case 0:
          text.insert(position, 1, c);
          break;
        case 1:
          if (position < text.size()) text.erase(position, 1);
          break;
        default:
          if (position < text.size()) text[position] = c;
      }
    }
    scratch.Write("mutated.csv", text);
    CsvTable table;
    const Status expected = ParseCsv(text, kColumns, &table);
    const Streamed streamed =
        Stream(path, 1 + random() % 16, 1 + random() % 3, AngleUnit::kRadian, false);
    ASSERT_EQ(streamed.status.ok(), expected.ok()) << text << "\n" << streamed.status.message();
    if (!expected.ok()) {
      ASSERT_EQ(streamed.status.message(), path + ": " + expected.message()) << text;
      continue;
    }
    ++parsed;
    ASSERT_EQ(streamed.test.theta_rad, table.numbers[0]) << text;
    ASSERT_EQ(streamed.test.measured_x, table.numbers[1]) << text;
    ASSERT_EQ(streamed.test.measured_y, table.numbers[2]) << text;
  }
  EXPECT_GT(parsed, 100);  // the mutations leave enough valid files to compare values
}

TEST(CalibrationStream, AppliesTheAngleUnitAsTheLoaderDoes) {
  ScratchDir scratch;
  std::string text = "theta,ax,ay\n";
  for (int degrees = 0; degrees <= 350; degrees += 10) {
    // The spec's outputs for the angle in degrees: f_x = -g sin(theta), f_y = -g cos(theta).
    text += StringPrintf("%d,%.6f,%.6f\n", degrees, -9.8 * std::sin(degrees * M_PI / 180),
                         -9.8 * std::cos(degrees * M_PI / 180));
  }
  const std::string path = scratch.Write("degrees.csv", text);
  const Streamed automatic = Stream(path, 7, 4, AngleUnit::kAuto);
  EXPECT_FALSE(automatic.status.ok());
  EXPECT_EQ(automatic.status.message(),
            path +
                ": theta spans 350 (from 0 to 350) over 36 samples, more than two turns if it "
                "were radians: it looks like degrees; pass --theta_unit=deg (or "
                "--theta_unit=rad if the table really turned that far)");
  const Streamed degrees = Stream(path, 7, 4, AngleUnit::kDegree);
  ASSERT_TRUE(degrees.status.ok()) << degrees.status.message();
  ASSERT_EQ(degrees.test.size(), 36);
  for (int i = 0; i < 36; ++i) {
    double expected = 10.0 * i;
    expected *= M_PI / 180.0;
    EXPECT_EQ(degrees.test.theta_rad[i], expected);
  }
  // Read as radians, the angles do not follow the outputs' direction (R near 0).
  const Streamed radians = Stream(path, 7, 4, AngleUnit::kRadian);
  EXPECT_NE(radians.status.message().find("theta read as radians does not follow the direction "
                                          "of the outputs: agreement R = "),
            std::string::npos)
      << radians.status.message();
  EXPECT_LT(std::abs(radians.stats.theta_agreement), 0.2);
  EXPECT_GT(degrees.stats.theta_agreement, 0.999);
  // The loader reads a CSV test through the stream: the same message for the same file.
  CalibrationTest loaded;
  EXPECT_EQ(LoadCalibrationTest(path, &loaded).message(), automatic.status.message());
}

TEST(CalibrationStream, RefusesALineLongerThanTheLimitWhereverTheReadsSplitIt) {
  ScratchDir scratch;
  const std::string path =
      scratch.Write("long.csv", "theta,ax,ay\n0,1,2\n0,1," + std::string(100, '2') + "\n0,1,2\n");
  for (const size_t chunk_bytes : {size_t{3}, size_t{50}, size_t{4096}}) {
    CalibrationStreamOptions options;
    options.chunk_bytes = chunk_bytes;
    options.max_line_bytes = 64;
    const Status status = StreamCalibrationCsv(path, options, Discard, nullptr);
    EXPECT_EQ(status.message(), path +
                                    ": line 3 is longer than 64 bytes, while a row of theta,ax,ay "
                                    "is a few dozen; is this a calibration CSV file?");
  }
  // Lines ended by '\r' alone are one long line: say so.
  std::string old_mac = "theta,ax,ay\r";
  for (int i = 0; i < 20; ++i) old_mac += "0,1,2\r";
  const std::string mac_path = scratch.Write("mac.csv", old_mac);
  CalibrationStreamOptions options;
  options.max_line_bytes = 64;
  EXPECT_NE(StreamCalibrationCsv(mac_path, options, Discard, nullptr)
                .message()
                .find("line 1 is longer than 64 bytes, while a row of theta,ax,ay is a few dozen; "
                      "its lines end in '\\r' alone"),
            std::string::npos);
}

TEST(CalibrationStream, SaysWhenTheFileCannotBeOpened) {
  ScratchDir scratch;
  const std::string path = scratch.File("absent.csv");
  EXPECT_EQ(StreamCalibrationCsv(path, {}, Discard, nullptr).message(),
            path + ": no such file; check the path");
}

// A folder is not "an empty file", and a pipe (bash's <(...), /dev/fd/63) is refused by name
// before it is opened: CheckInputFile, as every reader.
TEST(CalibrationStream, RefusesAFolderAndAPipeByName) {
  ScratchDir scratch;
  const std::string folder = scratch.File("folder.csv");
  ASSERT_EQ(mkdir(folder.c_str(), 0700), 0);
  EXPECT_EQ(StreamCalibrationCsv(folder, {}, Discard, nullptr).message(),
            folder + ": is a folder, not a CSV file; name the file itself");
  const std::string pipe = scratch.File("pipe.csv");
  ASSERT_EQ(mkfifo(pipe.c_str(), 0600), 0);
  // A writer that would feed a valid test to a reader that opens the pipe; the test opens it
  // itself afterwards (without blocking), so the writer never waits forever.
  std::thread writer([&pipe] {
    const int fd = open(pipe.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0) return;
    const std::string text = "theta,ax,ay\n0,-0.1,-9.8\n1.5,-9.8,-0.6\n3,-1.4,9.7\n";
    EXPECT_EQ(write(fd, text.data(), text.size()), static_cast<ssize_t>(text.size()));
    close(fd);
  });
  const Status status = StreamCalibrationCsv(pipe, {}, Discard, nullptr);
  const int release = open(pipe.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  writer.join();
  if (release >= 0) close(release);
  ASSERT_EQ(status.message(), pipe +
                                  ": is a pipe (FIFO), not a CSV file; save the stream to a file "
                                  "and name that");
  // Refused before it is opened, so no writer is needed.
  CalibrationTest test;
  EXPECT_EQ(LoadCalibrationTest(pipe, &test).message(), status.message());
}

// Degrees over a small span: 80 to 92 degrees spans 12 < 4 pi, so only the physics tells.
// The stream, the loader (which reads CSV through the stream) and the .mat loader agree.
TEST(CalibrationStream, RefusesDegreesOverASmallSpanByThePhysics) {
  TiltSchedule schedule;
  schedule.sample_count = 1201;
  schedule.theta_begin_rad = 80.0 * M_PI / 180.0;
  schedule.theta_end_rad = 92.0 * M_PI / 180.0;
  CalibrationTest test = SimulateTiltTest(schedule, CourseTableOneTruth(), 3);
  for (double& theta : test.theta_rad) theta *= 180.0 / M_PI;  // written as degrees
  ScratchDir scratch;
  const std::string path = scratch.File("calibration.csv");
  ASSERT_TRUE(WriteCalibrationCsv(path, test).ok());
  const std::string expected_start =
      path +
      ": read as radians, theta does not follow the direction of the outputs (agreement R = ";
  const std::string expected_end =
      "; R = mean cos(atan2(-ax, -ay) - theta), 1 when f_x = -g sin(theta), f_y = -g "
      "cos(theta)): theta looks like degrees; pass --theta_unit=deg";
  std::string first_message;
  for (const size_t chunk_bytes : kChunkBytes) {
    const Streamed automatic = Stream(path, chunk_bytes, 4096, AngleUnit::kAuto);
    ASSERT_FALSE(automatic.status.ok());
    const std::string& message = automatic.status.message();
    EXPECT_EQ(message.substr(0, expected_start.size()), expected_start) << message;
    EXPECT_NE(message.find(expected_end), std::string::npos) << message;
    EXPECT_NE(message.find("but read as degrees it does (R = 1.00"), std::string::npos) << message;
    EXPECT_LT(std::abs(automatic.stats.theta_agreement), 0.2);
    EXPECT_GT(automatic.stats.theta_agreement_as_degrees, 0.99);
    if (first_message.empty()) first_message = message;
    EXPECT_EQ(message, first_message);
    const Streamed told = Stream(path, chunk_bytes, 4096, AngleUnit::kDegree);
    ASSERT_TRUE(told.status.ok()) << told.status.message();
    EXPECT_EQ(told.test.size(), 1201);
    const Streamed radians = Stream(path, chunk_bytes, 4096, AngleUnit::kRadian);
    EXPECT_NE(radians.status.message().find("check the angle unit (--theta_unit), the column "
                                            "order (theta, ax, ay) and the axes' signs"),
              std::string::npos)
        << radians.status.message();
  }
  CalibrationTest loaded;
  EXPECT_EQ(LoadCalibrationTest(path, &loaded).message(), first_message);
  ASSERT_TRUE(LoadCalibrationTest(path, &loaded, {AngleUnit::kDegree}).ok());
  EXPECT_NEAR(loaded.theta_rad.back(), 92.0 * M_PI / 180.0, 1e-12);
  // The same test in a .mat file: the same refusal, from the in-memory path.
  const std::string mat_path = scratch.File("ensayo.mat");
  MatMatrix tita{test.size(), 1, test.theta_rad};
  MatMatrix datos{test.size(), 2, test.measured_x};
  datos.values.insert(datos.values.end(), test.measured_y.begin(), test.measured_y.end());
  ASSERT_TRUE(WriteMatFile(mat_path, {{"tita", tita}, {"datos", datos}}).ok());
  const Status from_mat = LoadCalibrationTest(mat_path, &loaded);
  ASSERT_FALSE(from_mat.ok());
  EXPECT_EQ(from_mat.message().substr(mat_path.size()),
            first_message.substr(path.size()));  // the same R, to the printed digits
  EXPECT_TRUE(LoadCalibrationTest(mat_path, &loaded, {AngleUnit::kDegree}).ok());
}

// ---- linear_ls streams a CSV test --------------------------------------------------------

constexpr char kDatos[] =
    "Posici\xC3\xB3n inicial = [0 0]\nVelocidad inicial = [1 3]\n"
    "varianza del ruido de los aceler\xC3\xB3metros = [0.25 0.64]\n";

TEST(LinearLsStreaming, SkipsOnlyTheCeresCheckAboveTheLimit) {
  TiltSchedule schedule;
  schedule.sample_count = 2000;
  const CalibrationTest test = SimulateTiltTest(schedule, CourseTableOneTruth(), 9);
  ScratchDir scratch;
  ASSERT_TRUE(WriteCalibrationCsv(scratch.File("calibration.csv"), test).ok());
  scratch.Write("datos.txt", kDatos);
  const std::string files = "--calibration_file='" + scratch.File("calibration.csv") +
                            "' --conditions_file='" + scratch.File("datos.txt") + "'";

  const testing::CommandResult with_ceres =
      testing::RunBinary("linear_ls", files + " --json='" + scratch.File("with.json") + "'");
  ASSERT_EQ(with_ceres.exit_status, 0) << with_ceres.stderr_text;
  const testing::CommandResult without_ceres =
      testing::RunBinary("linear_ls", files + " --ceres_max_samples=1999 --json='" +
                                          scratch.File("without.json") + "'");
  ASSERT_EQ(without_ceres.exit_status, 0) << without_ceres.stderr_text;
  EXPECT_EQ(without_ceres.stderr_text, "");

  // Everything before the solvers' comparison is the same, byte for byte.
  const std::string marker = "\n  closed form vs Ceres:";
  const size_t ceres_part = with_ceres.stdout_text.find(marker);
  ASSERT_NE(ceres_part, std::string::npos) << with_ceres.stdout_text;
  EXPECT_EQ(without_ceres.stdout_text.find(marker), std::string::npos);
  EXPECT_EQ(without_ceres.stdout_text,
            with_ceres.stdout_text.substr(0, ceres_part) +
                "\n  closed form only; Ceres skipped: 2000 samples, more than "
                "--ceres_max_samples=1999 (it would hold them all with their residuals in "
                "memory)\n");

  const nlohmann::json with = nlohmann::json::parse(testing::ReadText(scratch.File("with.json")));
  const nlohmann::json without =
      nlohmann::json::parse(testing::ReadText(scratch.File("without.json")));
  EXPECT_EQ(without["parameters"], with["parameters"]);
  EXPECT_EQ(without["covariance"], with["covariance"]);
  EXPECT_EQ(without["n_samples"].get<int>(), 2000);
  EXPECT_TRUE(without["solvers"]["ceres"].is_null());
  EXPECT_TRUE(without["solvers"]["max_relative_difference"].is_null());
  EXPECT_NE(without["solvers"]["ceres_skipped"].get<std::string>().find("2000 samples"),
            std::string::npos);
  EXPECT_TRUE(with["solvers"]["ceres"].is_object());
  EXPECT_TRUE(with["solvers"]["ceres_skipped"].is_null());
}

}  // namespace
}  // namespace accelcal
