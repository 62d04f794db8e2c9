#ifndef ACCELCAL_ESTIMATION_TILT_TABLE_LINEAR_LS_ACCUMULATOR_H_
#define ACCELCAL_ESTIMATION_TILT_TABLE_LINEAR_LS_ACCUMULATOR_H_

// The streaming sufficient statistics of the linear baseline (estimation/tilt_table/linear_ls.h):
// one pass over the samples, constant memory in N, mergeable across chunks. Per axis k the
// regression is y_i = b_k + s_k f_k,i with f_k the tilt table's specific force
// (models/tilt_table.h) and y_i = m_k,i - f_k,i. Sums are taken about the first sample (the
// "shifted data" algorithm), which keeps the centred second moments accurate even when the
// angles span little, exactly the case the conditioning check must judge correctly.

#include "common/measurements.h"

namespace accelcal {

// Sufficient statistics of one axis's regression y = b + s f.
class AxisRegressionAccumulator {
 public:
  void Add(double specific_force, double response);
  void Merge(const AxisRegressionAccumulator& other);

  long long count() const { return count_; }
  double MeanForce() const { return shift_force_ + sum_force_ / count_; }
  double MeanResponse() const { return shift_response_ + sum_response_ / count_; }
  // Centred sums: sum (f - mean f)^2, sum (f - mean f)(y - mean y), sum (y - mean y)^2.
  double CenteredForceForce() const;
  double CenteredForceResponse() const;
  double CenteredResponseResponse() const;

 private:
  friend class CalibrationAccumulator;  // AddTest sets the shifts and adds whole blocks

  // Adds sums taken about this accumulator's shifts, as Add takes them, over `count`
  // samples.
  void AddShiftedSums(long long count, double sum_force, double sum_response,
                      double sum_force_force, double sum_force_response,
                      double sum_response_response);

  long long count_ = 0;
  double shift_force_ = 0.0;
  double shift_response_ = 0.0;
  double sum_force_ = 0.0;
  double sum_response_ = 0.0;
  double sum_force_force_ = 0.0;
  double sum_force_response_ = 0.0;
  double sum_response_response_ = 0.0;
};

// Sufficient statistics of a whole tilt test (both axes and the angle span).
class CalibrationAccumulator {
 public:
  explicit CalibrationAccumulator(double gravity_mps2) : gravity_mps2_(gravity_mps2) {}

  // Samples per block of AddTest.
  static constexpr int kAddTestBlockSamples = 512;

  // One sample, with std::sin and std::cos.
  void Add(double theta_rad, double measured_x, double measured_y);
  // Every sample of `test`, as Add would, but 4.5 times as fast (twice without AVX2): in
  // blocks of kAddTestBlockSamples from the start of `test`, each with the batch SinCos
  // (common/sincos.h) and sums kept in vector lanes. The sums differ from Add's in the last
  // bits (sin and cos rounded differently, added in another order; more accurately, as the
  // partial sums are shorter). They depend on where the blocks start, so a test passed in
  // several calls gives the same statistics bit for bit when every call but the last has a
  // multiple of kAddTestBlockSamples samples, and equal to rounding otherwise.
  void AddTest(const CalibrationTest& test);
  // AddTest in contiguous parts of the test, each starting on a block boundary and holding
  // at least kParallelMinSamples samples (starting a thread costs tens of microseconds),
  // spread over up to `num_threads` threads and merged in order. The parts depend on the
  // test's length alone, so the statistics are the same bit for bit whatever num_threads;
  // they equal AddTest's to rounding (each part's sums are taken about its own first
  // sample). When a thread cannot be started, its parts run on the calling thread.
  void AddTest(const CalibrationTest& test, int num_threads);
  static constexpr int kParallelMinSamples = 1 << 18;

  // Adds another accumulator's samples (as if they followed this one's).
  void Merge(const CalibrationAccumulator& other);

  const AxisRegressionAccumulator& x() const { return x_; }
  const AxisRegressionAccumulator& y() const { return y_; }
  double gravity_mps2() const { return gravity_mps2_; }
  double theta_min_rad() const { return theta_min_rad_; }
  double theta_max_rad() const { return theta_max_rad_; }

 private:
  // AddTest's work on `count` samples given as three arrays.
  void AddSamples(const double* theta_rad, const double* measured_x, const double* measured_y,
                  int count);

  double gravity_mps2_;
  AxisRegressionAccumulator x_;
  AxisRegressionAccumulator y_;
  double theta_min_rad_ = 0.0;
  double theta_max_rad_ = 0.0;
};

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TILT_TABLE_LINEAR_LS_ACCUMULATOR_H_
