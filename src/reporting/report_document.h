#ifndef ACCELCAL_REPORTING_REPORT_DOCUMENT_H_
#define ACCELCAL_REPORTING_REPORT_DOCUMENT_H_

// A report as a short summary, a verdict and a list of sections (paragraphs, one table, one
// figure), rendered to Markdown and to a self-contained HTML page with the figures embedded,
// so the two never differ.

#include <string>
#include <vector>

namespace accelcal {

struct ReportSection {
  std::string title;
  std::vector<std::string> paragraphs;
  std::vector<std::vector<std::string>> table;  // first row: the header
  std::string figure;                           // PNG file name in the report folder, or empty
  std::string figure_caption;
};

struct ReportDocument {
  std::string title;
  std::vector<std::string> summary;  // plain-words lines, shown first ("In short")
  std::string verdict;
  std::vector<ReportSection> sections;
};

std::string RenderMarkdown(const ReportDocument& document);
// `folder` holds the figures, which are embedded as data: URLs; a missing one is named.
std::string RenderHtml(const ReportDocument& document, const std::string& folder);

std::string Base64(const std::string& bytes);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_REPORT_DOCUMENT_H_
