// Advice that converges (issue 30, item 3): a refusal of calibrate_imu that suggests a flag's
// value ("give --X=V", "say --unit=U", "choose one with --columns=...") is followed here, as a
// user would, and the run must then succeed or refuse for another reason, never the same one.
// (imu_tk's --init_rest_s advice is followed in tests/imu_tk_calibration_test.cc and
// CalibrateImuCli; the reader's --columns in ImuLogLayouts.)

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "common/format.h"
#include "test_support.h"

namespace accelcal {
namespace {

// The flag a refusal suggests: from "--NAME=" to the first blank, ')', ';' or line end after
// it, less the punctuation of the sentence around it.
std::string SuggestedFlag(const std::string& message, const std::string& name) {
  const size_t start = message.find("--" + name + "=");
  if (start == std::string::npos) return "";
  const size_t end = message.find_first_of(" );\n", start);
  std::string flag =
      message.substr(start, end == std::string::npos ? std::string::npos : end - start);
  while (!flag.empty() && (flag.back() == ',' || flag.back() == '.')) flag.pop_back();  // prose
  return flag;
}

// A hand-held session of 24 poses spread over the sphere (a Fibonacci lattice), 2.5 s each with
// a 0.5 s turn to the next, in m/s^2 (a log an app wrote) or in 12-bit counts; 100 Hz.
std::string Session(const std::string& header, bool counts) {
  constexpr int kPoses = 24;
  std::vector<std::array<double, 3>> directions;
  for (int p = 0; p < kPoses; ++p) {
    const double z = 1.0 - 2.0 * (p + 0.5) / kPoses;
    const double azimuth = p * M_PI * (3.0 - std::sqrt(5.0));
    const double r = std::sqrt(1.0 - z * z);
    directions.push_back({r * std::cos(azimuth), r * std::sin(azimuth), z});
  }
  unsigned seed = 7;
  auto noise = [&seed]() {  // deterministic, uniform in [-0.5, 0.5)
    seed = seed * 1103515245u + 12345u;
    return ((seed >> 16) % 1000) / 1000.0 - 0.5;
  };
  std::string text = header + "\n";
  int row = 0;
  for (int pose = 0; pose < kPoses; ++pose) {
    for (int j = 0; j < 300; ++j, ++row) {
      std::array<double, 3> a = directions[pose];
      if (j >= 250 && pose + 1 < kPoses) {  // a turn towards the next pose
        const double f = (j - 250) / 50.0;
        for (int k = 0; k < 3; ++k) a[k] = (1 - f) * a[k] + f * directions[pose + 1][k];
      }
      for (double& v : a) v = 9.81 * v + 0.02 * noise();
      if (counts) {
        text += StringPrintf("%.2f,%.0f,%.0f,%.0f\n", 0.01 * row, 2048 + 100 * a[0] + noise(),
                             2048 + 100 * a[1] + noise(), 2048 + 100 * a[2] + noise());
      } else {
        text += StringPrintf("%.2f,%.5f,%.5f,%.5f\n", 0.01 * row, a[0], a[1], a[2]);
      }
    }
  }
  return text;
}

// Runs calibrate_imu, follows the flag its refusal suggests, and checks what follows: an
// answer (the sessions here calibrate), never the same refusal or the same advice again.
void ExpectAdviceConverges(const std::vector<std::string>& arguments, const std::string& flag) {
  testing::CommandResult result = testing::RunBinaryArgs("calibrate_imu", arguments);
  ASSERT_EQ(result.exit_status, 2) << result.stdout_text;
  const std::string suggestion = SuggestedFlag(result.stderr_text, flag);
  ASSERT_FALSE(suggestion.empty()) << "no --" << flag << "= in: " << result.stderr_text;
  std::vector<std::string> followed = arguments;
  followed.push_back(suggestion);
  const testing::CommandResult next = testing::RunBinaryArgs("calibrate_imu", followed);
  // These sessions calibrate: the advice must lead to an answer.
  EXPECT_EQ(next.exit_status, 0) << suggestion << ": " << next.stderr_text;
  if (next.exit_status == 0) return;
  EXPECT_NE(next.stderr_text, result.stderr_text) << "the same refusal after " << suggestion;
  EXPECT_EQ(SuggestedFlag(next.stderr_text, flag), "")
      << "a second --" << flag << " after " << suggestion << ": " << next.stderr_text;
}

TEST(RefusalAdvice, TheUnitALogIsRefusedWithIsTheOneItIsReadIn) {
  testing::ScratchDir dir;
  // m/s^2 read as the default counts: "say --unit=m/s^2".
  const std::string log = dir.Write("phone.csv", Session("time,accX,accY,accZ", false));
  ExpectAdviceConverges({"--log=" + log, "--mode=ml"}, "unit");
  // counts said to be in g.
  const std::string raw = dir.Write("raw.csv", Session("time,accX,accY,accZ", true));
  ExpectAdviceConverges({"--log=" + raw, "--mode=ml", "--unit=g"}, "unit");
}

TEST(RefusalAdvice, SeveralAccelerometersAreReadOneAtATimeAsTheMessageSays) {
  testing::ScratchDir dir;
  std::string text = Session("t,ACC0_X,ACC0_Y,ACC0_Z", false);
  // The same samples twice, as an array logs two devices side by side.
  std::string doubled;
  size_t begin = 0;
  for (size_t end; (end = text.find('\n', begin)) != std::string::npos; begin = end + 1) {
    const std::string line = text.substr(begin, end - begin);
    doubled +=
        line + "," + (begin == 0 ? "ACC1_X,ACC1_Y,ACC1_Z" : line.substr(line.find(',') + 1)) + "\n";
  }
  const std::string log = dir.Write("array.csv", doubled);
  ExpectAdviceConverges({"--log=" + log, "--mode=ml", "--unit=m/s^2"}, "columns");
}

TEST(RefusalAdvice, AHeaderlessLogIsReadWithTheColumnsTheMessageNames) {
  testing::ScratchDir dir;
  std::string text = Session("#", false);
  std::string seven;  // t, a, and a still gyroscope: seven numbers per row, no names
  size_t begin = text.find('\n') + 1;
  for (size_t end; (end = text.find('\n', begin)) != std::string::npos; begin = end + 1)
    seven += text.substr(begin, end - begin) + ",0.001,0.002,0.003\n";
  const std::string log = dir.Write("seven.csv", seven);
  ExpectAdviceConverges({"--log=" + log, "--mode=ml", "--unit=m/s^2"}, "columns");
}

}  // namespace
}  // namespace accelcal
