// apply with a triad's calibration that has a gyroscope section (io/calibration_file.h), end to
// end: the gyroscope columns corrected as w = T K (u - b) with the sigma and correlations of
// J C J^T, both computed here independently of the library (tests/test_support.h); either
// without the other said and the accelerometer corrected alone; a damaged section refused in
// one line with nothing written.

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "common/format.h"
#include "gyroscope_calibration_example.h"
#include "io/calibration_file.h"
#include "test_support.h"

namespace accelcal {
namespace {

using testing::ExpectBadInputContract;
using testing::RunBinary;

constexpr char kGyroscopeHeader[] =
    "gx_radps,gy_radps,gz_radps,sigma_gx_radps,sigma_gy_radps,sigma_gz_radps,corr_gxy,corr_gxz,"
    "corr_gyz";

// The raw gyroscope output of sample j: counts about the offset, some thousands of counts
// (a fraction of a rad/s to a few rad/s), not integers.
Eigen::Vector3d GyroscopeOutput(int j) {
  return Eigen::Vector3d(31.5 + 4000.0 * std::sin(0.7 * j) + 0.25,
                         -12.25 + 9000.0 * std::cos(0.3 * j) - 0.125,
                         7.0 - 15000.0 * std::sin(0.11 * j + 0.2) + 0.375);
}

// A log of `samples` at 100 Hz: the accelerometer at rest in turning directions (1 g of the
// example triad's 415 counts per m/s^2 about its offsets), and the gyroscope's columns when
// `header` names them.
std::string Log(const std::string& header, int samples) {
  std::string text = header + "\n";
  const bool gyroscope =
      header.find("gx") != std::string::npos || header.find("gyr_x") != std::string::npos;
  for (int j = 0; j < samples; ++j) {
    const double angle = 0.2 * j;
    const double force[3] = {9.81 * std::sin(angle) * 0.6, 9.81 * std::cos(angle) * 0.6,
                             9.81 * 0.8};
    const double offset[3] = {32808.0, 32743.0, 32778.0};
    text += RoundTripDouble(0.01 * (j + 1));
    for (int k = 0; k < 3; ++k) text += "," + RoundTripDouble(offset[k] + 415.0 * force[k]);
    if (gyroscope) {
      const Eigen::Vector3d u = GyroscopeOutput(j);
      for (int k = 0; k < 3; ++k) text += "," + RoundTripDouble(u[k]);
    }
    text += "\n";
  }
  return text;
}

struct Csv {
  std::vector<std::string> comments;
  std::vector<std::string> header;
  std::vector<std::map<std::string, double>> rows;
};

Csv ReadCsv(const std::string& path) {
  Csv csv;
  std::stringstream lines(testing::ReadText(path));
  for (std::string line; std::getline(lines, line);) {
    if (!line.empty() && line[0] == '#') {
      csv.comments.push_back(line);
      continue;
    }
    std::vector<std::string> fields;
    std::stringstream row(line);
    for (std::string field; std::getline(row, field, ',');) fields.push_back(field);
    if (csv.header.empty()) {
      csv.header = fields;
      continue;
    }
    EXPECT_EQ(fields.size(), csv.header.size()) << line;
    std::map<std::string, double> values;
    for (size_t i = 0; i < fields.size() && i < csv.header.size(); ++i)
      values[csv.header[i]] = std::stod(fields[i]);
    csv.rows.push_back(values);
  }
  return csv;
}

std::string Joined(const std::vector<std::string>& fields) {
  std::string text;
  for (const std::string& field : fields) text += (text.empty() ? "" : ",") + field;
  return text;
}

bool AnyContains(const std::vector<std::string>& lines, const std::string& fragment) {
  for (const std::string& line : lines) {
    if (line.find(fragment) != std::string::npos) return true;
  }
  return false;
}

std::string WriteCalibration(const testing::ScratchDir& scratch, const CalibrationRecord& record,
                             const std::string& name = "cal.json") {
  return scratch.Write(name, CalibrationJson(record).dump(2) + "\n");
}

// Each corrected rate is T K (u - b) of its row's output, to 1e-9; its sigma the square root of
// J C J^T's diagonal to 1e-6 relative (apply writes 6 digits); its correlations likewise.
TEST(ApplyGyroscopeCli, CorrectsTheGyroscopeColumnsWithTheCalibrationsSigma) {
  testing::ScratchDir scratch;
  const std::string cal = WriteCalibration(scratch, testing::ExampleTriadRecordWithGyroscope());
  constexpr int kSamples = 40;
  const std::string in = scratch.Write("run.csv", Log("t_s,ax,ay,az,gx,gy,gz", kSamples));
  const std::string out = scratch.File("corrected.csv");
  const testing::CommandResult applied =
      RunBinary("apply", "--calibration=" + cal + " --in=" + in + " --out=" + out);
  ASSERT_EQ(applied.exit_status, 0) << applied.stderr_text;
  EXPECT_EQ(applied.stderr_text, "");
  EXPECT_NE(applied.stdout_text.find(
                "first sample  gyroscope output (31.75, 8987.625, -2972.665) count -> ("),
            std::string::npos)
      << applied.stdout_text;

  const Csv csv = ReadCsv(out);
  EXPECT_EQ(Joined(csv.header),
            std::string("t_s,ax_mps2,ay_mps2,az_mps2,sigma_ax_mps2,sigma_ay_mps2,sigma_az_mps2,"
                        "corr_xy,corr_xz,corr_yz,") +
                kGyroscopeHeader);
  EXPECT_TRUE(AnyContains(csv.comments, "# gyroscope: g*_radps = T K (u - b)"));
  EXPECT_TRUE(AnyContains(csv.comments,
                          "in count; sigma_g*_radps and corr_g*: the calibration's "
                          "uncertainty"));
  EXPECT_TRUE(AnyContains(csv.comments, "not the gyroscope's white noise"));
  ASSERT_EQ(csv.rows.size(), static_cast<size_t>(kSamples));

  Eigen::VectorXd values(kGyroscopeCalibrationParameterCount);
  const GyroscopeParameters parameters = testing::ExampleGyroscopeParameters();
  const GyroscopeOffset offset = testing::ExampleGyroscopeOffset();
  for (int p = 0; p < kGyroscopeParameterCount; ++p) values[p] = parameters[p];
  for (int k = 0; k < 3; ++k) values[kGyroscopeCalibrationOffsetX + k] = offset[k];
  const Eigen::MatrixXd covariance = testing::ExampleGyroscopeCovariance();
  const char* axes[3] = {"x", "y", "z"};
  for (int j = 0; j < kSamples; ++j) {
    SCOPED_TRACE(j);
    const std::map<std::string, double>& row = csv.rows[j];
    const Eigen::Vector3d u = GyroscopeOutput(j);
    const Eigen::Vector3d rate = testing::PlainGyroscopeRate(values, u);
    const Eigen::Matrix3d rate_covariance =
        testing::PlainGyroscopeRateCovariance(values, covariance, u);
    for (int k = 0; k < 3; ++k) {
      const double got = row.at(std::string("g") + axes[k] + "_radps");
      EXPECT_NEAR(got, rate[k], 1e-9 * std::max(1.0, std::abs(rate[k]))) << axes[k];
      const double sigma = std::sqrt(rate_covariance(k, k));
      EXPECT_NEAR(row.at(std::string("sigma_g") + axes[k] + "_radps") / sigma, 1.0, 1e-6)
          << axes[k];
    }
    const char* pairs[3][2] = {{"xy", "01"}, {"xz", "02"}, {"yz", "12"}};
    for (const auto& pair : pairs) {
      const int a = pair[1][0] - '0', b = pair[1][1] - '0';
      const double correlation =
          rate_covariance(a, b) / std::sqrt(rate_covariance(a, a) * rate_covariance(b, b));
      EXPECT_NEAR(row.at(std::string("corr_g") + pair[0]), correlation, 1e-6) << pair[0];
    }
  }
}

// A gyroscope section whose only effect term is a time offset (session-only: the two streams'
// alignment belongs to the logging chain): apply corrects the rates as the 12 parameters do, and
// says on stderr and in a '#' line that the term is carried and not applied, and why.
TEST(ApplyGyroscopeCli, LeavesASessionOnlyTimeOffsetOutAndSaysSo) {
  constexpr int kTimeOffset = GyroscopeEffectFirstOf<GyroscopeTimeOffsetEffect>();
  CalibrationRecord record = testing::ExampleTriadRecordWithGyroscope();
  GyroscopeEffectCoefficients values{};
  values[kTimeOffset] = 3e-3;
  testing::AddExampleGyroscopeTerms({kTimeOffset}, values, {1e-8}, &record);
  testing::ScratchDir scratch;
  const std::string cal = WriteCalibration(scratch, record);
  constexpr int kSamples = 10;
  const std::string in = scratch.Write("run.csv", Log("t_s,ax,ay,az,gx,gy,gz", kSamples));
  const std::string out = scratch.File("corrected.csv");
  const testing::CommandResult applied =
      RunBinary("apply", "--calibration=" + cal + " --in=" + in + " --out=" + out);
  ASSERT_EQ(applied.exit_status, 0) << applied.stderr_text;
  const std::string said =
      "the calibration's effect terms gyroscope_time_offset are not applied: they belong to the "
      "session calibrated (the two streams' alignment belongs to the logging chain";
  EXPECT_NE(applied.stderr_text.find("apply: note: gyroscope: " + said), std::string::npos)
      << applied.stderr_text;
  const Csv csv = ReadCsv(out);
  EXPECT_TRUE(AnyContains(csv.comments, "# gyroscope: " + said)) << Joined(csv.comments);
  ASSERT_EQ(csv.rows.size(), static_cast<size_t>(kSamples));
  Eigen::VectorXd twelve(kGyroscopeCalibrationParameterCount);
  const GyroscopeParameters parameters = testing::ExampleGyroscopeParameters();
  const GyroscopeOffset offset = testing::ExampleGyroscopeOffset();
  for (int p = 0; p < kGyroscopeParameterCount; ++p) twelve[p] = parameters[p];
  for (int k = 0; k < 3; ++k) twelve[kGyroscopeCalibrationOffsetX + k] = offset[k];
  for (int j = 0; j < kSamples; ++j) {
    const Eigen::Vector3d rate = testing::PlainGyroscopeRate(twelve, GyroscopeOutput(j));
    EXPECT_NEAR(csv.rows[j].at("gx_radps"), rate[0], 1e-9 * std::max(1.0, std::abs(rate[0])));
    EXPECT_NEAR(csv.rows[j].at("gz_radps"), rate[2], 1e-9 * std::max(1.0, std::abs(rate[2])));
  }
}

// apply with `record` on a log of `header`: the accelerometer corrected alone, and `note` said
// on stderr and in a '#' line.
void ExpectAccelerometerOnly(const CalibrationRecord& record, const std::string& header,
                             const std::string& note) {
  testing::ScratchDir scratch;
  const std::string cal = WriteCalibration(scratch, record);
  const std::string in = scratch.Write("run.csv", Log(header, 20));
  const std::string out = scratch.File("corrected.csv");
  const testing::CommandResult applied =
      RunBinary("apply", "--calibration=" + cal + " --in=" + in + " --out=" + out);
  ASSERT_EQ(applied.exit_status, 0) << applied.stderr_text;
  EXPECT_NE(applied.stderr_text.find("apply: note: " + note), std::string::npos)
      << applied.stderr_text;
  const Csv csv = ReadCsv(out);
  EXPECT_EQ(csv.header.size(), 10u) << Joined(csv.header);
  EXPECT_TRUE(AnyContains(csv.comments, "# gyroscope: " + note));
  EXPECT_EQ(csv.rows.size(), 20u);
}

// A section without gyroscope columns: the section said unused.
TEST(ApplyGyroscopeCli, ASectionWithoutGyroscopeColumnsIsSaidUnused) {
  ExpectAccelerometerOnly(testing::ExampleTriadRecordWithGyroscope(), "t_s,ax,ay,az",
                          "the calibration's gyroscope section was not used: the log has no "
                          "gyroscope columns");
}

// Gyroscope columns without a section: the columns said not corrected.
TEST(ApplyGyroscopeCli, GyroscopeColumnsWithoutASectionAreSaidNotCorrected) {
  ExpectAccelerometerOnly(testing::ExampleTriadRecord(), "t_s,ax,ay,az,gx,gy,gz",
                          "the log's gyroscope columns were not corrected: the calibration has no "
                          "gyroscope section");
}

// A damaged section, or columns that state another unit than the section's: exit status 2,
// one line naming the file and the key, and no output.
TEST(ApplyGyroscopeCli, RefusesADamagedSectionInOneLineAndWritesNothing) {
  testing::ScratchDir scratch;
  const nlohmann::json good = CalibrationJson(testing::ExampleTriadRecordWithGyroscope());
  const std::string in = scratch.Write("run.csv", Log("t_s,ax,ay,az,gx,gy,gz", 20));
  const std::string out = scratch.File("corrected.csv");
  using Json = nlohmann::json;
  struct Damage {
    const char* what;
    std::function<void(Json*)> damage;
    const char* expected;  // after "FILE: "
    const char* also;      // further on in the line
  };
  const double variance = good["gyroscope"]["covariance"][6][6].get<double>();
  const double c = 2.0 * std::sqrt(variance * good["gyroscope"]["covariance"][7][7].get<double>());
  const Damage damages[] = {
      {"missing parameter",
       [](Json* j) { (*j)["gyroscope"]["parameters"].erase("gyroscope_gain_y"); },
       "the key \"gyroscope/parameters/gyroscope_gain_y\" is missing", ""},
      {"wrong unit", [](Json* j) { (*j)["gyroscope"]["units"]["gyroscope_offset_x"] = "deg/s"; },
       "gyroscope/units/gyroscope_offset_x must be \"count\"", ""},
      {"asymmetric covariance", [c](Json* j) { (*j)["gyroscope"]["covariance"][6][7] = c; },
       "gyroscope/covariance is not symmetric (gyroscope_gain_y, gyroscope_gain_x)", ""},
      {"not positive semi-definite",
       [c](Json* j) {
         (*j)["gyroscope"]["covariance"][6][7] = c;
         (*j)["gyroscope"]["covariance"][7][6] = c;
       },
       "gyroscope/covariance is not positive semi-definite", ""},
      {"stddev contradicting the covariance",
       [variance](Json* j) {
         (*j)["gyroscope"]["stddev"]["gyroscope_gain_x"] = 1.1 * std::sqrt(variance);
       },
       "gyroscope/stddev/gyroscope_gain_x = ", "contradicts gyroscope/covariance[6][6] = "},
      {"NaN (written as null)",
       [](Json* j) { (*j)["gyroscope"]["parameters"]["gyroscope_misalignment_zx"] = std::nan(""); },
       "gyroscope/parameters/gyroscope_misalignment_zx must be a number", ""},
      {"nested 200000 deep", [](Json* j) { (*j)["gyroscope"]["fit"] = "NESTED"; },
       "arrays and objects nested more than 64 deep, under /gyroscope", ""},
  };
  int index = 0;
  for (const Damage& damage : damages) {
    SCOPED_TRACE(damage.what);
    Json damaged = good;
    damage.damage(&damaged);
    std::string text = damaged.dump(1);
    const size_t nested = text.find("\"NESTED\"");
    if (nested != std::string::npos) {
      text.replace(nested, 8, std::string(200000, '[') + std::string(200000, ']'));
    }
    const std::string cal = scratch.Write("damaged" + std::to_string(index++) + ".json", text);
    const testing::CommandResult result =
        RunBinary("apply", "--calibration=" + cal + " --in=" + in + " --out=" + out);
    ExpectBadInputContract(result, "apply", cal + ": " + damage.expected);
    EXPECT_NE(result.stderr_text.find(damage.also), std::string::npos) << result.stderr_text;
    EXPECT_FALSE(testing::PathExists(out));
  }

  // The columns' names say deg/s; the section is for counts.
  const std::string cal = WriteCalibration(scratch, testing::ExampleTriadRecordWithGyroscope());
  const std::string dps =
      scratch.Write("dps.csv", Log("t_s,ax,ay,az,gyr_x_dps,gyr_y_dps,gyr_z_dps", 20));
  ExpectBadInputContract(
      RunBinary("apply", "--calibration=" + cal + " --in=" + dps + " --out=" + out), "apply",
      dps + ": the gyroscope columns' names say deg/s, but " + cal +
          "'s gyroscope section is for outputs in count");
  EXPECT_FALSE(testing::PathExists(out));

  // A gyroscope sample far beyond any gyroscope's range: a damaged value, not a reading.
  std::string text = Log("t_s,ax,ay,az,gx,gy,gz", 20);
  const size_t row = text.find("\n0.05,");
  ASSERT_NE(row, std::string::npos) << text;
  const size_t end = text.find('\n', row + 1);
  text.replace(text.rfind(',', end) + 1, end - text.rfind(',', end) - 1, "1e300");
  const std::string damaged = scratch.Write("damaged.csv", text);
  ExpectBadInputContract(
      RunBinary("apply", "--calibration=" + cal + " --in=" + damaged + " --out=" + out), "apply",
      damaged + ": sample 5 (t = 0.05 s), gyroscope output (");
  EXPECT_FALSE(testing::PathExists(out));
}

}  // namespace
}  // namespace accelcal
