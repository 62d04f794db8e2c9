// The main job: one command from data to a report folder whose figures are embedded, whose
// results agree with the individual binaries, and which is never left half-written.

#include <dirent.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "common/format.h"
#include "reporting/report_document.h"
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
  // The summary, then the verdict, come first in both reports.
  const std::string markdown = testing::ReadText(report + "/report.md");
  EXPECT_EQ(markdown.find("# accelcal report\n\n**In short.**\n\n- The vehicle reached C"), 0u)
      << markdown.substr(0, 200);
  EXPECT_LT(markdown.find("\n**Verdict.** the baseline explains the data"), markdown.find("\n## "))
      << markdown.substr(0, 1000);
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
  // Issue 18: the console said "(and ... figures)" while the report said none were drawn; it
  // says what happened and why, as the report does.
  EXPECT_EQ(result.stdout_text.find("figures)"), std::string::npos) << result.stdout_text;
  EXPECT_NE(result.stdout_text.find("\n  figures: none drawn: cannot start /nonexistent/python3"),
            std::string::npos)
      << result.stdout_text;
}

TEST(AnalyzeBinary, TheConsoleNamesTheFiguresDrawn) {
  if (!MatplotlibAvailable()) GTEST_SKIP() << "no python3-matplotlib: figures are not drawn";
  ScratchDir out;
  const CommandResult result = RunBinary("analyze", "--out_dir='" + out.File("report") + "'");
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  EXPECT_NE(result.stdout_text.find(
                "\n  figures: all drawn (trajectory.png, discovery.png, min_samples.png)"),
            std::string::npos)
      << result.stdout_text;
}

// The cells of the Markdown table that follows `heading` in `markdown`, header row first.
std::vector<std::vector<std::string>> MarkdownTable(const std::string& markdown,
                                                    const std::string& heading) {
  std::vector<std::vector<std::string>> rows;
  size_t at = markdown.find(heading);
  if (at == std::string::npos) return rows;
  at = markdown.find("\n|", at);
  while (at != std::string::npos && at + 1 < markdown.size() && markdown[at + 1] == '|') {
    const size_t end = markdown.find('\n', at + 1);
    const std::string line = markdown.substr(at + 1, end - at - 1);
    std::vector<std::string> cells;
    // A cell's own '|' is escaped as "\|".
    for (size_t from = 1, bar = 0; (bar = line.find('|', bar + 1)) != std::string::npos;) {
      if (line[bar - 1] == '\\') continue;
      std::string cell = line.substr(from, bar - from);
      from = bar + 1;
      for (size_t at; (at = cell.find("\\|")) != std::string::npos;) cell.erase(at, 1);
      cell.erase(0, cell.find_first_not_of(' '));
      cell.erase(cell.find_last_not_of(' ') + 1);
      cells.push_back(cell);
    }
    if (cells.empty() || cells[0] != "---") rows.push_back(cells);
    at = end;
  }
  return rows;
}

// Issue 18: the discovery table marked nonorthogonality significant at step 1 beside a
// verdict naming only angle_offset, because the step-2 rows were filtered out. Every row
// the table marks significant or added must be accounted for: added and in the final
// effects (or said dropped), or said to be scored again at a later step that the table shows.
TEST(AnalyzeBinary, TheDiscoveryTableAgreesWithTheVerdict) {
  ScratchDir out;
  const std::string report = out.File("report");
  const CommandResult result =
      RunBinary("analyze", "--out_dir='" + report + "' --python=/nonexistent/python3");
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  const nlohmann::json results = nlohmann::json::parse(testing::ReadText(report + "/results.json"));
  std::set<std::string> effects;
  for (const auto& effect : results["discover"]["effects"]) effects.insert(effect["name"]);
  const std::string markdown = testing::ReadText(report + "/report.md");
  const auto table = MarkdownTable(markdown, "## 3. What the baseline gets wrong");
  ASSERT_GE(table.size(), 2u) << markdown;
  const std::vector<std::string> header = {"step",    "candidate",   "delta chi2",
                                           "p-value", "significant", "outcome"};
  ASSERT_EQ(table[0], header);
  // (step, candidate) of every row, and every step's rows as many as the JSON's.
  std::set<std::pair<int, std::string>> shown;
  for (size_t r = 1; r < table.size(); ++r) shown.insert({std::stoi(table[r][0]), table[r][1]});
  EXPECT_EQ(shown.size(), results["discover"]["candidates"].size());
  int significant_rows = 0;
  for (size_t r = 1; r < table.size(); ++r) {
    const std::vector<std::string>& row = table[r];
    SCOPED_TRACE(row[0] + " " + row[1]);
    const std::string& outcome = row[5];
    if (outcome.rfind("added", 0) == 0) {
      EXPECT_TRUE(effects.count(row[1]) == 1 || outcome.find("dropped") != std::string::npos)
          << outcome;
      if (effects.count(row[1]) == 1) {
        EXPECT_NE(markdown.find("**Verdict.**"), std::string::npos);
        EXPECT_NE(markdown.substr(0, markdown.find("\n## ")).find(row[1]), std::string::npos)
            << "an effect of the final model the verdict does not name";
      }
    }
    if (row[4] != "yes") continue;
    ++significant_rows;
    if (outcome.rfind("added", 0) == 0) continue;
    const std::string again = "scored again at step ";
    const size_t at = outcome.find(again);
    ASSERT_NE(at, std::string::npos) << "significant, neither added nor re-scored: " << outcome;
    const int later = std::stoi(outcome.substr(at + again.size()));
    EXPECT_GT(later, std::stoi(row[0]));
    EXPECT_EQ(shown.count({later, row[1]}), 1u) << "the table does not show step " << later;
  }
  EXPECT_GE(significant_rows, 2);  // angle_offset and nonorthogonality at step 1
  EXPECT_NE(markdown.find("How the model grew: step 1 added angle_offset"), std::string::npos)
      << markdown;
}

// The line of `text` that starts with `start` (without its newline), or "".
std::string LineStartingWith(const std::string& text, const std::string& start) {
  const size_t at = text.find("\n" + start);
  if (at == std::string::npos) return "";
  return text.substr(at + 1, text.find('\n', at + 1) - at - 1);
}

// The report's first lines say, in words, what results.json says: the landmark reached, how
// many sigma away it and the nearest other one are, the baseline's chi-square and discovery's
// verdict.
void ExpectSummaryAgreesWithResults(const std::string& markdown, const nlohmann::json& results) {
  const std::string summary = markdown.substr(0, markdown.find("\n**Verdict.**"));
  const nlohmann::json& trajectory = results["trajectory"];
  ASSERT_TRUE(trajectory["reached"].is_string()) << trajectory["reached"];
  const std::string reached = trajectory["reached"];
  double reached_sigmas = -1.0;
  double nearest_other = HUGE_VAL;
  std::string nearest_name;
  for (const auto& landmark : trajectory["landmarks"]) {
    const double sigmas = std::sqrt(landmark["mahalanobis2"].get<double>());
    if (landmark["name"] == reached) {
      reached_sigmas = sigmas;
    } else if (sigmas < nearest_other) {
      nearest_other = sigmas;
      nearest_name = landmark["name"];
    }
  }
  const std::string landmark_line = LineStartingWith(summary, "- The vehicle reached ");
  EXPECT_EQ(landmark_line.find(StringPrintf("- The vehicle reached %s: the endpoint is %.2f sigma "
                                            "from it (p = %.3g)",
                                            reached.c_str(), reached_sigmas,
                                            trajectory["p_value"].get<double>())),
            0u)
      << summary;
  EXPECT_NE(landmark_line.find(StringPrintf(
                "every other landmark is more than %.0f sigma away (the nearest, %s, %.2f sigma)",
                std::floor(nearest_other), nearest_name.c_str(), nearest_other)),
            std::string::npos)
      << landmark_line;
  const std::string baseline_line = LineStartingWith(summary, "- The baseline fit");
  EXPECT_NE(baseline_line.find(StringPrintf("chi2/dof %.4f in x",
                                            results["linear_ls"]["chi2"]["x"].get<double>() /
                                                results["linear_ls"]["dof"]["x"].get<double>())),
            std::string::npos)
      << baseline_line;
  EXPECT_NE(baseline_line.find(results["discover"]["verdict"].get<std::string>()),
            std::string::npos)
      << baseline_line;
}

// `value` in the report's comparison form, `digits` significant: 7.6664e-2, -1.7508e-2.
std::string Scientific(const nlohmann::json& value, int digits) {
  std::string text = StringPrintf("%.*e", digits - 1, value.get<double>());
  const size_t e = text.find('e');
  const std::string sign = text[e + 1] == '-' ? "-" : "";
  const size_t first = text.find_first_not_of('0', e + 2);
  return text.substr(0, e + 1) + sign + text.substr(first);
}

// Runs analyze without figures; returns report.md and results.json.
void RunAnalyzeWithoutFigures(const std::string& arguments, std::string* markdown,
                              nlohmann::json* results) {
  ScratchDir out;
  const std::string report = out.File("report");
  const CommandResult result =
      RunBinary("analyze", arguments + " --out_dir='" + report + "' --python=/nonexistent/python3");
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  *markdown = testing::ReadText(report + "/report.md");
  *results = nlohmann::json::parse(testing::ReadText(report + "/results.json"));
}

// Issue 18 item 5: the report starts with a summary in plain words, computed from the results.
TEST(AnalyzeBinary, TheSummaryNamesTheLandmarkTheDecisionReached) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  std::string markdown;
  nlohmann::json results;
  RunAnalyzeWithoutFigures("--data_dir='" + dir + "'", &markdown, &results);
  ASSERT_EQ(results["trajectory"]["reached"], "C");
  ExpectSummaryAgreesWithResults(markdown, results);
  EXPECT_NE(
      markdown.find("- The vehicle reached C: the endpoint is 0.95 sigma from it (p = 0.634); "
                    "every other landmark is more than 7 sigma away (the nearest, D, 7.16 "
                    "sigma)."),
      std::string::npos)
      << markdown.substr(0, 1500);
  EXPECT_NE(markdown.find("the stated noise explains the size of its residuals"),
            std::string::npos);
}

TEST(AnalyzeBinary, TheSummaryOfASimulationWithAHiddenEffectSaysWhatDiscoveryFound) {
  std::string markdown;
  nlohmann::json results;
  RunAnalyzeWithoutFigures("--set=angle_offset=0.004", &markdown, &results);
  ExpectSummaryAgreesWithResults(markdown, results);
  const std::string summary = markdown.substr(0, markdown.find("\n**Verdict.**"));
  EXPECT_NE(summary.find("Yet discovery, which looks beyond their size, finds: missing: "
                         "angle_offset"),
            std::string::npos)
      << summary;
  EXPECT_NE(summary.find("- These data are simulated: the truth hidden in them is angle_offset = "
                         "0.004 rad, and the run ends at C."),
            std::string::npos)
      << summary;
  EXPECT_EQ(summary.find("The reference report"), std::string::npos) << summary;
}

// The row of `table` whose first cell starts with `figure`.
std::vector<std::string> RowStartingWith(const std::vector<std::vector<std::string>>& table,
                                         const std::string& figure) {
  for (const auto& row : table)
    if (!row.empty() && row[0].rfind(figure, 0) == 0) return row;
  return {};
}

// Issue 18 item 5: the reference report's printed figures beside this run's, each verdict
// computed; this run's side must be the numbers of results.json.
TEST(AnalyzeBinary, OnTheCourseDataTheReportSetsTheReferenceReportBesideItsOwnFigures) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  std::string markdown;
  nlohmann::json results;
  RunAnalyzeWithoutFigures("--data_dir='" + dir + "'", &markdown, &results);
  const auto table = MarkdownTable(markdown, "## 6. The reference report and this analysis");
  ASSERT_GE(table.size(), 2u) << markdown;
  const std::vector<std::string> header = {"figure", "reference report", "this analysis",
                                           "verdict"};
  ASSERT_EQ(table[0], header);
  EXPECT_NE(markdown.find("These are the course data the reference report analysed"),
            std::string::npos);

  const nlohmann::json& parameters = results["linear_ls"]["parameters"];
  const std::vector<std::string> b_x = RowStartingWith(table, "b_x");
  ASSERT_EQ(b_x.size(), 4u);
  EXPECT_EQ(b_x[1], "7.667e-2");
  EXPECT_EQ(b_x[2], Scientific(parameters["bias_x"], 5))
      << "this analysis' b_x is not results.json's";
  EXPECT_EQ(b_x[3].rfind("off by one in the last printed digit", 0), 0u) << b_x[3];
  EXPECT_EQ(RowStartingWith(table, "s_x")[3], "agrees to the printed digits");

  const std::vector<std::string> var_b_x = RowStartingWith(table, "var b_x");
  ASSERT_EQ(var_b_x.size(), 4u);
  EXPECT_EQ(var_b_x[1], "1.245e-5");
  EXPECT_EQ(var_b_x[2], Scientific(results["linear_ls"]["covariance"][0][0], 5));
  EXPECT_EQ(var_b_x[3].rfind("differs by 4.9 units of the last printed digit", 0), 0u)
      << var_b_x[3];
  EXPECT_NE(var_b_x[3].find("sigma^2/N = 0.25/20001 = 1.24994e-05 here; a transcription error"),
            std::string::npos)
      << var_b_x[3];

  const std::vector<std::string> model = RowStartingWith(table, "the model (section 1)");
  ASSERT_EQ(model.size(), 4u);
  EXPECT_NE(model[2].find("eq. (2) would give b_x = 7.86e-2, s_x = -2.54e-2"), std::string::npos)
      << model[2];
  EXPECT_EQ(model[3].rfind("Table 1 follows the spec's model", 0), 0u) << model[3];

  const std::vector<std::string> landmark = RowStartingWith(table, "landmark reached");
  ASSERT_EQ(landmark.size(), 4u);
  EXPECT_EQ(landmark[1], "none");
  EXPECT_EQ(landmark[2].rfind("reached " + results["trajectory"]["reached"].get<std::string>() +
                                  ", 0.95 sigma away",
                              0),
            0u)
      << landmark[2];
  EXPECT_EQ(landmark[3].rfind("differs", 0), 0u);

  const std::vector<std::string> bound = RowStartingWith(table, "endpoint error bound");
  ASSERT_EQ(bound.size(), 4u);
  const nlohmann::json& budget = results["trajectory"]["error_budget"];
  ASSERT_TRUE(budget.is_array()) << budget;
  EXPECT_NE(bound[1].find(StringPrintf("%.2f m (x)", budget[0]["report_bound_m"].get<double>())),
            std::string::npos)
      << bound[1] << "\n"
      << budget[0];

  const std::vector<std::string> samples = RowStartingWith(table, "samples needed");
  ASSERT_EQ(samples.size(), 4u);
  EXPECT_EQ(samples[1], "N_x = 2222, N_y = 185466 (per-axis bounds)");
  int uniform_n_min = -1;
  for (const auto& design : results["min_samples"]["designs"])
    if (design["name"] == "uniform") uniform_n_min = design["n_min"];
  EXPECT_EQ(samples[2].rfind(StringPrintf("N = %d: ", uniform_n_min), 0), 0u) << samples[2];
  EXPECT_NE(samples[3].find("so no N meets it"), std::string::npos) << samples[3];

  EXPECT_EQ(RowStartingWith(table, "d_min,x")[3], "agrees to the printed digits");
  EXPECT_EQ(RowStartingWith(table, "d_min,y")[3], "agrees to the printed digits");
  // The summary counts what the table shows.
  int agreeing = 0;
  int numeric = 0;
  for (size_t r = 1; r < table.size(); ++r) {
    const std::string& verdict = table[r][3];
    const bool agrees = verdict.rfind("agrees to the printed digits", 0) == 0 ||
                        verdict.rfind("agrees within the rounding", 0) == 0;
    agreeing += agrees ? 1 : 0;
    numeric += agrees || verdict.rfind("off by one", 0) == 0 || verdict.rfind("differs by", 0) == 0;
  }
  EXPECT_NE(markdown.find(StringPrintf("- The reference report (2018): %d of the %d figures it "
                                       "printed agree to their printed digits (b_x is off by one "
                                       "in its last digit, var b_x differs); its conclusion that "
                                       "the run reaches no landmark does not hold: it reaches C.",
                                       agreeing, numeric)),
            std::string::npos)
      << markdown.substr(0, 1500);
}

TEST(AnalyzeBinary, OnSimulatedDataTheReferenceSectionSaysTheDataDiffer) {
  std::string markdown;
  nlohmann::json results;
  RunAnalyzeWithoutFigures("--set=", &markdown, &results);
  const size_t section = markdown.find("## 6. The reference report and this analysis\n\n");
  ASSERT_NE(section, std::string::npos) << markdown;
  const std::string text = markdown.substr(section, markdown.find("\n## ", section + 1) - section);
  EXPECT_NE(text.find("These are not the course data the reference report analysed"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("b_x = " + Scientific(results["linear_ls"]["parameters"]["bias_x"], 5) +
                      " where the report has 7.667e-2"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find('|'), std::string::npos) << "a comparison table on other data: " << text;
  EXPECT_EQ(markdown.find("The reference report (2018)"), std::string::npos);
}

// Issue 18 item 5: the joint column differs from the linear one on the course data although
// discovery added nothing; the report says why (the run tied to the landmark), with the shifts
// its table shows.
TEST(AnalyzeBinary, TheJointSectionSaysWhyItsColumnMoves) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  std::string markdown;
  nlohmann::json results;
  RunAnalyzeWithoutFigures("--data_dir='" + dir + "'", &markdown, &results);
  const std::string tied = results["discover"]["tied_landmark"];
  ASSERT_EQ(tied, "C");
  const std::string paragraph = LineStartingWith(markdown, "Why the joint column moves: ");
  ASSERT_FALSE(paragraph.empty()) << markdown;
  EXPECT_EQ(paragraph.rfind("Why the joint column moves: the joint problem ties the run's endpoint "
                            "to " +
                                tied + ", the landmark decided",
                            0),
            0u)
      << paragraph;
  EXPECT_NE(paragraph.find("Discovery added no effect, so this is the whole shift."),
            std::string::npos)
      << paragraph;
  // Each shift the paragraph names is the table's.
  const auto table = MarkdownTable(markdown, "## 4. The joint model");
  ASSERT_GE(table.size(), 5u);
  int named = 0;
  for (size_t r = 1; r < table.size(); ++r) {
    const std::string& shift = table[r][4];
    if (shift.empty() || std::abs(std::stod(shift)) < 0.05) continue;
    ++named;
    EXPECT_NE(paragraph.find(table[r][0] + " " + shift + " sigma"), std::string::npos)
        << table[r][0] << " " << shift << " is not in: " << paragraph;
  }
  EXPECT_EQ(named, 2);  // bias_x and bias_y
}

// Issue 18: at 390 px the tables were cut off (no viewport tag, nothing scrolled).
TEST(ReportDocument, TheHtmlFitsAPhone) {
  ReportDocument document;
  document.title = "a report";
  document.verdict = "fine";
  for (int k = 0; k < 2; ++k) {
    ReportSection section;
    section.title = "section";
    section.table = {{"a", "b", "c", "d", "e", "f"}, {"1", "2", "3", "4", "5", "6"}};
    section.figure = "absent.png";
    document.sections.push_back(section);
  }
  const std::string html = RenderHtml(document, "/nonexistent");
  const size_t head_end = html.find("</head>");
  ASSERT_NE(head_end, std::string::npos);
  EXPECT_NE(html.substr(0, head_end)
                .find("<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"),
            std::string::npos)
      << html;
  // Every table sits directly in a wrapper that scrolls sideways.
  const std::string wrapper = "<div class=\"table-scroll\">\n<table>";
  int tables = 0;
  for (size_t at = html.find("<table"); at != std::string::npos; at = html.find("<table", at + 1)) {
    ++tables;
    ASSERT_GE(at, wrapper.size() - 7);
    EXPECT_EQ(html.compare(at - (wrapper.size() - 7), wrapper.size(), wrapper), 0)
        << html.substr(at - 40, 60);
    EXPECT_NE(html.find("</table>\n</div>", at), std::string::npos);
  }
  EXPECT_EQ(tables, 2);
  EXPECT_NE(html.find(".table-scroll{overflow-x:auto"), std::string::npos);
  EXPECT_NE(html.find("img{max-width:100%"), std::string::npos);
}

// A stand-in for --python that interrupts the run that started it: analyze starts the
// plotter only once it is filling its staging folder (results.json and the CSVs written, the
// figures and report.md/html not yet), so the signal lands mid-write by construction, not
// after a guessed sleep. The plotter records the staging folder's name and listing at that
// moment, then sends `signal_name` to its parent, analyze. Its first call (`-c "import
// matplotlib, numpy"`) only succeeds.
std::string WriteInterruptingPlotter(const ScratchDir& scratch, const std::string& signal_name) {
  const std::string path =
      scratch.Write("interrupting_python",
                    "#!/bin/sh\n"
                    "case \"$1\" in -c) exit 0 ;; esac\n"
                    "for argument in \"$@\"; do\n"
                    "  case \"$argument\" in --json=*) json=\"${argument#--json=}\" ;; esac\n"
                    "done\n"
                    "staging=$(dirname \"$json\")\n"
                    "ls -A \"$staging\" > '" +
                        scratch.File("listing") +
                        "'\n"
                        "echo \"$staging\" > '" +
                        scratch.File("staging") +
                        "'\n"
                        "kill -" +
                        signal_name +
                        " $PPID\n"
                        "exit 0\n");
  chmod(path.c_str(), 0755);
  return path;
}

// Runs analyze with `arguments` (no shell) and returns its wait status.
int RunAnalyzeDirectly(const std::vector<std::string>& arguments) {
  return testing::SpawnBinary("analyze", arguments, "/dev/null", "/dev/null");
}

// The folder's entries beside `path` whose names start with path's name + ".tmp.".
std::vector<std::string> StagingFoldersBeside(const std::string& path) {
  const std::string parent = path.substr(0, path.rfind('/'));
  const std::string prefix = path.substr(path.rfind('/') + 1) + ".tmp.";
  std::vector<std::string> found;
  DIR* dir = opendir(parent.c_str());
  if (dir == nullptr) return found;
  while (const dirent* entry = readdir(dir)) {
    if (std::string(entry->d_name).rfind(prefix, 0) == 0) found.push_back(entry->d_name);
  }
  closedir(dir);
  return found;
}

// What the plotter saw when it sent the signal: the staging folder beside `report` (not
// `report` itself), part-way filled.
void ExpectKilledWhileWriting(const ScratchDir& scratch, const std::string& report) {
  std::string staging = testing::ReadText(scratch.File("staging"));
  ASSERT_FALSE(staging.empty()) << "the plotter never ran: the signal was not sent mid-write";
  staging.pop_back();  // the newline
  EXPECT_EQ(staging.rfind(report + ".tmp.", 0), 0u) << staging;
  const std::string listing = testing::ReadText(scratch.File("listing"));
  EXPECT_NE(listing.find(".accelcal-output\n"), std::string::npos) << listing;
  EXPECT_NE(listing.find("results.json\n"), std::string::npos) << listing;
  EXPECT_EQ(listing.find("report.html"), std::string::npos) << listing;  // not yet written
}

TEST(AnalyzeBinary, KilledWhileWritingItLeavesNoReportFolder) {
  ScratchDir scratch;
  const std::string report = scratch.File("report");
  const std::string plotter = WriteInterruptingPlotter(scratch, "KILL");
  const int status = RunAnalyzeDirectly({"--out_dir=" + report, "--python=" + plotter});
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL)
      << "analyze was not killed (wait status " << status << ")";
  ExpectKilledWhileWriting(scratch, report);
  EXPECT_FALSE(testing::PathExists(report));
  // SIGKILL cannot be caught: the staging folder stays beside --out_dir, never at it.
  EXPECT_EQ(StagingFoldersBeside(report).size(), 1u);
}

TEST(AnalyzeBinary, InterruptedWhileWritingItLeavesNothingAtAll) {
  for (const char* signal_name : {"TERM", "INT"}) {
    SCOPED_TRACE(signal_name);
    ScratchDir scratch;
    const std::string report = scratch.File("report");
    const std::string plotter = WriteInterruptingPlotter(scratch, signal_name);
    const int status = RunAnalyzeDirectly({"--out_dir=" + report, "--python=" + plotter});
    EXPECT_FALSE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "analyze finished normally";
    ExpectKilledWhileWriting(scratch, report);
    EXPECT_FALSE(testing::PathExists(report));
    // A signal it can catch: the staging folder is removed too.
    EXPECT_TRUE(StagingFoldersBeside(report).empty());
  }
}

TEST(AnalyzeBinary, AFinishedReportOutlivesARefusedAndAKilledOverwrite) {
  ScratchDir scratch;
  const std::string report = scratch.File("report");
  ASSERT_EQ(RunBinary("analyze", "--out_dir='" + report + "' --set= --python=/nonexistent/python3")
                .exit_status,
            0);
  const std::string before = testing::ReadText(report + "/results.json");
  const std::string markdown_before = testing::ReadText(report + "/report.md");
  ASSERT_FALSE(before.empty());
  testing::ExpectBadInputContract(RunBinary("analyze", "--out_dir='" + report + "'"), "analyze",
                                  "exists and is not empty; pass --overwrite");
  // The overwrite computes a different report (angle_offset hidden), killed mid-write.
  const std::string plotter = WriteInterruptingPlotter(scratch, "KILL");
  const int status =
      RunAnalyzeDirectly({"--overwrite", "--out_dir=" + report, "--python=" + plotter});
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << "wait status " << status;
  ExpectKilledWhileWriting(scratch, report);
  EXPECT_EQ(testing::ReadText(report + "/results.json"), before);
  EXPECT_EQ(testing::ReadText(report + "/report.md"), markdown_before);
}

}  // namespace
}  // namespace accelcal
