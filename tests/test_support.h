#ifndef ACCELCAL_TESTS_TEST_SUPPORT_H_
#define ACCELCAL_TESTS_TEST_SUPPORT_H_

// Helpers shared by the tests: Eigen comparisons (after manif's gtest_eigen_utils.h),
// where the course data and the binaries are, scratch directories, and running a binary
// to check its exit status, stdout and stderr.

#include <dirent.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "common/measurements.h"
#include "models/effects.h"

namespace accelcal {
namespace testing {

// Pointers to the values of `layout`'s parameters: a residual's blocks for Evaluate.
template <size_t N>
std::vector<const double*> BlockPointers(const std::array<Parameter, N>& layout,
                                         const ModelParameters<double>& values) {
  std::vector<const double*> pointers;
  for (const Parameter parameter : layout) pointers.push_back(&values[parameter]);
  return pointers;
}

template <typename A, typename B>
::testing::AssertionResult EigenNear(const Eigen::MatrixBase<A>& actual,
                                     const Eigen::MatrixBase<B>& expected, double tolerance) {
  if (actual.rows() != expected.rows() || actual.cols() != expected.cols()) {
    return ::testing::AssertionFailure() << "shapes differ";
  }
  const double difference = (actual - expected).cwiseAbs().maxCoeff();
  if (difference <= tolerance) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "max |difference| " << difference << " > " << tolerance << "\nactual:\n"
         << actual << "\nexpected:\n"
         << expected;
}
#define EXPECT_EIGEN_NEAR(actual, expected, tolerance) \
  EXPECT_TRUE(::accelcal::testing::EigenNear(actual, expected, tolerance))

inline bool PathExists(const std::string& path) {
  struct stat info;
  return stat(path.c_str(), &info) == 0;
}

// A data folder: $`variable`, else `default_dir`; empty unless it holds `marker` (tests then
// skip, saying so).
inline std::string DataDirFrom(const char* variable, const std::string& default_dir,
                               const std::string& marker) {
  const char* from_environment = std::getenv(variable);
  const std::string dir =
      from_environment != nullptr && *from_environment != '\0' ? from_environment : default_dir;
  return PathExists(dir + "/" + marker) ? dir : "";
}

// The course data: $ACCELCAL_COURSE_DATA, else ../shared/data/tp2-2018 beside the repository.
inline std::string CourseDataDir() {
  return DataDirFrom("ACCELCAL_COURSE_DATA", ACCELCAL_DEFAULT_COURSE_DATA, "ensayo.mat");
}

#define ACCELCAL_REQUIRE_COURSE_DATA(dir)                                           \
  const std::string dir = ::accelcal::testing::CourseDataDir();                     \
  if (dir.empty()) {                                                                \
    GTEST_SKIP() << "course data not found: set ACCELCAL_COURSE_DATA or put it in " \
                    "../shared/data/tp2-2018";                                      \
  }

// imu_tk's Xsens example (issue 20): $ACCELCAL_IMU_TK_DATA, else ../shared/data/imu_tk-xsens.
inline std::string ImuTkDataDir() {
  return DataDirFrom("ACCELCAL_IMU_TK_DATA", ACCELCAL_DEFAULT_IMU_TK_DATA, "xsens_acc.mat");
}

#define ACCELCAL_REQUIRE_IMU_TK_DATA(dir)                                           \
  const std::string dir = ::accelcal::testing::ImuTkDataDir();                      \
  if (dir.empty()) {                                                                \
    GTEST_SKIP() << "imu_tk data not found: set ACCELCAL_IMU_TK_DATA or put it in " \
                    "../shared/data/imu_tk-xsens";                                  \
  }

// imucal's Ferraris example (issue 20): $ACCELCAL_IMUCAL_DATA, else
// ../shared/data/imucal-ferraris.
inline std::string ImucalDataDir() {
  return DataDirFrom("ACCELCAL_IMUCAL_DATA", ACCELCAL_DEFAULT_IMUCAL_DATA, "annotated_session.csv");
}

#define ACCELCAL_REQUIRE_IMUCAL_DATA(dir)                                           \
  const std::string dir = ::accelcal::testing::ImucalDataDir();                     \
  if (dir.empty()) {                                                                \
    GTEST_SKIP() << "imucal data not found: set ACCELCAL_IMUCAL_DATA or put it in " \
                    "../shared/data/imucal-ferraris";                               \
  }

inline std::string BinaryPath(const std::string& name) {
  return std::string(ACCELCAL_BIN_DIR) + "/" + name;
}

// A fresh directory under $TMPDIR, removed at destruction.
class ScratchDir {
 public:
  ScratchDir() {
    const char* base = std::getenv("TMPDIR");
    std::string pattern = std::string(base != nullptr ? base : "/tmp") + "/accelcal_test_XXXXXX";
    path_ = mkdtemp(pattern.data()) != nullptr ? pattern : "";
    EXPECT_FALSE(path_.empty());
  }
  ~ScratchDir() {
    if (!path_.empty()) std::system(("rm -rf '" + path_ + "'").c_str());
  }
  const std::string& path() const { return path_; }
  std::string File(const std::string& name) const { return path_ + "/" + name; }
  std::string Write(const std::string& name, const std::string& contents) const {
    std::ofstream(File(name), std::ios::binary) << contents;
    return File(name);
  }

 private:
  std::string path_;
};

inline std::string ReadText(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream buffer;
  buffer << file.rdbuf();
  return buffer.str();
}

// The names in folder `dir` (none when it cannot be read).
inline std::vector<std::string> FilesIn(const std::string& dir) {
  std::vector<std::string> names;
  DIR* listing = opendir(dir.c_str());
  if (listing == nullptr) return names;
  while (const dirent* entry = readdir(listing)) {
    const std::string name = entry->d_name;
    if (name != "." && name != "..") names.push_back(name);
  }
  closedir(listing);
  return names;
}

struct CommandResult {
  int exit_status = -1;
  std::string stdout_text;
  std::string stderr_text;
};

// Runs `command` through the shell with stdout and stderr captured separately.
inline CommandResult RunCommand(const std::string& command) {
  ScratchDir capture;
  const std::string out = capture.File("stdout");
  const std::string err = capture.File("stderr");
  const int status = std::system((command + " >'" + out + "' 2>'" + err + "'").c_str());
  CommandResult result;
  result.exit_status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.stdout_text = ReadText(out);
  result.stderr_text = ReadText(err);
  return result;
}

// Runs build/bin/<binary> with `arguments` (already shell-quoted where needed).
inline CommandResult RunBinary(const std::string& binary, const std::string& arguments) {
  return RunCommand("'" + BinaryPath(binary) + "' " + arguments);
}

// Runs the program at `program` (a path) with `arguments` as its argument vector (no shell, so
// nothing needs quoting), its descriptors set up by `actions`, SIGPIPE at its default as from a
// shell. Returns its wait status, -1 when it could not start.
inline int SpawnProgramWithActions(const std::string& program,
                                   const std::vector<std::string>& arguments,
                                   const posix_spawn_file_actions_t* actions) {
  std::vector<std::string> strings = {program};
  strings.insert(strings.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (std::string& argument : strings) argv.push_back(argument.data());
  argv.push_back(nullptr);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  sigset_t defaults;
  sigemptyset(&defaults);
  sigaddset(&defaults, SIGPIPE);
  posix_spawnattr_setsigdefault(&attributes, &defaults);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGDEF);
  pid_t pid = -1;
  const int spawned = posix_spawn(&pid, argv[0], actions, &attributes, argv.data(), environ);
  posix_spawnattr_destroy(&attributes);
  EXPECT_EQ(spawned, 0) << argv[0];
  int status = 0;
  if (spawned != 0 || waitpid(pid, &status, 0) != pid) return -1;
  return status;
}

// The same for build/bin/<binary>.
inline int SpawnBinaryWithActions(const std::string& binary,
                                  const std::vector<std::string>& arguments,
                                  const posix_spawn_file_actions_t* actions) {
  return SpawnProgramWithActions(BinaryPath(binary), arguments, actions);
}

// Runs the program at `program` (a path) with `arguments`, its stdout and stderr into the files
// named.
inline int SpawnProgram(const std::string& program, const std::vector<std::string>& arguments,
                        const std::string& stdout_path, const std::string& stderr_path) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  const int flags = O_WRONLY | O_CREAT | O_TRUNC;
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, stdout_path.c_str(), flags, 0600);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, stderr_path.c_str(), flags, 0600);
  const int status = SpawnProgramWithActions(program, arguments, &actions);
  posix_spawn_file_actions_destroy(&actions);
  return status;
}

// Runs build/bin/<binary> with `arguments`, its stdout and stderr into the files named.
inline int SpawnBinary(const std::string& binary, const std::vector<std::string>& arguments,
                       const std::string& stdout_path, const std::string& stderr_path) {
  return SpawnProgram(BinaryPath(binary), arguments, stdout_path, stderr_path);
}

// SpawnProgram with stdout and stderr captured (into files: never a terminal).
inline CommandResult RunProgramArgs(const std::string& program,
                                    const std::vector<std::string>& arguments) {
  ScratchDir capture;
  const int status =
      SpawnProgram(program, arguments, capture.File("stdout"), capture.File("stderr"));
  CommandResult result;
  result.exit_status = status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.stdout_text = ReadText(capture.File("stdout"));
  result.stderr_text = ReadText(capture.File("stderr"));
  return result;
}

// The same for build/bin/<binary>.
inline CommandResult RunBinaryArgs(const std::string& binary,
                                   const std::vector<std::string>& arguments) {
  return RunProgramArgs(BinaryPath(binary), arguments);
}

inline int CountLines(const std::string& text);

// The project's contract for bad input: exit status 2, exactly one line on stderr that
// starts with "<binary>: error: " and contains `fragment`, and nothing on stdout.
inline void ExpectBadInputContract(const CommandResult& result, const std::string& binary,
                                   const std::string& fragment) {
  EXPECT_EQ(result.exit_status, 2) << "stderr: " << result.stderr_text;
  EXPECT_EQ(CountLines(result.stderr_text), 1) << result.stderr_text;
  EXPECT_EQ(result.stderr_text.rfind(binary + ": error: ", 0), 0u) << result.stderr_text;
  EXPECT_NE(result.stderr_text.find(fragment), std::string::npos)
      << "stderr: " << result.stderr_text << "expected: " << fragment;
  EXPECT_TRUE(result.stdout_text.empty()) << result.stdout_text;
}

inline int CountLines(const std::string& text) {
  int lines = 0;
  for (char c : text) lines += c == '\n';
  return lines;
}

// Independent of the library's estimators, for tests that check a printed or written figure
// against a computation of their own: per axis, the 2x2 normal equations of the baseline,
// m - f = b + s f (f = -g sin theta for x, -g cos theta for y), accumulated in long double
// and solved by Cramer's rule; the covariance sigma^2 (A^T A)^-1 and the chi-square of the
// residuals against the stated noise variance.
struct PlainAxisFit {
  double bias = 0.0;
  double scale = 0.0;
  double var_bias = 0.0;
  double var_scale = 0.0;
  double cov_bias_scale = 0.0;
  double chi2 = 0.0;
};

inline PlainAxisFit PlainBaselineFit(const CalibrationTest& test, int axis, double variance,
                                     double gravity_mps2 = 9.8) {
  auto force = [&](int i) {
    return axis == 0 ? -gravity_mps2 * std::sin(test.theta_rad[i])
                     : -gravity_mps2 * std::cos(test.theta_rad[i]);
  };
  auto measured = [&](int i) { return axis == 0 ? test.measured_x[i] : test.measured_y[i]; };
  long double n = 0, sf = 0, sff = 0, sy = 0, sfy = 0;
  for (int i = 0; i < test.size(); ++i) {
    const long double f = force(i);
    const long double y = measured(i) - f;
    n += 1;
    sf += f;
    sff += f * f;
    sy += y;
    sfy += f * y;
  }
  const long double determinant = n * sff - sf * sf;
  PlainAxisFit fit;
  fit.bias = static_cast<double>((sff * sy - sf * sfy) / determinant);
  fit.scale = static_cast<double>((n * sfy - sf * sy) / determinant);
  fit.var_bias = static_cast<double>(variance * sff / determinant);
  fit.var_scale = static_cast<double>(variance * n / determinant);
  fit.cov_bias_scale = static_cast<double>(-variance * sf / determinant);
  long double chi2 = 0;
  for (int i = 0; i < test.size(); ++i) {
    const long double r = measured(i) - (1 + fit.scale) * force(i) - fit.bias;
    chi2 += r * r / variance;
  }
  fit.chi2 = static_cast<double>(chi2);
  return fit;
}

// The spec's trapezoidal double integration as a plain loop: the position after the last of
// the accelerations `a` (spaced dt), from position 0 and velocity v0.
inline double PlainTrapezoidEndpoint(const std::vector<double>& a, double dt, double v0) {
  double position = 0.0;
  double velocity = v0;
  for (size_t j = 1; j < a.size(); ++j) {
    const double next = velocity + dt / 2 * (a[j] + a[j - 1]);
    position += dt / 2 * (velocity + next);
    velocity = next;
  }
  return position;
}

// A gyroscope's correction written out from docs/gyroscope.md's matrices, independent of
// models/gyroscope.h: `values` the 12 of a calibration file's gyroscope section (misalignment
// yz, zy, zx, xz, xy, yx; gain x, y, z; offset x, y, z), `raw` one output; w = T K (u - b), rad/s.
inline Eigen::Vector3d PlainGyroscopeRate(const Eigen::VectorXd& values,
                                          const Eigen::Vector3d& raw) {
  const double yz = values[0], zy = values[1], zx = values[2];
  const double xz = values[3], xy = values[4], yx = values[5];
  Eigen::Matrix3d misalignment;
  misalignment << 1.0, -yz, zy, xz, 1.0, -zx, -xy, yx, 1.0;
  const Eigen::Vector3d gain = values.segment<3>(6);
  const Eigen::Vector3d offset = values.segment<3>(9);
  return misalignment * gain.asDiagonal() * (raw - offset);
}

// The covariance of PlainGyroscopeRate that the parameters' `covariance` gives, J C J^T, with J
// by central differences (exact up to rounding: w is linear in each parameter alone), steps of
// each parameter's sigma.
inline Eigen::Matrix3d PlainGyroscopeRateCovariance(const Eigen::VectorXd& values,
                                                    const Eigen::MatrixXd& covariance,
                                                    const Eigen::Vector3d& raw) {
  Eigen::MatrixXd jacobian(3, values.size());
  for (int p = 0; p < values.size(); ++p) {
    const double step = std::sqrt(covariance(p, p));
    Eigen::VectorXd up = values, down = values;
    up[p] += step;
    down[p] -= step;
    jacobian.col(p) = (PlainGyroscopeRate(up, raw) - PlainGyroscopeRate(down, raw)) / (2 * step);
  }
  return jacobian * covariance * jacobian.transpose();
}

}  // namespace testing
}  // namespace accelcal

// A Status that failed with a message of one line containing `fragment`.
#define EXPECT_ERROR_CONTAINS(status_expression, fragment)                           \
  do {                                                                               \
    const ::accelcal::Status status_ = (status_expression);                          \
    EXPECT_FALSE(status_.ok()) << "expected an error containing: " << fragment;      \
    EXPECT_NE(status_.message().find(fragment), std::string::npos)                   \
        << "message: " << status_.message() << "\nexpected: " << fragment;           \
    EXPECT_EQ(status_.message().find('\n'), std::string::npos) << status_.message(); \
  } while (false)

#endif  // ACCELCAL_TESTS_TEST_SUPPORT_H_
