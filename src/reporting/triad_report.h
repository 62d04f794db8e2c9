#ifndef ACCELCAL_REPORTING_TRIAD_REPORT_H_
#define ACCELCAL_REPORTING_TRIAD_REPORT_H_

// calibrate_imu --mode=ml --report=FILE.html: one self-contained HTML page (the figures are
// embedded as base64 PNG, nothing is fetched) that says what the run found and how far to
// trust it:
//   - the poses the detector found (start, end, duration, mean and noise per axis, gravity
//     direction) and the detector's own figures (noise floor, threshold, still fraction);
//   - the whitened residual of every pose, per axis, as a table and a figure with the +-2 band;
//   - the parameters +- sigma beside imu_tk's (when its rules gave an answer) and, for imu_tk's
//     own Xsens log (recognised by its SHA-256), beside imu_tk's printed values and the
//     datasheet's;
//   - the parameters these poses determine poorly (estimation/triad/triad_determination.h);
//   - the fit statistic described (chi2, dof, p, the noise model that weighted it), and the
//     run's one verdict, discovery's, in the verdict box and its section;
//   - the norm of the calibrated specific force over the log, the poses shaded;
//   - the provenance (the log with its SHA-256, the command line, the version, the date).
// The figures are drawn by tools/plot_triad.py in a temporary folder that is removed
// afterwards; without Python or matplotlib the page is still produced and says which figures
// are absent and why. Formatting only: the caller writes the text with its other outputs.

#include <string>

#include "common/status.h"
#include "common/triad_log.h"
#include "io/provenance.h"
#include "reporting/analyze_report.h"
#include "reporting/calibrate_imu_report.h"

namespace accelcal {

// The page's HTML in `html`; `figures` receives which figures were drawn and why the others
// were not. Fails only when the temporary folder for the figures cannot be made or written.
Status TriadReportHtml(const TriadLog& log, const CalibrateImuReport& report,
                       const DataSource& source, const FigureTools& tools, std::string* html,
                       FigureOutcome* figures);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_TRIAD_REPORT_H_
