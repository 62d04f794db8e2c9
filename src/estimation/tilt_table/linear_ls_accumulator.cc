#include "estimation/tilt_table/linear_ls_accumulator.h"

#include <algorithm>
#include <cstring>
#include <system_error>
#include <thread>
#include <vector>

#include "common/cpu_features.h"
#include "common/sincos.h"
#include "models/tilt_table.h"

namespace accelcal {

void AxisRegressionAccumulator::Add(double specific_force, double response) {
  if (count_ == 0) {
    shift_force_ = specific_force;
    shift_response_ = response;
  }
  const double f = specific_force - shift_force_;
  const double y = response - shift_response_;
  ++count_;
  sum_force_ += f;
  sum_response_ += y;
  sum_force_force_ += f * f;
  sum_force_response_ += f * y;
  sum_response_response_ += y * y;
}

void AxisRegressionAccumulator::AddShiftedSums(long long count, double sum_force,
                                               double sum_response, double sum_force_force,
                                               double sum_force_response,
                                               double sum_response_response) {
  count_ += count;
  sum_force_ += sum_force;
  sum_response_ += sum_response;
  sum_force_force_ += sum_force_force;
  sum_force_response_ += sum_force_response;
  sum_response_response_ += sum_response_response;
}

void AxisRegressionAccumulator::Merge(const AxisRegressionAccumulator& other) {
  if (other.count_ == 0) return;
  if (count_ == 0) {
    *this = other;
    return;
  }
  // Re-express the other's sums about this accumulator's shift: with
  // f' = f_other + df (df the difference of shifts), sum f'^2 = sum f^2 + 2 df sum f + n df^2.
  const double df = other.shift_force_ - shift_force_;
  const double dy = other.shift_response_ - shift_response_;
  const double n = static_cast<double>(other.count_);
  sum_force_force_ += other.sum_force_force_ + 2.0 * df * other.sum_force_ + n * df * df;
  sum_response_response_ +=
      other.sum_response_response_ + 2.0 * dy * other.sum_response_ + n * dy * dy;
  sum_force_response_ +=
      other.sum_force_response_ + dy * other.sum_force_ + df * other.sum_response_ + n * df * dy;
  sum_force_ += other.sum_force_ + n * df;
  sum_response_ += other.sum_response_ + n * dy;
  count_ += other.count_;
}

double AxisRegressionAccumulator::CenteredForceForce() const {
  return std::max(0.0, sum_force_force_ - sum_force_ * sum_force_ / count_);
}

double AxisRegressionAccumulator::CenteredForceResponse() const {
  return sum_force_response_ - sum_force_ * sum_response_ / count_;
}

double AxisRegressionAccumulator::CenteredResponseResponse() const {
  return std::max(0.0, sum_response_response_ - sum_response_ * sum_response_ / count_);
}

void CalibrationAccumulator::Add(double theta_rad, double measured_x, double measured_y) {
  double force_x;
  double force_y;
  TiltTableSpecificForce(theta_rad, gravity_mps2_, &force_x, &force_y);
  // The baseline has no non-orthogonality: each axis senses its own component.
  x_.Add(force_x, measured_x - force_x);
  y_.Add(force_y, measured_y - force_y);
  if (x_.count() == 1) theta_min_rad_ = theta_max_rad_ = theta_rad;
  theta_min_rad_ = std::min(theta_min_rad_, theta_rad);
  theta_max_rad_ = std::max(theta_max_rad_, theta_rad);
}

namespace {

// Add's sums over one block of AddTest, for both axes, and the block's angle range.
struct AxisBlockSums {
  double force = 0.0;
  double response = 0.0;
  double force_force = 0.0;
  double force_response = 0.0;
  double response_response = 0.0;
};

struct BlockSums {
  AxisBlockSums x;
  AxisBlockSums y;
  double theta_min_rad = 0.0;
  double theta_max_rad = 0.0;
};

// The samples of one block, with their angles' sines and cosines, and the shifts the
// sums are taken about.
struct Block {
  const double* theta_rad;
  const double* sin_theta;
  const double* cos_theta;
  const double* measured_x;
  const double* measured_y;
  int count;
  double gravity_mps2;
  double shift_force_x;
  double shift_response_x;
  double shift_force_y;
  double shift_response_y;
};

// Two or four doubles as one value, with element-wise arithmetic (GCC's and clang's
// vector extension): an SSE2 register, an AVX register.
typedef double Double2 __attribute__((vector_size(2 * sizeof(double))));
typedef double Double4 __attribute__((vector_size(4 * sizeof(double))));

// Add's arithmetic per sample (the tilt table's force at the reported angle, from the block's
// sines and cosines, then the shifted sums), a vector of samples at a time: each of the ten sums
// and the angle range is kept in one vector's lanes, added up at the end. The compiler would not do
// this itself, as it reorders the additions, which it may not do to floating-point sums; it is also
// more accurate than Add's one running sum (each lane and each block is a shorter sum). The vector
// is what the target's registers hold: with more lanes than that, the 12 running vectors spill out
// of the 16 registers.
template <typename Vector>
__attribute__((always_inline)) inline BlockSums SumBlockLoop(const Block& block) {
  constexpr int kLanes = sizeof(Vector) / sizeof(double);
  const double* __restrict theta_rad = block.theta_rad;
  const double* __restrict sin_theta = block.sin_theta;
  const double* __restrict cos_theta = block.cos_theta;
  const double* __restrict measured_x = block.measured_x;
  const double* __restrict measured_y = block.measured_y;
  Vector force_x = {};
  Vector response_x = {};
  Vector force_force_x = {};
  Vector force_response_x = {};
  Vector response_response_x = {};
  Vector force_y = {};
  Vector response_y = {};
  Vector force_force_y = {};
  Vector force_response_y = {};
  Vector response_response_y = {};
  Vector theta_min_rad = Vector{} + theta_rad[0];
  Vector theta_max_rad = theta_min_rad;
  const int vector_count = block.count / kLanes * kLanes;
  for (int i = 0; i < vector_count; i += kLanes) {
    // Unaligned loads. (Not a Load function: one returning a Double4 has another ABI in
    // the baseline build than with AVX, and GCC warns about it even when inlined.)
    Vector sin_i;
    Vector cos_i;
    Vector measured_x_i;
    Vector measured_y_i;
    Vector theta_i;
    std::memcpy(&sin_i, sin_theta + i, sizeof sin_i);
    std::memcpy(&cos_i, cos_theta + i, sizeof cos_i);
    std::memcpy(&measured_x_i, measured_x + i, sizeof measured_x_i);
    std::memcpy(&measured_y_i, measured_y + i, sizeof measured_y_i);
    std::memcpy(&theta_i, theta_rad + i, sizeof theta_i);
    Vector specific_force_x;
    Vector specific_force_y;
    TiltTableSpecificForceFromSinCos(sin_i, cos_i, block.gravity_mps2, &specific_force_x,
                                     &specific_force_y);
    const Vector fx = specific_force_x - block.shift_force_x;
    const Vector yx = (measured_x_i - specific_force_x) - block.shift_response_x;
    const Vector fy = specific_force_y - block.shift_force_y;
    const Vector yy = (measured_y_i - specific_force_y) - block.shift_response_y;
    force_x += fx;
    response_x += yx;
    force_force_x += fx * fx;
    force_response_x += fx * yx;
    response_response_x += yx * yx;
    force_y += fy;
    response_y += yy;
    force_force_y += fy * fy;
    force_response_y += fy * yy;
    response_response_y += yy * yy;
    // std::min and std::max, lane by lane.
    theta_min_rad = theta_i < theta_min_rad ? theta_i : theta_min_rad;
    theta_max_rad = theta_max_rad < theta_i ? theta_i : theta_max_rad;
  }
  // Pairwise over the lanes.
  const auto total = [](const Vector& lanes) {
    if constexpr (kLanes == 2) {
      return lanes[0] + lanes[1];
    } else {
      static_assert(kLanes == 4, "two or four lanes");
      return (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]);
    }
  };
  BlockSums sums;
  sums.x = {total(force_x), total(response_x), total(force_force_x), total(force_response_x),
            total(response_response_x)};
  sums.y = {total(force_y), total(response_y), total(force_force_y), total(force_response_y),
            total(response_response_y)};
  sums.theta_min_rad = theta_min_rad[0];
  sums.theta_max_rad = theta_max_rad[0];
  for (int lane = 1; lane < kLanes; ++lane) {
    sums.theta_min_rad = std::min(sums.theta_min_rad, theta_min_rad[lane]);
    sums.theta_max_rad = std::max(sums.theta_max_rad, theta_max_rad[lane]);
  }
  // The last count % kLanes samples, one by one.
  for (int i = vector_count; i < block.count; ++i) {
    double specific_force_x;
    double specific_force_y;
    TiltTableSpecificForceFromSinCos(sin_theta[i], cos_theta[i], block.gravity_mps2,
                                     &specific_force_x, &specific_force_y);
    const double fx = specific_force_x - block.shift_force_x;
    const double yx = (measured_x[i] - specific_force_x) - block.shift_response_x;
    const double fy = specific_force_y - block.shift_force_y;
    const double yy = (measured_y[i] - specific_force_y) - block.shift_response_y;
    sums.x.force += fx;
    sums.x.response += yx;
    sums.x.force_force += fx * fx;
    sums.x.force_response += fx * yx;
    sums.x.response_response += yx * yx;
    sums.y.force += fy;
    sums.y.response += yy;
    sums.y.force_force += fy * fy;
    sums.y.force_response += fy * yy;
    sums.y.response_response += yy * yy;
    sums.theta_min_rad = std::min(sums.theta_min_rad, theta_rad[i]);
    sums.theta_max_rad = std::max(sums.theta_max_rad, theta_rad[i]);
  }
  return sums;
}

// Compiled twice (common/cpu_features.h): for the baseline x86-64 and for AVX2 + FMA.
BlockSums SumBlockBaseline(const Block& block) { return SumBlockLoop<Double2>(block); }
ACCELCAL_TARGET_AVX2_FMA BlockSums SumBlockAvx2Fma(const Block& block) {
  return SumBlockLoop<Double4>(block);
}

}  // namespace

void CalibrationAccumulator::AddTest(const CalibrationTest& test) {
  AddSamples(test.theta_rad.data(), test.measured_x.data(), test.measured_y.data(), test.size());
}

void CalibrationAccumulator::AddTest(const CalibrationTest& test, int num_threads) {
  const int size = test.size();
  // The parts depend on the test alone, so the statistics do not depend on num_threads.
  const int parts = std::max(1, size / kParallelMinSamples);
  if (parts == 1) {
    AddTest(test);
    return;
  }
  // Part p covers [begin(p), begin(p + 1)), its start rounded down to a block boundary.
  const auto begin = [&](int part) {
    if (part == parts) return size;
    const long long start = static_cast<long long>(size) * part / parts;
    return static_cast<int>(start / kAddTestBlockSamples * kAddTestBlockSamples);
  };
  std::vector<CalibrationAccumulator> accumulators(parts, CalibrationAccumulator(gravity_mps2_));
  const int workers_wanted = std::max(1, std::min(num_threads, parts));
  // Worker w adds parts w, w + workers_wanted, ...
  const auto add_parts = [&](int worker) {
    for (int part = worker; part < parts; part += workers_wanted) {
      const int start = begin(part);
      accumulators[part].AddSamples(test.theta_rad.data() + start, test.measured_x.data() + start,
                                    test.measured_y.data() + start, begin(part + 1) - start);
    }
  };
  std::vector<std::thread> workers;
  std::vector<int> inline_workers = {0};  // the calling thread's share
  for (int worker = 1; worker < workers_wanted; ++worker) {
    try {
      workers.emplace_back(add_parts, worker);
    } catch (const std::system_error&) {
      inline_workers.push_back(worker);
    }
  }
  for (const int worker : inline_workers) add_parts(worker);
  for (std::thread& worker : workers) worker.join();
  for (const CalibrationAccumulator& accumulator : accumulators) Merge(accumulator);
}

void CalibrationAccumulator::Merge(const CalibrationAccumulator& other) {
  if (other.x_.count() == 0) return;
  if (x_.count() == 0) {
    theta_min_rad_ = other.theta_min_rad_;
    theta_max_rad_ = other.theta_max_rad_;
  } else {
    theta_min_rad_ = std::min(theta_min_rad_, other.theta_min_rad_);
    theta_max_rad_ = std::max(theta_max_rad_, other.theta_max_rad_);
  }
  x_.Merge(other.x_);
  y_.Merge(other.y_);
}

void CalibrationAccumulator::AddSamples(const double* theta_rad, const double* measured_x,
                                        const double* measured_y, int size) {
  // Add spends 7.5 of its 12 ns per sample in std::sin and std::cos, and the rest mostly
  // waiting for its running sums. So the test goes in blocks: the block's sines and cosines
  // in one vectorized call, then all the sums in one vectorized pass (SumBlockLoop). The
  // two buffers, 8 KB, stay in the L1 cache.
  constexpr int kBlock = kAddTestBlockSamples;
  double sin_theta[kBlock];
  double cos_theta[kBlock];
  const bool avx2_fma = CpuHasAvx2Fma();
  for (int start = 0; start < size; start += kBlock) {
    Block block;
    block.count = std::min(kBlock, size - start);
    block.theta_rad = theta_rad + start;
    block.measured_x = measured_x + start;
    block.measured_y = measured_y + start;
    block.sin_theta = sin_theta;
    block.cos_theta = cos_theta;
    block.gravity_mps2 = gravity_mps2_;
    SinCos(block.theta_rad, block.count, sin_theta, cos_theta);
    if (x_.count_ == 0) {
      // Add's shifts: the first sample's specific force and response.
      TiltTableSpecificForceFromSinCos(sin_theta[0], cos_theta[0], gravity_mps2_, &x_.shift_force_,
                                       &y_.shift_force_);
      x_.shift_response_ = block.measured_x[0] - x_.shift_force_;
      y_.shift_response_ = block.measured_y[0] - y_.shift_force_;
      theta_min_rad_ = theta_max_rad_ = block.theta_rad[0];
    }
    block.shift_force_x = x_.shift_force_;
    block.shift_response_x = x_.shift_response_;
    block.shift_force_y = y_.shift_force_;
    block.shift_response_y = y_.shift_response_;
    const BlockSums sums = avx2_fma ? SumBlockAvx2Fma(block) : SumBlockBaseline(block);
    x_.AddShiftedSums(block.count, sums.x.force, sums.x.response, sums.x.force_force,
                      sums.x.force_response, sums.x.response_response);
    y_.AddShiftedSums(block.count, sums.y.force, sums.y.response, sums.y.force_force,
                      sums.y.force_response, sums.y.response_response);
    theta_min_rad_ = std::min(theta_min_rad_, sums.theta_min_rad);
    theta_max_rad_ = std::max(theta_max_rad_, sums.theta_max_rad);
  }
}

}  // namespace accelcal
