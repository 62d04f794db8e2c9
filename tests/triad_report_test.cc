// calibrate_imu --mode=ml --report: one self-contained HTML page on imu_tk's own Xsens log,
// with every pose, every pose's residual (table and figure), the parameters with sigma beside
// imu_tk's and the datasheet's, the fit and the provenance; a refused run writes nothing; and
// without Python the page is still written and says which figures are absent.

#include "reporting/triad_report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/format.h"
#include "estimation/statistics/chi_square.h"
#include "reporting/calibrate_imu_report.h"
#include "reporting/triad_discovery_report.h"
#include "test_support.h"

namespace accelcal {
namespace {

using testing::RunBinary;

bool MatplotlibAvailable() {
  return testing::RunCommand("/usr/bin/python3 -c 'import matplotlib, numpy'").exit_status == 0;
}

// Standard base64 (RFC 4648) decoded; empty when a character is outside the alphabet.
std::string DecodeBase64(const std::string& text) {
  static const std::string kAlphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  unsigned buffer = 0;
  int bits = 0;
  for (char c : text) {
    if (c == '=') break;
    const size_t value = kAlphabet.find(c);
    if (value == std::string::npos) return "";
    buffer = (buffer << 6) | static_cast<unsigned>(value);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out += static_cast<char>((buffer >> bits) & 0xff);
    }
  }
  return out;
}

// The bytes of the embedded image whose alt text starts with `alt`, or "" when absent.
std::string EmbeddedPng(const std::string& html, const std::string& alt) {
  const size_t image = html.find("<img alt=\"" + alt);
  if (image == std::string::npos) return "";
  const std::string prefix = "src=\"data:image/png;base64,";
  const size_t start = html.find(prefix, image);
  if (start == std::string::npos) return "";
  const size_t data = start + prefix.size();
  return DecodeBase64(html.substr(data, html.find('"', data) - data));
}

bool IsCompletePng(const std::string& bytes) {
  static const std::string kSignature = "\x89PNG\r\n\x1a\n";
  static const std::string kEnd = std::string("IEND\xae\x42\x60\x82", 8);
  return bytes.size() > 64 && bytes.compare(0, kSignature.size(), kSignature) == 0 &&
         bytes.compare(bytes.size() - kEnd.size(), kEnd.size(), kEnd) == 0;
}

// A table cell as RenderHtml writes it.
std::string Cell(const std::string& label, const std::string& value) {
  return "<td data-label=\"" + label + "\">" + value + "</td>";
}

TEST(TriadReport, XsensReportHasEveryPoseResidualFigureParametersWithSigmaAndTheLogsSha256) {
  ACCELCAL_REQUIRE_IMU_TK_DATA(dir);
  testing::ScratchDir scratch;
  const std::string report = scratch.File("xsens report.html");
  const std::string json_path = scratch.File("ml.json");
  const testing::CommandResult result =
      RunBinary("calibrate_imu", "--log='" + dir + "/xsens_acc.mat' --g=9.81744 --mode=ml " +
                                     "--json='" + json_path + "' --report='" + report + "'");
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  EXPECT_NE(result.stdout_text.find("report: " + report), std::string::npos) << result.stdout_text;
  const std::string html = testing::ReadText(report);
  const nlohmann::json json = nlohmann::json::parse(testing::ReadText(json_path));
  ASSERT_FALSE(html.empty());

  // Every pose: its row in the poses table (number, start, end) and in the residual table
  // (number and the x residual, to the table's three decimals).
  const nlohmann::json& intervals = json["intervals"];
  ASSERT_EQ(intervals.size(), 38u);
  for (size_t p = 0; p < intervals.size(); ++p) {
    const std::string pose = std::to_string(p + 1);
    EXPECT_NE(html.find(Cell("pose", pose) +
                        Cell("start", std::to_string(intervals[p]["start"].get<int>())) +
                        Cell("end", std::to_string(intervals[p]["end"].get<int>()))),
              std::string::npos)
        << "pose " << pose;
    const double r_x = intervals[p]["whitened_residual"][0].get<double>();
    EXPECT_NE(html.find(Cell("pose", pose) + Cell("r x", StringPrintf("%+.3f", r_x))),
              std::string::npos)
        << "pose " << pose << " residual " << r_x;
  }

  // The parameters with sigma, imu_tk's, the difference, imu_tk's printed value and the
  // datasheet's, for every parameter.
  EXPECT_NE(html.find("<th>parameter</th><th>unit</th><th>ml</th><th>sigma</th><th>imu_tk</th>"
                      "<th>(ml - imu_tk) / sigma</th><th>imu_tk printed</th><th>datasheet</th>"),
            std::string::npos);
  for (const auto& [name, sigma] : json["stddev"].items()) {
    EXPECT_NE(html.find(Cell("sigma", StringPrintf("%.3g", sigma.get<double>()))),
              std::string::npos)
        << name;
    EXPECT_NE(html.find("data-label=\"parameter\">" + name + "</td>"), std::string::npos) << name;
  }
  EXPECT_NE(html.find(">1/414.459</td><td class=\"words\" data-label=\"datasheet\">1/415</td>"),
            std::string::npos);

  // The fit described with the noise model that weighted it (not judged: the verdict is
  // discovery's), the provenance.
  EXPECT_NE(html.find("the pose means weighted by the Allan variance of their samples"),
            std::string::npos);
  EXPECT_EQ(html.find("under white noise"), std::string::npos);
  // Discovery's section: every candidate in its table, what static poses cannot test, the
  // verdict as the JSON gives it.
  EXPECT_NE(html.find("What the model misses (discovery)"), std::string::npos);
  for (const auto& candidate : json["discovery"]["candidates"])
    EXPECT_NE(html.find(candidate["effect"].get<std::string>()), std::string::npos);
  EXPECT_NE(html.find("gravity_error: not testable from static poses"), std::string::npos);
  EXPECT_NE(html.find("Verdict (" + json["verdict"].get<std::string>() + ")"), std::string::npos);
  EXPECT_NE(html.find("on 29 degrees of freedom"), std::string::npos);
  EXPECT_NE(html.find("335a234736ff4dd8741118283d5d4cd389ac54b04d00e6cd8d48ca3e532b7510"),
            std::string::npos);
  EXPECT_NE(html.find("--report="), std::string::npos);  // the command line
  // No number printed as nan or inf (printf's spellings), and none replaced by "n/a".
  for (const char* bad : {"nan<", "nan,", "nan ", "nan)", "inf<", "inf,", "inf ", "inf)", "n/a"})
    EXPECT_EQ(html.find(bad), std::string::npos) << bad;

  // Self-contained: nothing fetched, nothing linked beside the page.
  EXPECT_EQ(html.find("src=\"http"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
  EXPECT_EQ(html.find("<a href"), std::string::npos);

  if (!MatplotlibAvailable()) {
    EXPECT_NE(html.find("Figure not drawn (triad_residuals.png)"), std::string::npos);
    GTEST_SKIP() << "no python3-matplotlib: the figures are not drawn";
  }
  EXPECT_TRUE(IsCompletePng(EmbeddedPng(html, "Whitened residual per pose")));
  EXPECT_TRUE(IsCompletePng(EmbeddedPng(html, "The norm of the specific force")));
  EXPECT_EQ(html.find("not drawn"), std::string::npos);
}

// The fit described on each side of the chi-square, consistent with the one verdict: too large
// and flagged by discovery (the sigmas understate), about right (nothing added), and too small
// and noted (the sigmas are conservative, as on mimu4444 IMU 4 run 3). It never judges.
TEST(FitDescription, SaysWhatTheVerdictImpliesForTheSigmasOnBothTails) {
  TriadMlResult ml;
  ml.degrees_of_freedom = 12;
  for (const double per_dof : {5.0, 1.0, 0.195}) {
    ml.chi2 = per_dof * ml.degrees_of_freedom;
    ml.chi2_per_dof = per_dof;
    ml.chi2_per_dof_spread = std::sqrt(2.0 / ml.degrees_of_freedom);
    ml.p_value = ChiSquareSurvival(ml.chi2, ml.degrees_of_freedom);
    TriadDiscoveryResult discovery;
    discovery.final_fit = ml;
    ResidualCheck chi2;
    chi2.name = "chi2";
    chi2.flagged = per_dof > 1.5;
    discovery.checks = {chi2};
    discovery.verdict_code = chi2.flagged ? Verdict::kUnexplained : Verdict::kExplained;
    discovery.noise_overstated.flagged = per_dof < 0.5;
    const std::string description = FitDescription(ml, false, discovery);
    std::printf("  chi2/dof %g: %s\n", per_dof, description.c_str());
    EXPECT_NE(description.find(StringPrintf("on 12 degrees of freedom, chi2/dof = %.4g", per_dof)),
              std::string::npos)
        << description;
    EXPECT_NE(description.find("weighted by white noise"), std::string::npos) << description;
    EXPECT_EQ(description.find("explain"), std::string::npos) << description;
    EXPECT_EQ(description.find("understate") != std::string::npos, per_dof > 1.5) << description;
    EXPECT_EQ(description.find("conservative") != std::string::npos, per_dof < 0.5) << description;
  }
}

TEST(TriadReport, ARefusedRunWritesNoReport) {
  ACCELCAL_REQUIRE_IMU_TK_DATA(dir);
  testing::ScratchDir scratch;
  const std::string report = scratch.File("report.html");
  const std::string json = scratch.File("out.json");
  // imu_tk's cost gives no per-pose residual to report.
  testing::ExpectBadInputContract(
      RunBinary("calibrate_imu", "--log='" + dir + "/xsens_acc.mat' --mode=imu_tk --json=" + json +
                                     " --report=" + report),
      "calibrate_imu", "--report needs --mode=ml");
  testing::ExpectBadInputContract(
      RunBinary("calibrate_imu", "--mode=ferraris --session=whatever.csv --report=" + report),
      "calibrate_imu", "--report needs --mode=ml");
  // A log the detector cannot use: refused after the flags were accepted.
  std::string text;
  for (int i = 0; i < 50; ++i) text += std::to_string(0.01 * (i + 1)) + " 32768 32768 36800\n";
  const std::string log = scratch.Write("log.txt", text);
  testing::ExpectBadInputContract(RunBinary("calibrate_imu", "--log=" + log + " --mode=ml --json=" +
                                                                 json + " --report=" + report),
                                  "calibrate_imu", "record a longer session");
  EXPECT_FALSE(testing::PathExists(report));
  EXPECT_FALSE(testing::PathExists(json));
}

// Without Python the page is still made, whole, and names the absent figures and why.
TEST(TriadReport, WithoutPythonThePageSaysWhichFiguresAreAbsent) {
  CalibrateImuReport report;
  report.log_path = "/data/log.txt";
  report.mode = "ml";
  report.imu_tk_status = Status::Error("no rest");
  TriadLog log;
  for (int i = 0; i < 300; ++i) log.Add(0.01 * i, 0.0, 0.0, 1.0);
  for (int p = 0; p < 2; ++p) {
    StaticInterval interval;
    interval.start = 150 * p;
    interval.end = 150 * p + 149;
    report.pose_intervals.push_back(interval);
    report.ml.directions.push_back({0.0, 0.0, 1.0});
    report.ml.whitened_residuals.push_back({0.5, -0.25, 1.5});
  }
  report.ml.parameters = TriadParametersWithOffset(0.0, 0.0, 0.0);
  for (int k = 0; k < 3; ++k) report.ml.parameters[kTriadGainX + k] = 9.81;
  report.ml.stddev.fill(0.01);
  report.ml.pose_count = 2;
  std::string html;
  FigureOutcome figures;
  ASSERT_TRUE(TriadReportHtml(log, report, DataSource(),
                              {ACCELCAL_SOURCE_DIR "/tools", "/nonexistent/python3"}, &html,
                              &figures)
                  .ok());
  EXPECT_TRUE(figures.drawn.empty());
  EXPECT_EQ(figures.absent.size(), 2u);
  EXPECT_NE(html.find("<li>2 figures not drawn: the section says why.</li>"), std::string::npos);
  EXPECT_NE(html.find("Figure not drawn (triad_residuals.png): cannot start /nonexistent/python3"),
            std::string::npos)
      << html;
  EXPECT_NE(html.find("Figure not drawn (triad_norm.png): cannot start /nonexistent/python3"),
            std::string::npos);
  EXPECT_EQ(html.find("data:image/png"), std::string::npos);
  EXPECT_NE(html.find("imu_tk's rules give no answer on this log: no rest."), std::string::npos);
  EXPECT_NE(html.rfind("</body></html>\n"), std::string::npos);
}

}  // namespace
}  // namespace accelcal
