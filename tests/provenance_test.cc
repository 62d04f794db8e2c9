// SHA-256 against FIPS 180-4's examples and sha256sum, and the provenance every output
// carries (io/provenance.h).

#include "io/provenance.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "common/format.h"
#include "common/sha256.h"
#include "io/imu_log.h"
#include "io/input_file.h"
#include "io/mat_file.h"
#include "io/scenario_json.h"
#include "test_support.h"

namespace accelcal {
namespace {

TEST(Sha256, MatchesTheStandardsExamples) {
  // FIPS 180-4 examples (NIST CSRC, "SHA256.pdf") and the empty message.
  EXPECT_EQ(Sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(Sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(Sha256Hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

TEST(Sha256, AMessageGivenInPiecesOfAnySizeHasTheSameDigest) {
  // One million 'a' (FIPS 180-2, appendix B.3), in pieces that straddle the 64-byte blocks.
  const std::string million(1000000, 'a');
  const std::string expected = "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0";
  EXPECT_EQ(Sha256Hex(million), expected);
  for (const size_t piece : {1u, 7u, 55u, 56u, 63u, 64u, 65u, 1000u}) {
    Sha256 hash;
    for (size_t at = 0; at < million.size(); at += piece) {
      hash.Update(million.data() + at, std::min(piece, million.size() - at));
    }
    EXPECT_EQ(hash.HexDigest(), expected) << "pieces of " << piece;
  }
}

TEST(HashInputFile, AgreesWithSha256sumAndRefusesWhatIsNotAFile) {
  testing::ScratchDir scratch;
  std::string contents;
  for (int i = 0; i < 100000; ++i) contents += static_cast<char>(i * 7 % 256);
  const std::string path = scratch.Write("bytes.bin", contents);
  InputFile file;
  ASSERT_TRUE(HashInputFile(path, &file).ok());
  EXPECT_EQ(file.bytes, contents.size());
  const testing::CommandResult sha256sum = testing::RunCommand("sha256sum '" + path + "'");
  ASSERT_EQ(sha256sum.exit_status, 0);
  EXPECT_EQ(file.sha256, sha256sum.stdout_text.substr(0, 64));
  EXPECT_FALSE(HashInputFile(scratch.path(), &file).ok());
  EXPECT_FALSE(HashInputFile(scratch.File("absent"), &file).ok());
}

// Issue 35, item 5: a log that changes while it is read (a logger still appending). The
// provenance's checksum is of the bytes the reader parsed; a file changed after it was read,
// while it was read, or between its checksum and its reading is refused, saying so. The runs of
// the binaries record their reads (InitProblem); so does each test here.
class InputReads : public ::testing::Test {
 protected:
  void SetUp() override { StartRecordingInputReads(); }

  // A 100 Hz CSV log of `rows` still samples.
  static std::string LogText(int rows, int first = 0) {
    std::string text = first == 0 ? "t,ax,ay,az\n" : "";
    for (int j = first; j < first + rows; ++j) text += StringPrintf("%.2f,1,2,9.8\n", 0.01 * j);
    return text;
  }
  static void Append(const std::string& path, const std::string& text) {
    std::ofstream(path, std::ios::app | std::ios::binary) << text;
  }

  testing::ScratchDir scratch_;
};

TEST_F(InputReads, TheChecksumIsOfTheBytesTheLogReaderParsedAndAFileChangedSinceIsRefused) {
  const std::string text = LogText(200);
  const std::string path = scratch_.Write("log.csv", text);
  TriadLog log;
  ASSERT_TRUE(ReadImuLog(path, ImuLogReadOptions(), &log, ImuLogSpacing::kAny).ok());
  ASSERT_EQ(log.size(), 200u);
  DataSource source;
  ASSERT_TRUE(DescribeMeasuredData("", {{"log", path}}, &source).ok());
  EXPECT_EQ(source.files["log"].bytes, text.size());
  EXPECT_EQ(source.files["log"].sha256, Sha256Hex(text));
  // The logger writes 10 more samples before the checksum is taken.
  Append(path, LogText(10, 200));
  const Status status = DescribeMeasuredData("", {{"log", path}}, &source);
  EXPECT_ERROR_CONTAINS(status, path + ": the file changed after it was read (" +
                                    std::to_string(text.size()) + " bytes read, ");
  EXPECT_ERROR_CONTAINS(status, "copy it once the recording has stopped");
}

TEST_F(InputReads, ALogThatGrowsWhileItIsStreamedIsRefused) {
  const std::string path = scratch_.Write("log.csv", LogText(200));
  bool appended = false;
  size_t samples = 0;
  const Status status = StreamImuLog(path, ImuLogReadOptions(), 1, [&](const TriadLog& batch) {
    samples += batch.size();
    if (!appended) Append(path, LogText(10, 200));
    appended = true;
  });
  EXPECT_ERROR_CONTAINS(status, path + ": the file changed while it was read (");
  EXPECT_ERROR_CONTAINS(status, "a logger may still be writing it");
}

TEST_F(InputReads, AFileChangedBetweenItsChecksumAndItsReadingIsRefused) {
  // The sessions' order: the checksums first (to refuse a session given twice), then the reads.
  const std::string path = scratch_.Write("session.csv", LogText(200));
  DataSource source;
  ASSERT_TRUE(DescribeMeasuredData("", {{"session_1", path}}, &source).ok());
  Append(path, LogText(10, 200));
  TriadLog log;
  const Status status = ReadImuLog(path, ImuLogReadOptions(), &log, ImuLogSpacing::kAny);
  EXPECT_ERROR_CONTAINS(status, path + ": the file changed between two readings of this run");
}

TEST_F(InputReads, AMatLogChangedAfterItWasReadIsRefused) {
  MatMatrix t{30, 1, {}}, acc{30, 3, {}};
  for (int j = 0; j < 30; ++j) t.values.push_back(0.01 * j);
  for (double value : {1.0, 2.0, 9.8}) acc.values.insert(acc.values.end(), 30, value);
  const std::string path = scratch_.File("log.mat");
  ASSERT_TRUE(WriteMatFile(path, {{"t", t}, {"acc", acc}}).ok());
  TriadLog log;
  ASSERT_TRUE(ReadImuLog(path, ImuLogReadOptions(), &log, ImuLogSpacing::kAny).ok());
  DataSource source;
  ASSERT_TRUE(DescribeMeasuredData("", {{"log", path}}, &source).ok());
  EXPECT_EQ(source.files["log"].sha256, Sha256Hex(testing::ReadText(path)));
  Append(path, std::string(8, '\0'));
  EXPECT_ERROR_CONTAINS(DescribeMeasuredData("", {{"log", path}}, &source),
                        path + ": the file changed after it was read");
}

// A logger caught mid-line: the bytes after the last complete line are a partial line. The log is
// refused (cut short) and nothing of it is recorded, so no checksum can stand for a count of
// samples it did not give.
TEST_F(InputReads, ALogEndingInAPartialLineIsRefusedAndNotRecorded) {
  const std::string path = scratch_.Write("log.csv", LogText(200) + "2.00,1,2,9");
  TriadLog log;
  EXPECT_ERROR_CONTAINS(ReadImuLog(path, ImuLogReadOptions(), &log, ImuLogSpacing::kAny),
                        "line 202 has no line end: the file looks cut short");
  InputRead read;
  EXPECT_FALSE(FindInputRead(path, &read));
}

// A whole-file reader (the calibration file, a CSV) records its bytes too.
TEST_F(InputReads, AWholeFileReadIsRecordedAndMustNotChangeAfter) {
  const std::string path = scratch_.Write("notes.txt", "one\n");
  std::string contents;
  ASSERT_TRUE(ReadInputText(path, 1 << 20, "a text", &contents).ok());
  InputFile file;
  ASSERT_TRUE(HashInputFile(path, &file).ok());
  EXPECT_EQ(file.sha256, Sha256Hex("one\n"));
  Append(path, "two\n");
  EXPECT_ERROR_CONTAINS(HashInputFile(path, &file), "the file changed after it was read (4 bytes");
}

TEST(DataLine, SaysMeasuredOrSimulatedAndWhatIsHidden) {
  DataSource measured;
  measured.data_dir = "../shared/data/tp2-2018";
  measured.files["calibration"].path = "../shared/data/tp2-2018/ensayo.mat";
  measured.files["conditions"].path = "../shared/data/tp2-2018/datos.txt";
  EXPECT_EQ(DataLine(measured), "data: ../shared/data/tp2-2018 (2 files)");

  Scenario scenario;
  ASSERT_TRUE(LoadScenarioOrDefault("", "angle_offset=0.004", &scenario).ok());
  DataSource simulated;
  ASSERT_TRUE(DescribeSimulation(scenario, "", 7, &simulated).ok());
  EXPECT_EQ(DataLine(simulated),
            "data: simulated, scenario tp2-2018, seed 7, hidden angle_offset=0.004");
  ASSERT_TRUE(LoadScenarioOrDefault("", "", &scenario).ok());
  ASSERT_TRUE(DescribeSimulation(scenario, "", 1, &simulated).ok());
  EXPECT_EQ(DataLine(simulated),
            "data: simulated, scenario tp2-2018, seed 1, nothing hidden beyond the baseline");
  // A disturbance outside the catalogue is hidden too.
  ASSERT_TRUE(LoadScenarioOrDefault("", "noise_ar1_x=0.5", &scenario).ok());
  ASSERT_TRUE(DescribeSimulation(scenario, "", 1, &simulated).ok());
  EXPECT_NE(DataLine(simulated).find("hidden noise_ar1_x=0.5"), std::string::npos)
      << DataLine(simulated);
}

TEST(CommandLine, IsRecordedSoAShellReadsItBack) {
  std::string arguments[] = {"/usr/local/bin/linear_ls", "--data_dir=my data", "--set=a=1,b=2",
                             "--json=it's.json"};
  char* argv[] = {arguments[0].data(), arguments[1].data(), arguments[2].data(),
                  arguments[3].data()};
  RecordCommandLine(4, argv);
  EXPECT_EQ(CommandLine(), "linear_ls '--data_dir=my data' --set=a=1,b=2 '--json=it'\\''s.json'");
  const testing::CommandResult echoed =
      testing::RunCommand("printf '%s|' " + CommandLine().substr(CommandLine().find(' ') + 1));
  EXPECT_EQ(echoed.stdout_text, "--data_dir=my data|--set=a=1,b=2|--json=it's.json|");
}

}  // namespace
}  // namespace accelcal
