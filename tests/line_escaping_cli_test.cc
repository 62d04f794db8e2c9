// A path with a newline (or another line break: a carriage return, Unicode's line and paragraph
// separators, which YAML also breaks lines at) never reaches a line-oriented output raw (issue
// 45, "Silent wrong answers"): in Kalibr's imu.yaml it would start a line of its own, a key
// Kalibr reads; in apply's CSV a provenance line without '#', which the documented reader takes
// for the header. Every such text goes through one rule, common/line_text.h's EscapeForLine, and
// the command line through bash's $'...' quoting (io/provenance.h). Run from outside: the
// binaries on files whose names carry the breaks, their outputs read back as their readers do.

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "common/format.h"
#include "gyroscope_calibration_example.h"
#include "io/calibration_file.h"
#include "test_support.h"

namespace accelcal {
namespace {

using testing::ReadText;
using testing::RunBinaryArgs;
using testing::ScratchDir;

// Line breaks a path may hold: LF, CR, and YAML's other breaks (NEL, LS, PS, in UTF-8).
const std::string kBreaks[] = {"\n", "\r", "\xC2\x85", "\xE2\x80\xA8", "\xE2\x80\xA9"};

// `text` with its control bytes shown as \xNN, for the failures' messages.
std::string Visible(const std::string& text) {
  std::string shown;
  for (const char c : text) {
    const unsigned char byte = static_cast<unsigned char>(c);
    shown += byte < 0x20 || byte >= 0x7f ? StringPrintf("\\x%02X", byte) : std::string(1, c);
  }
  return shown;
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream stream(text);
  for (std::string line; std::getline(stream, line);) lines.push_back(line);
  return lines;
}

// /usr/bin/python3 with `arguments` (an argument vector, no shell): its stdout, or "" with a
// failure recorded.
std::string RunPython(const std::vector<std::string>& arguments) {
  const testing::CommandResult result = testing::RunProgramArgs("/usr/bin/python3", arguments);
  if (result.exit_status != 0) {
    ADD_FAILURE() << "python3 failed: " << result.stderr_text;
    return "";
  }
  return result.stdout_text;
}

// allan's JSON for a log in counts with per-axis white noise n and random walk k, and the
// SHA-256 the log's had (two different logs for the two sensors).
nlohmann::json AllanJson(double n, double k, const std::string& log_sha256) {
  nlohmann::json axes;
  for (const char* axis : {"x", "y", "z"}) {
    axes[axis] = {
        {"white_noise", {{"fitted", true}, {"resolved", true}, {"value", n}}},
        {"random_walk", {{"fitted", true}, {"resolved", true}, {"value", k}, {"high", 0.0}}},
        {"points", {{{"tau_s", 1.0}, {"adev_high", 2.0}}}}};
  }
  return {{"problem", "allan"}, {"output_unit", "count"},
          {"gain", 1.0},        {"sample_period_s", 0.005},
          {"axes", axes},       {"input_files", {{"log", {{"sha256", log_sha256}}}}}};
}

TEST(KalibrExport, ALineBreakInAPathCannotAddAKeyToTheYaml) {
  for (const std::string& line_break : kBreaks) {
    ScratchDir scratch;
    // Each path would put a key of its own on a line of its own, were it written raw.
    const std::string calibration =
        scratch.Write("cal" + line_break + "injected_calibration: 1" + line_break + ".json",
                      CalibrationJson(testing::ExampleTriadRecordWithGyroscope()).dump(2) + "\n");
    const std::string allan = scratch.Write("acc" + line_break + "injected_allan: 2.json",
                                            AllanJson(0.3, 0.01, "ab12").dump(2));
    const std::string gyro_allan = scratch.Write("gyro" + line_break + "update_rate: 1.json",
                                                 AllanJson(0.4, 0.02, "cd34").dump(2));
    const std::string out = scratch.File("imu.yaml");
    const auto result = RunBinaryArgs(
        "export_calibration", {"--format=kalibr", "--calibration=" + calibration,
                               "--allan=" + allan, "--gyro_allan=" + gyro_allan, "--out=" + out});
    ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
    // YAML as Kalibr reads it (PyYAML, which breaks lines at all five): exactly its six keys
    // and the topic, with the values written (update_rate the fits' 200 Hz, not the path's 1).
    const std::string keys =
        RunPython({"-c",
                   "import sys, yaml\n"
                   "d = yaml.safe_load(open(sys.argv[1], encoding='utf-8'))\n"
                   "print(' '.join(sorted(d)), d['update_rate'], d['rostopic'])\n",
                   out});
    EXPECT_EQ(keys,
              "accelerometer_noise_density accelerometer_random_walk gyroscope_noise_density "
              "gyroscope_random_walk rostopic update_rate 200 /imu0\n")
        << "line break " << Visible(line_break) << " in\n"
        << ReadText(out);
    // And no line break of any kind inside a line: every line a comment or one of the keys.
    for (const std::string& line : Lines(ReadText(out))) {
      for (const std::string& other : kBreaks)
        EXPECT_EQ(line.find(other), std::string::npos) << Visible(line);
      EXPECT_TRUE(line.rfind("# ", 0) == 0 || line.find(": ") != std::string::npos) << line;
    }
  }
}

TEST(ImuTkExport, ALineBreakInAPathStaysInsideItsComment) {
  ScratchDir scratch;
  const std::string calibration =
      scratch.Write("cal\n1 2 3\n.json",
                    CalibrationJson(testing::ExampleTriadRecordWithGyroscope()).dump(2) + "\n");
  const std::string prefix = scratch.File("imu");
  const auto result = RunBinaryArgs(
      "export_calibration", {"--format=imu_tk", "--calibration=" + calibration, "--out=" + prefix});
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  for (const char* sensor : {"_acc.calib", "_gyro.calib"}) {
    const std::vector<std::string> lines = Lines(ReadText(prefix + sensor));
    // imu_tk's 21 numbers (three 3x3 matrices and a vector, blank lines between), then comments.
    int numbers = 0;
    bool comments = false;
    for (const std::string& line : lines) {
      if (line.rfind("#", 0) == 0) {
        comments = true;
        continue;
      }
      EXPECT_FALSE(comments) << "a line after the comments that is not one: " << line;
      std::istringstream stream(line);
      for (double value; stream >> value;) ++numbers;
    }
    EXPECT_EQ(numbers, 21) << sensor;
  }
}

// apply's provenance lines are written by problems/apply.cc's ProvenanceLines: the command line
// is escaped by io/provenance.h, each input's path needs EscapeForLine(file.path) there (its line
// "# " + role + ": " + file.path + ...), the one change this test waits for.
TEST(ApplyCsv, ALineBreakInAPathStaysInsideItsProvenanceLine) {
  ScratchDir scratch;
  const CalibrationRecord record = testing::ExampleTriadRecord();
  // The path would start the columns' header line, were it written raw.
  const std::string calibration =
      scratch.Write("cal\nt_s,ax_mps2\n.json", CalibrationJson(record).dump(2) + "\n");
  // A still log of the example triad: u = b + a / gain about gravity along z.
  std::string csv = "t,ax,ay,az\n";
  for (int j = 0; j < 200; ++j) {
    csv += StringPrintf("%.2f,%.3f,%.3f,%.3f\n", j * 0.01, record.values[6] + 0.01 * (j % 3),
                        record.values[7], record.values[8] + 9.81 / record.values[5]);
  }
  const std::string log = scratch.Write("run\rx\xE2\x80\xA8y\nz.csv", csv);
  const std::string out = scratch.File("corrected.csv");
  const auto result =
      RunBinaryArgs("apply", {"--calibration=" + calibration, "--in=" + log, "--out=" + out});
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  const std::vector<std::string> lines = Lines(ReadText(out));
  // The documented reading: '#' lines, then the header, then one row per sample.
  size_t header = 0;
  while (header < lines.size() && lines[header].rfind("#", 0) == 0) ++header;
  ASSERT_LT(header, lines.size());
  EXPECT_EQ(lines[header],
            "t_s,ax_mps2,ay_mps2,az_mps2,sigma_ax_mps2,sigma_ay_mps2,sigma_az_mps2,corr_xy,"
            "corr_xz,corr_yz");
  EXPECT_EQ(lines.size(), header + 1 + 200);
  for (size_t i = 0; i < header; ++i) {
    EXPECT_EQ(lines[i].find('\r'), std::string::npos) << Visible(lines[i]);
    EXPECT_EQ(lines[i].find("\xE2\x80\xA8"), std::string::npos) << Visible(lines[i]);
  }
  // The paths are there, escaped: each provenance line names its file.
  const std::string text = ReadText(out);
  EXPECT_NE(text.find("# calibration: " + scratch.path() + "/cal\\nt_s,ax_mps2\\n.json (sha256 "),
            std::string::npos)
      << Visible(text.substr(0, 1200));
  EXPECT_NE(text.find("# log: " + scratch.path() + "/run\\rx\\u2028y\\nz.csv (sha256 "),
            std::string::npos)
      << Visible(text.substr(0, 1200));
}

}  // namespace
}  // namespace accelcal
