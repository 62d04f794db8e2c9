#ifndef ACCELCAL_REPORTING_ANALYZE_REPORT_H_
#define ACCELCAL_REPORTING_ANALYZE_REPORT_H_

// analyze's report folder: report.md and a self-contained report.html (one document: the
// verdict, then baseline, trajectory and landmark, discovery, the joint model and the
// minimum number of samples), results.json with every stage's JSON, each stage's own JSON
// and CSV files, and the figures drawn by the plot scripts in tools/ (a figure that cannot
// be drawn is named in the report with the reason).

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/measurements.h"
#include "common/status.h"
#include "estimation/tilt_table/discovery.h"
#include "io/provenance.h"
#include "reporting/linear_ls_report.h"
#include "reporting/report_document.h"
#include "reporting/trajectory_report.h"
#include "studies/min_samples.h"

namespace accelcal {

struct AnalyzeReport {
  std::string source;              // where the data came from, one line
  DataSource data_source;          // the same with checksums (io/provenance.h)
  nlohmann::json truth = nullptr;  // the simulation's truth, or null for measured data
  CalibrationTest test;            // the tilt test discovery ran on
  std::vector<Landmark> landmarks;
  double alpha = 0.01;
  double max_error = 0.01;
  LinearLsReport linear;
  TrajectoryReport trajectory;
  DiscoveryResult discovery;
  MinSamplesResult min_samples;  // designs without Monte Carlo checks
};

// results.json: {"truth", "linear_ls", "trajectory", "discover", "min_samples"} and the
// provenance keys (source, input_files, command_line, accelcal_version; io/provenance.h).
nlohmann::json AnalyzeJson(const AnalyzeReport& report);

// The plot scripts (tools/plot_*.py) and the Python that runs them.
struct FigureTools {
  std::string tools_dir;
  std::string python;
};

// Runs the plot script `script` of tools.tools_dir with `arguments` (an argument vector, no
// shell); returns "" when it drew, or why the figure is absent (no script, no matplotlib, a
// failure), in words for the report.
std::string Plot(const FigureTools& tools, const std::string& script,
                 const std::vector<std::string>& arguments);

// A report's provenance section: the data line, the version, the date and the command line,
// and every input file with its size and SHA-256.
ReportSection ProvenanceSection(const DataSource& source, const std::string& title);

// Which figures the plot scripts drew, and why each absent one is absent.
struct FigureOutcome {
  std::vector<std::string> drawn;
  std::map<std::string, std::string> absent;  // figure -> why
};

// One line for the console: the figures drawn, or those not drawn and why (a reason shared by
// every absent figure is said once).
std::string FigureOutcomeLine(const FigureOutcome& figures);

// Writes the report folder's files into `dir`; `figures` receives which figures were drawn.
Status WriteAnalyzeReport(const std::string& dir, const AnalyzeReport& report,
                          const FigureTools& tools, FigureOutcome* figures);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_ANALYZE_REPORT_H_
