// The main job: one command from data to a report folder whose figures are embedded, whose
// results agree with the individual binaries, and which is never left half-written.

#include <gtest/gtest.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "test_support.h"

namespace accelcal {
namespace {

using testing::CommandResult;
using testing::RunBinary;
using testing::ScratchDir;

bool MatplotlibAvailable() {
  return testing::RunCommand("/usr/bin/python3 -c 'import matplotlib, numpy'").exit_status == 0;
}

// A PNG's width and height, or (0, 0) when the bytes are not a PNG.
std::pair<int, int> PngSize(const std::string& bytes) {
  if (bytes.size() < 24 || bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0) return {0, 0};
  auto be32 = [&](size_t at) {
    return (static_cast<unsigned char>(bytes[at]) << 24) |
           (static_cast<unsigned char>(bytes[at + 1]) << 16) |
           (static_cast<unsigned char>(bytes[at + 2]) << 8) |
           static_cast<unsigned char>(bytes[at + 3]);
  };
  return {static_cast<int>(be32(16)), static_cast<int>(be32(20))};
}

TEST(AnalyzeBinary, OnTheCourseDataItAgreesWithTheIndividualBinaries) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  ScratchDir out;
  const std::string report = out.File("report");
  const CommandResult result =
      RunBinary("analyze", "--data_dir='" + dir + "' --out_dir='" + report + "'");
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  const nlohmann::json results = nlohmann::json::parse(testing::ReadText(report + "/results.json"));

  ASSERT_EQ(RunBinary("linear_ls", "--data_dir='" + dir + "' --json='" + out.File("l.json") + "'")
                .exit_status,
            0);
  const nlohmann::json linear = nlohmann::json::parse(testing::ReadText(out.File("l.json")));
  EXPECT_EQ(results["linear_ls"]["parameters"], linear["parameters"]);
  EXPECT_EQ(results["linear_ls"]["covariance"], linear["covariance"]);

  ASSERT_EQ(RunBinary("trajectory", "--data_dir='" + dir + "' --json='" + out.File("t.json") + "'")
                .exit_status,
            0);
  const nlohmann::json trajectory = nlohmann::json::parse(testing::ReadText(out.File("t.json")));
  EXPECT_EQ(results["trajectory"]["endpoint"], trajectory["endpoint"]);
  EXPECT_EQ(results["trajectory"]["reached"], trajectory["reached"]);
  EXPECT_EQ(results["trajectory"]["landmarks"], trajectory["landmarks"]);

  ASSERT_EQ(RunBinary("discover", "--data_dir='" + dir + "' --json='" + out.File("d.json") + "'")
                .exit_status,
            0);
  const nlohmann::json discover = nlohmann::json::parse(testing::ReadText(out.File("d.json")));
  EXPECT_EQ(results["discover"]["verdict"], discover["verdict"]);
  EXPECT_EQ(results["discover"]["verdict_code"], "explained");
  EXPECT_EQ(results["discover"]["verdict_code"], discover["verdict_code"]);
  EXPECT_EQ(results["discover"]["remaining"], discover["remaining"]);
  EXPECT_EQ(results["discover"]["effects"], discover["effects"]);

  ASSERT_EQ(RunBinary("min_samples", "--data_dir='" + dir + "' --repetitions=0 --json='" +
                                         out.File("m.json") + "'")
                .exit_status,
            0);
  const nlohmann::json samples = nlohmann::json::parse(testing::ReadText(out.File("m.json")));
  ASSERT_EQ(results["min_samples"]["designs"].size(), samples["designs"].size());
  for (size_t k = 0; k < samples["designs"].size(); ++k) {
    EXPECT_EQ(results["min_samples"]["designs"][k]["n_min"], samples["designs"][k]["n_min"]);
    EXPECT_EQ(results["min_samples"]["designs"][k]["n_min_3sigma"],
              samples["designs"][k]["n_min_3sigma"]);
  }
  // The verdict comes first in both reports.
  const std::string markdown = testing::ReadText(report + "/report.md");
  EXPECT_EQ(markdown.find("# accelcal report\n\n**Verdict.** the baseline explains the data"), 0u)
      << markdown.substr(0, 200);
  EXPECT_NE(markdown.find("Verdict: explained (of explained, missing, unexplained, "
                          "cannot_tell_apart)"),
            std::string::npos);
  EXPECT_NE(markdown.find("What the final model leaves: nothing the checks can see"),
            std::string::npos);
  EXPECT_EQ(testing::CountLines(testing::ReadText(report + "/residuals.csv")), 1 + 5000);
}

TEST(AnalyzeBinary, TheHtmlEmbedsEveryFigureAndEachIsAValidImage) {
  if (!MatplotlibAvailable()) GTEST_SKIP() << "no python3-matplotlib: figures are not drawn";
  ScratchDir out;
  const std::string report = out.File("report");
  const CommandResult result = RunBinary("analyze", "--out_dir='" + report + "'");
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  EXPECT_NE(result.stdout_text.find("missing: angle_offset"), std::string::npos)
      << result.stdout_text;
  const std::string html = testing::ReadText(report + "/report.html");
  for (const char* figure : {"trajectory.png", "discovery.png", "min_samples.png"}) {
    const auto [width, height] = PngSize(testing::ReadText(report + "/" + figure));
    EXPECT_GE(width, 600) << figure;
    EXPECT_GE(height, 400) << figure;
    EXPECT_LE(width, 4000) << figure;
  }
  size_t embedded = 0;
  for (size_t at = html.find("data:image/png;base64,"); at != std::string::npos;
       at = html.find("data:image/png;base64,", at + 1)) {
    ++embedded;
  }
  EXPECT_EQ(embedded, 3u);
  EXPECT_EQ(html.find("is absent"), std::string::npos);
  EXPECT_NE(html.find("The truth hidden in it: angle_offset = 0.004 rad"), std::string::npos);
}

TEST(AnalyzeBinary, AMissingPlotterIsSaidInTheReportNotAFailure) {
  ScratchDir out;
  const std::string report = out.File("report");
  const CommandResult result =
      RunBinary("analyze", "--out_dir='" + report + "' --python=/nonexistent/python3 --set=");
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  const std::string markdown = testing::ReadText(report + "/report.md");
  EXPECT_NE(markdown.find("## Figures not drawn"), std::string::npos);
  EXPECT_NE(markdown.find("trajectory.png: cannot start /nonexistent/python3"), std::string::npos)
      << markdown;
}

TEST(AnalyzeBinary, AnInterruptedRunLeavesNoPartialReportAndAnOldOneStays) {
  ScratchDir out;
  const std::string report = out.File("report");
  // Killed mid-way: no report folder at all.
  testing::RunCommand("'" + testing::BinaryPath("analyze") + "' --out_dir='" + report +
                      "' >/dev/null 2>&1 & pid=$!; sleep 0.8; kill -9 $pid; wait $pid");
  EXPECT_FALSE(testing::PathExists(report));
  // A finished report is not replaced without --overwrite, nor by a killed overwrite.
  ASSERT_EQ(RunBinary("analyze", "--out_dir='" + report + "' --set=").exit_status, 0);
  const std::string before = testing::ReadText(report + "/results.json");
  testing::ExpectBadInputContract(RunBinary("analyze", "--out_dir='" + report + "'"), "analyze",
                                  "exists and is not empty; pass --overwrite");
  testing::RunCommand("'" + testing::BinaryPath("analyze") + "' --overwrite --out_dir='" + report +
                      "' >/dev/null 2>&1 & pid=$!; sleep 0.8; kill -9 $pid; wait $pid");
  EXPECT_EQ(testing::ReadText(report + "/results.json"), before);
}

}  // namespace
}  // namespace accelcal
