// The reference report's printed figures against computed ones: "agrees to the printed digits"
// means the computed value rounds to the printed one, and a table of sentences is shown as
// blocks on a phone.

#include "reporting/reference_report.h"

#include <gtest/gtest.h>

#include "reporting/report_document.h"

namespace accelcal {
namespace {

TEST(ReferenceReport, ComparesToThePrintedDigits) {
  // Table 1's b_x: 7.6664e-2 rounds to 7.666e-2, one unit below the printed 7.667e-2.
  EXPECT_EQ(CompareToPrinted({7.667e-2, 4}, 7.6664e-2), Agreement::kLastDigit);
  EXPECT_NEAR(UnitsOfLastDigit({7.667e-2, 4}, 7.6664e-2), -0.6, 1e-9);
  EXPECT_EQ(CompareToPrinted({-3.014e-2, 4}, -3.0142e-2), Agreement::kAgrees);
  EXPECT_EQ(CompareToPrinted({-3.014e-2, 4}, -3.0145e-2), Agreement::kAgrees);  // rounds either way
  EXPECT_EQ(CompareToPrinted({-3.014e-2, 4}, -3.0146e-2), Agreement::kLastDigit);
  // var b_x: 1.2499e-5 is 4.9 units of the printed 1.245e-5's last digit away.
  EXPECT_EQ(CompareToPrinted({1.245e-5, 4}, 1.2499e-5), Agreement::kDiffers);
  EXPECT_NEAR(UnitsOfLastDigit({1.245e-5, 4}, 1.2499e-5), 4.9, 1e-9);
  EXPECT_EQ(CompareToPrinted({13.26, 4}, 13.2600001), Agreement::kAgrees);
  EXPECT_EQ(CompareToPrinted({1.620, 4}, 1.6212), Agreement::kLastDigit);
  EXPECT_EQ(CompareToPrinted({1.620, 4}, 1.6216), Agreement::kDiffers);
}

TEST(ReportDocument, ATableOfSentencesIsShownAsBlocksOnAPhone) {
  ReportDocument document;
  document.title = "a report";
  document.summary = {"first line", "second line"};
  ReportSection numbers;
  numbers.title = "numbers";
  numbers.table = {{"a", "b"}, {"1.5", "2e-3"}};
  ReportSection sentences;
  sentences.title = "sentences";
  sentences.table = {{"figure", "verdict"},
                     {"b_x", "off by one in the last printed digit: a rounding slip, as it says"}};
  document.sections = {numbers, sentences};
  const std::string html = RenderHtml(document, "/nonexistent");
  EXPECT_NE(html.find("<b>In short.</b>\n<ul>\n<li>first line</li>\n<li>second line</li>"),
            std::string::npos)
      << html;
  EXPECT_LT(html.find("In short."), html.find("class=\"verdict\""));
  EXPECT_NE(html.find("<div class=\"table-scroll\">\n<table>\n<tr><th>a</th>"), std::string::npos);
  EXPECT_NE(html.find("<div class=\"table-scroll\">\n<table class=\"stack\">\n<tr><th>figure</th>"),
            std::string::npos)
      << html;
  EXPECT_NE(html.find("<td class=\"words long\" data-label=\"verdict\">off by one"),
            std::string::npos)
      << html;
  EXPECT_NE(html.find("table.stack td::before{content:attr(data-label)"), std::string::npos);
  const std::string markdown = RenderMarkdown(document);
  EXPECT_EQ(
      markdown.find("# a report\n\n**In short.**\n\n- first line\n- second line\n\n**Verdict.**"),
      0u)
      << markdown;
}

}  // namespace
}  // namespace accelcal
