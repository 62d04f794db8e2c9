#ifndef ACCELCAL_REPORTING_CALIBRATE_IMU_REPORT_H_
#define ACCELCAL_REPORTING_CALIBRATE_IMU_REPORT_H_

// What calibrate_imu prints and writes. In imu_tk mode: the threshold sweep, the chosen k, the
// parameters with their units (beside imu_tk's printed values and the datasheet's when the
// log is imu_tk's own Xsens example, recognised by its SHA-256), the static intervals. In ml mode:
// the maximum-likelihood parameters ± sigma beside imu_tk's and their difference in sigma, the
// covariance, the parameters the poses determine poorly, the fit statistic described and
// discovery's verdict, the run's one verdict. The text and the JSON come from the same numbers.
// Formatting only.

#include <Eigen/Core>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/triad_log.h"
#include "estimation/gyroscope/gyroscope_discovery.h"
#include "estimation/gyroscope/gyroscope_ml_calibration.h"
#include "estimation/gyroscope/imu_tk_gyroscope_calibration.h"
#include "estimation/triad/imu_tk_calibration.h"
#include "estimation/triad/noise_floor_detector.h"
#include "estimation/triad/triad_determination.h"
#include "estimation/triad/triad_discovery.h"
#include "estimation/triad/triad_ml_calibration.h"
#include "estimation/triad/triad_pose_noise.h"
#include "estimation/triad/triad_session_calibration.h"
#include "io/calibration_file.h"
#include "io/imu_log.h"
#include "io/provenance.h"
#include "models/gyroscope_units.h"
#include "models/triad_units.h"

namespace accelcal {

struct CalibrateImuReport {
  std::string log_path;
  std::string log_layout;                          // ImuLogSource::layout
  std::vector<std::string> log_notes;              // what the reader chose, to be printed
  ImuLogTiming log_timing;                         // how the samples' times were found
  std::vector<std::string> log_metadata;           // lines before the header, skipped
  size_t gyroscope_samples = 0;                    // read beside the accelerometer's, or 0
  std::string log_sha256;                          // to recognise imu_tk's example log
  TriadOutputUnit unit = TriadOutputUnit::kCount;  // the log's, as the user stated it
  size_t sample_count = 0;
  double first_t_s = 0.0;
  double last_t_s = 0.0;
  double rest_end_s = 0.0;
  ImuTkOptions options;
  std::string initial_offset_from;  // how the start's offsets were chosen
  ImuTkResult result;
  std::string mode = "imu_tk";  // "imu_tk" or "ml"
  // Mode imu_tk on a log with a gyroscope: imu_tk's gyroscope calibration
  // (estimation/gyroscope/imu_tk_gyroscope_calibration.h) after the accelerometer's.
  bool has_gyroscope_calibration = false;
  std::string gyroscope_path;    // --gyro_log, or "" for the log's own gyroscope columns
  std::string gyroscope_sha256;  // --gyro_log's, to recognise imu_tk's example
  GyroscopeOutputUnit gyroscope_unit = GyroscopeOutputUnit::kCount;
  std::string initial_gyro_gain_from;  // how the start's gains were chosen
  ImuTkGyroscopeOptions gyroscope_options;
  ImuTkGyroscopeResult gyroscope;
  // Mode ml on a log with a gyroscope: its maximum-likelihood calibration
  // (estimation/gyroscope/gyroscope_ml_calibration.h); imu_tk's above beside it when its rules
  // gave one (has_gyroscope_calibration), else why not.
  bool has_gyroscope_ml = false;
  GyroscopeMlOptions gyroscope_ml_options;
  // The gyroscope's calibration: the model discovery settled on (its final fit when it found
  // effects, which it then carries; else the 12 unknowns' fit, discovery's baseline, which is
  // gyroscope_discovery.baseline either way).
  GyroscopeMlResult gyroscope_ml;
  GyroscopeDiscoveryOptions gyroscope_discovery_options;
  GyroscopeDiscoveryResult gyroscope_discovery;
  Status imu_tk_gyroscope_status;
  // --imu_tk_calib_out's two files, when asked for ("" when not written).
  std::string imu_tk_calib_acc_path;
  std::string imu_tk_calib_gyro_path;
  // Mode ml: the poses of the detector ("noise_floor" or "imu_tk"), the maximum-likelihood
  // fit, and imu_tk's result beside it when its rules gave one (imu_tk_status says why not).
  std::string detector = "noise_floor";
  // Set when the noise floor's detector refused (its message) and imu_tk's intervals stood in.
  std::string detector_fallback_reason;
  NoiseFloorOptions noise_floor_options;
  NoiseFloorDetection noise_floor;
  std::vector<StaticInterval> pose_intervals;  // one per pose of the fit
  Status imu_tk_status;
  TriadMlOptions ml_options;
  // The accelerometer's calibration: the model discovery settled on (its final fit when it kept
  // effects; else the maximum-likelihood fit of ml_options), what the outputs and the
  // calibration file give; and, when it carries effect terms, the 9-parameter fit beside it
  // (discovery's baseline; has_ml_baseline).
  TriadMlResult ml;
  bool has_ml_baseline = false;
  TriadMlResult ml_baseline;
  int ml_sample_count = 0;  // samples in the poses' means
  // Mode ml: the Allan model of the pose means, and whether the fit uses it (else white).
  TriadPoseNoise pose_noise;
  bool allan_noise = false;
  // Mode ml: what the 9-parameter model misses (estimation/triad/triad_discovery.h).
  TriadDiscoveryOptions discovery_options;
  TriadDiscoveryResult discovery;
  // Mode ml: the parameters these poses determine too loosely to vouch for
  // (estimation/triad/triad_determination.h), filled by TakeSessionCalibration.
  std::vector<TriadPoorlyDetermined> poorly_determined;
};

// Mode ml: one session's calibration (estimation/triad/triad_session_calibration.h) into the fields
// above, which this report, reporting/triad_report.cc and tools/bench/triad_bench.cc read; `ml`
// becomes the model discovery settled on (TriadSettledModel).
bool TriadDiscoveryKeptEffects(const TriadDiscoveryResult& discovery);
// The effect terms a fit estimated, in the block's order (as the calibration file lists them),
// and its covariance over the 9 and them, in that order.
std::vector<int> TriadTermsInOrder(const TriadMlResult& ml);
Eigen::MatrixXd TriadMlCovariance(const TriadMlResult& ml);
// Mode ml: one session's calibration into the report, as above.
void TakeSessionCalibration(TriadSessionCalibration session, CalibrateImuReport* report);

// The SHA-256 of imu_tk's bin/test_data/xsens_acc.mat (../shared/data/imu_tk-xsens/SOURCE.txt).
constexpr char kImuTkXsensAccSha256[] =
    "335a234736ff4dd8741118283d5d4cd389ac54b04d00e6cd8d48ca3e532b7510";

// What imu_tk printed on its Xsens example (issue 20) and the sensor's datasheet values
// (SOURCE.txt), in block order, as printed; shown only beside a run on that very file, which
// IsImuTkExample recognises (its SHA-256 and imu_tk's own sweep of k).
extern const char* const kImuTkPrinted[kTriadParameterCount];
extern const char* const kDatasheet[kTriadParameterCount];
bool IsImuTkExample(const CalibrateImuReport& report);

// The SHA-256 of imu_tk's bin/test_data/xsens_gyro.mat, the example's gyroscope file.
constexpr char kImuTkXsensGyroSha256[] =
    "e0d6cc7ccbc996aba3dae5063e97360a8b765ad1dffd02eae8ec69820eb37c1d";
// The datasheet's value of gyroscope parameter i (the 9, then the offsets) on imu_tk's Xsens
// pair, as SOURCE.txt gives it ("-" for the misalignments it does not give).
const char* DatasheetGyroscopeValue(int i);
// The gyroscope's calibration ran on imu_tk's example pair (both files recognised).
bool IsImuTkGyroscopeExample(const CalibrateImuReport& report);
// The lines imu_tk prints for the gyroscope, from "Gyroscopes calibration: residual" to the
// inverse scale factors, in its format (cout's default 6 digits, Eigen's matrix layout).
std::string ImuTkGyroscopePrintout(const ImuTkGyroscopeResult& result);

// Mode ml: the poses' detector in one line.
std::string PosesLine(const CalibrateImuReport& report);
// Mode ml: the poorly determined parameters, as the table lists them (a line "none" when
// there are none), and as the JSON's and the calibration file's `poorly_determined` array.
std::string PoorlyDeterminedTable(const CalibrateImuReport& report);
// A list of poorly determined parameters as the table prints it: "<label>: none (...)", or
// "<label> (estimated and written, but <subject> do not vouch for them; ...): names" and each
// entry's value(index) +- sigma, reason and suggestion. The accelerometer's (above) and the
// gyroscope's (gyroscope_report.h).
std::string PoorlyDeterminedLines(const std::string& label, const std::string& subject,
                                  const std::vector<PoorlyDeterminedParameter>& list,
                                  const std::function<double(int)>& value);
nlohmann::json PoorlyDeterminedJson(const std::vector<TriadPoorlyDetermined>& list);

std::string CalibrateImuTable(const CalibrateImuReport& report, bool full_solver_report);
// Mode ml's result as a calibration file's record (io/calibration_file.h, geometry triad).
CalibrationRecord TriadCalibrationRecord(const CalibrateImuReport& report,
                                         const DataSource& source);
// Mode ml with a gyroscope: its calibration (the 12 unknowns' fit, discovery's baseline) as the
// calibration file's gyroscope section, its fit and verdict in the section's `fit`. Fails, in one
// line, where the file's reader would refuse it.
Status AddGyroscopeSection(const CalibrateImuReport& report, CalibrationRecord* record);
nlohmann::json CalibrateImuJson(const CalibrateImuReport& report);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_CALIBRATE_IMU_REPORT_H_
