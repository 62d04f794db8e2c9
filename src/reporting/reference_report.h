#ifndef ACCELCAL_REPORTING_REFERENCE_REPORT_H_
#define ACCELCAL_REPORTING_REFERENCE_REPORT_H_

// The reference report (../shared/reference/seed-report.md: University of Buenos Aires,
// Signal Processing 86.51, 2018) beside this analysis. Its printed figures are constants of
// that document, kept in reference_report.cc with the table or section each comes from; this
// analysis' side and every verdict ("agrees to the printed digits", "off by one in the last
// printed digit", "differs") are computed from the run at hand, so on other data the
// comparison says the data differ instead of repeating claims about the course data.

#include <optional>
#include <string>
#include <vector>

#include "reporting/analyze_report.h"

namespace accelcal {

// A number as a document printed it: its value and how many significant digits it printed.
struct PrintedFigure {
  double value = 0.0;
  int significant_digits = 4;
};

enum class Agreement {
  kAgrees,     // the computed value, rounded to the printed digits, is the printed figure
  kLastDigit,  // off by one unit in the last printed digit
  kDiffers,    // further apart
};

Agreement CompareToPrinted(const PrintedFigure& printed, double computed);
// The difference in units of the printed figure's last digit (0.6 for 7.6664e-2 against 7.667e-2).
double UnitsOfLastDigit(const PrintedFigure& printed, double computed);

struct ReferenceRow {
  std::string figure;     // what is compared, with its unit
  std::string reference;  // as the reference report printed or concluded it
  std::string accelcal;   // this analysis, from this run
  std::string verdict;    // computed from the two
  // For a row comparing a printed number: how the two agree.
  std::optional<Agreement> agreement = std::nullopt;
};

struct ReferenceComparison {
  // Whether these are the course data the reference report analysed: its Table 1 is
  // reproduced to within one unit of each estimate's last printed digit.
  bool course_data = false;
  std::string recognition;  // one paragraph: how the data were recognised, or how they differ
  std::vector<ReferenceRow> rows;  // empty when the data are not the course's
  int agreeing_rows = 0;           // rows whose figures agree to the printed digits
  int numeric_rows = 0;            // rows comparing a printed number
  std::string summary;             // one plain-words line for the report's summary, or ""
};

ReferenceComparison CompareWithReferenceReport(const AnalyzeReport& report);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_REFERENCE_REPORT_H_
