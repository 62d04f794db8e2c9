#ifndef ACCELCAL_RESIDUALS_GYROSCOPE_RESIDUALS_H_
#define ACCELCAL_RESIDUALS_GYROSCOPE_RESIDUALS_H_

// The two residuals of the gyroscope's maximum-likelihood calibration
// (estimation/gyroscope/gyroscope_ml_calibration.h, docs/gyroscope.md), both whitened:
//
// GyroscopeRestResidual, one per static pose p (3 components):
//   r = (ubar_p - u(w = 0, f = g n_p)) / sigma_p
// the gyroscope's mean output over the pose against what it reads at rest (its offset, and the
// g-sensitivity's rate under the pose's specific force), per axis divided by the standard
// deviation of the mean. Blocks: the 9 parameters, the offset (3), the effect coefficients (15),
// the pose's unit gravity direction n_p (3).
//
// GyroscopeTurnResidual, one per turn from pose p to pose p + 1 (2 components):
//   r = W E^T (R^T n_p - n_p+1)
// R the rotation the calibrated rates w_j = GyroscopeCorrectedRate(u_j, f_j) integrate to over the
// turn's samples by the fourth-order rule IntegrateAngularRateHermite (models/gyroscope.h); E the
// 3 x 2 orthonormal basis of the plane normal to n_p+1 (as estimated before the fit: the residual
// of unit vectors lies in it to first order), W the inverse Cholesky factor of the residual's
// 2 x 2 covariance. Blocks: the 9 parameters, the offset, the effects, n_p, n_p+1. The rotation
// is integrated once per point of the gyroscope unknowns (a memo of the last), its derivatives by
// them by transport (TransportedJacobian); the directions' derivatives follow in closed form.

#include <ceres/autodiff_cost_function.h>
#include <ceres/jet.h>
#include <ceres/sized_cost_function.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <mutex>
#include <utility>
#include <vector>

#include "models/gyroscope.h"
#include "models/gyroscope_effects.h"

namespace accelcal {

class GyroscopeRestResidual {
 public:
  // `whitening`: W (row-major, 3 x 3), the inverse of the mean's covariance's Cholesky factor:
  // the residual is W (mean - predicted).
  GyroscopeRestResidual(const std::array<double, 3>& mean, const std::array<double, 9>& whitening,
                        double gravity_mps2)
      : mean_(mean), whitening_(whitening), gravity_mps2_(gravity_mps2) {}

  // `vertical_rate`: the Earth's rate along gravity (rad/s; Omega sin(latitude)), which the
  // sensor at rest turns at about its up direction, the unit specific force `direction`.
  template <typename T>
  bool operator()(const T* const parameters, const T* const offset, const T* const effects,
                  const T* const direction, const T* const vertical_rate, T* residual) const {
    const T rate[3] = {vertical_rate[0] * direction[0], vertical_rate[0] * direction[1],
                       vertical_rate[0] * direction[2]};
    const T force[3] = {T(gravity_mps2_) * direction[0], T(gravity_mps2_) * direction[1],
                        T(gravity_mps2_) * direction[2]};
    T raw[3];
    GyroscopeRawWithEffects(parameters, offset, effects, rate, force, raw);
    T difference[3];
    for (int k = 0; k < 3; ++k) difference[k] = T(mean_[k]) - raw[k];
    for (int k = 0; k < 3; ++k) {
      residual[k] = T(whitening_[3 * k]) * difference[0] +
                    T(whitening_[3 * k + 1]) * difference[1] +
                    T(whitening_[3 * k + 2]) * difference[2];
    }
    return true;
  }

  static ceres::CostFunction* Create(const std::array<double, 3>& mean,
                                     const std::array<double, 9>& whitening, double gravity_mps2) {
    return new ceres::AutoDiffCostFunction<GyroscopeRestResidual, 3, kGyroscopeParameterCount, 3,
                                           kGyroscopeEffectCoefficientCount, 3, 1>(
        new GyroscopeRestResidual(mean, whitening, gravity_mps2));
  }

 private:
  const std::array<double, 3> mean_;
  const std::array<double, 9> whitening_;
  const double gravity_mps2_;
};

// The samples of one turn: outputs, the calibrated specific force at each (m/s^2), the steps.
struct GyroscopeTurnSamples {
  std::vector<std::array<double, 3>> raw;
  std::vector<std::array<double, 3>> specific_force;
  std::vector<double> step_s;  // step_s[j]: from sample j to j + 1
};

class GyroscopeTurnResidual
    : public ceres::SizedCostFunction<2, kGyroscopeParameterCount, 3,
                                      kGyroscopeEffectCoefficientCount, 3, 3> {
 public:
  static constexpr int kUnknowns = kGyroscopeParameterCount + 3 + kGyroscopeEffectCoefficientCount;

  // `basis`: E's two columns; `whitening`: W, row-major.
  // `estimated`: the effect coefficients the fit estimates (the others' derivatives are not
  // computed; their block columns come out 0, as a held coefficient's are).
  GyroscopeTurnResidual(GyroscopeTurnSamples samples,
                        const std::array<std::array<double, 3>, 2>& basis,
                        const std::array<double, 4>& whitening, std::vector<int> estimated = {})
      : samples_(std::move(samples)),
        basis_(basis),
        whitening_(whitening),
        estimated_(std::move(estimated)) {}

  static constexpr int kGyroscopeCalibrationUnknowns = kGyroscopeParameterCount + 3;

  // How the derivatives are computed: by transport (the default, TransportedJacobian) or through
  // the Runge-Kutta stages (RotationJacobian, the reference the tests compare it with).
  void set_exact_derivatives(bool exact) { exact_derivatives_ = exact; }

  template <int N>
  void Derivatives(double const* const* blocks, const double* before, double* rotation,
                   double (*rotated_jacobian)[kUnknowns]) const {
    if (exact_derivatives_) {
      RotationJacobian<N>(blocks, before, rotation, rotated_jacobian);
    } else {
      TransportedJacobian<N>(blocks, before, rotation, rotated_jacobian);
    }
  }

  // The unknowns differentiated when N derivatives are asked for: the 9 parameters and the 3
  // offsets, then the effect coefficients the fit estimates (all 15 when N is kUnknowns), as
  // indices of the 27 (block order) in column[0 .. returned count).
  template <int N>
  int DifferentiatedColumns(int* column) const {
    int index = 0;
    for (int i = 0; i < kGyroscopeCalibrationUnknowns; ++i) column[index++] = i;
    const bool all = N == kUnknowns;
    for (int i = 0; i < kGyroscopeEffectCoefficientCount && index < N; ++i) {
      if (all || std::find(estimated_.begin(), estimated_.end(), i) != estimated_.end())
        column[index++] = kGyroscopeCalibrationUnknowns + i;
    }
    return index;
  }

  // The unknowns as Jets of N derivatives, derivative u belonging to unknown column[u]
  // (DifferentiatedColumns), the others constant. Returns the derivatives used.
  template <int N, typename Jet>
  int SeedJets(double const* const* blocks, Jet* parameters, Jet* offset, Jet* effects,
               int* column) const {
    const int index = DifferentiatedColumns<N>(column);
    for (int i = 0; i < kGyroscopeParameterCount; ++i) parameters[i] = Jet(blocks[0][i]);
    for (int i = 0; i < 3; ++i) offset[i] = Jet(blocks[1][i]);
    for (int i = 0; i < kGyroscopeEffectCoefficientCount; ++i) effects[i] = Jet(blocks[2][i]);
    for (int u = 0; u < index; ++u) {
      const int unknown = column[u];
      if (unknown < kGyroscopeParameterCount) {
        parameters[unknown].v[u] = 1.0;
      } else if (unknown < kGyroscopeCalibrationUnknowns) {
        offset[unknown - kGyroscopeParameterCount].v[u] = 1.0;
      } else {
        effects[unknown - kGyroscopeCalibrationUnknowns].v[u] = 1.0;
      }
    }
    return index;
  }

  // R at the blocks' values, and the derivatives of R^T n_before by the first N unknowns (the 9
  // parameters, the offsets, then the effects; the others' columns left as they are).
  template <int N>
  void RotationJacobian(double const* const* blocks, const double* before, double* rotation,
                        double (*rotated_jacobian)[kUnknowns]) const {
    using Jet = ceres::Jet<double, N>;
    Jet parameters[kGyroscopeParameterCount], offset[3], effects[kGyroscopeEffectCoefficientCount];
    int column[N];
    const int index = SeedJets<N>(blocks, parameters, offset, effects, column);
    Jet jet_rotation[9];
    Rotation(parameters, offset, effects, jet_rotation);
    for (int i = 0; i < 9; ++i) rotation[i] = jet_rotation[i].a;
    for (int k = 0; k < 3; ++k) {
      for (int u = 0; u < kUnknowns; ++u) rotated_jacobian[k][u] = 0.0;
      for (int u = 0; u < index; ++u) {
        rotated_jacobian[k][column[u]] = jet_rotation[k].v[u] * before[0] +
                                         jet_rotation[3 + k].v[u] * before[1] +
                                         jet_rotation[6 + k].v[u] * before[2];
      }
    }
  }

  // The same derivatives by transporting each sample's rate perturbation to the turn's end
  // (docs/gyroscope.md): a change dw_j of the rate at sample j, held over its trapezoid weight c_j,
  // turns the end attitude by dtheta = c_j R_N^T R_j dw_j (the end's body frame), and R^T n
  // changes by [v]x dtheta, v = R^T n. The sum is the continuous-time sensitivity, which the
  // discrete rule's differs from by O((w dt)^2) relative (GyroscopeTurnResidual's test measures
  // it). The rate's derivatives are written out (models/gyroscope_effects.h: w = T v' - G f,
  // v'_k = v_k + a_k |v_k| + n_k v_k^2, v_k = gain_k (u_k - b_k)): each is a column of T or an
  // entry of dT/dp times a per-sample weight (v', s_k (u_k - b_k), s_k, |v_k|, v_k^2 with
  // s_k = dv'_k/dv_k, or f), so the turn needs only the sums sum_j c_j R_j (x) weight_j, 27
  // numbers per kind of weight, and no ceres::Jet per sample.
  template <int N>
  void TransportedJacobian(double const* const* blocks, const double* before, double* rotation,
                           double (*rotated_jacobian)[kUnknowns]) const {
    std::lock_guard<std::mutex> lock(memo_mutex_);
    const Memo& memo = Integrated(blocks);
    for (int i = 0; i < 9; ++i) rotation[i] = memo.rotation[i];
    if (memo.derivatives != N) RateSums<N>(blocks);
    const double v[3] = {
        rotation[0] * before[0] + rotation[3] * before[1] + rotation[6] * before[2],
        rotation[1] * before[0] + rotation[4] * before[1] + rotation[7] * before[2],
        rotation[2] * before[0] + rotation[5] * before[1] + rotation[8] * before[2]};
    for (int k = 0; k < 3; ++k)
      for (int u = 0; u < kUnknowns; ++u) rotated_jacobian[k][u] = 0.0;
    for (int u = 0; u < memo.derivative_count; ++u) {
      // v = R^T n_before; d(R^T n)/du = v x D(:, u).
      const double* d = memo.sums[u];
      const int unknown = memo.column[u];
      rotated_jacobian[0][unknown] = v[1] * d[2] - v[2] * d[1];
      rotated_jacobian[1][unknown] = v[2] * d[0] - v[0] * d[2];
      rotated_jacobian[2][unknown] = v[0] * d[1] - v[1] * d[0];
    }
  }

  // The memo's sums D(:, u) = sum_j c_j R_N^T R_j dw_j/du for the first N unknowns, from its path.
  // Called with memo_mutex_ held, after Integrated(blocks).
  template <int N>
  void RateSums(double const* const* blocks) const {
    const double* parameters = blocks[0];
    const double* offset = blocks[1];
    const double* effects = blocks[2];
    const int count = static_cast<int>(samples_.raw.size());
    const std::vector<std::array<double, 4>>& path = memo_.path;
    int* column = memo_.column;
    const int index = DifferentiatedColumns<N>(column);
    bool asymmetry = false, nonlinearity = false, g_sensitivity = false;
    for (int u = 0; u < index; ++u) {
      const int c = column[u] - kGyroscopeCalibrationUnknowns;
      if (c < 0) continue;
      g_sensitivity |= c < kGyroscopeScaleAsymmetry;
      asymmetry |= c >= kGyroscopeScaleAsymmetry && c < kGyroscopeScaleNonlinearity;
      nonlinearity |= c >= kGyroscopeScaleNonlinearity;
    }
    // sums[kind][i][a][c] = sum_j c_j R_j(i, a) weight_j(c).
    enum Kind { kPrimed, kGain, kOffset, kAbsolute, kSquare, kForce, kKinds };
    double sums[kKinds][3][3][3] = {};
    for (int j = 0; j < count; ++j) {
      const double weight = 0.5 * ((j > 0 ? samples_.step_s[j - 1] : 0.0) +
                                   (j + 1 < count ? samples_.step_s[j] : 0.0));
      double here[9];
      QuaternionToRotationMatrix(path[j].data(), here);
      for (double& h : here) h *= weight;
      double weights[kKinds][3];
      for (int k = 0; k < 3; ++k) {
        const double centred = samples_.raw[j][k] - offset[k];
        const double along = parameters[kGyroscopeGainX + k] * centred;
        const double asymmetry_k = effects[kGyroscopeScaleAsymmetry + k];
        const double nonlinearity_k = effects[kGyroscopeScaleNonlinearity + k];
        // ceres::abs's derivative: +1 at 0, as the Jets had it.
        const double sign = along < 0.0 ? -1.0 : 1.0;
        const double slope = 1.0 + asymmetry_k * sign + 2.0 * nonlinearity_k * along;
        weights[kPrimed][k] =
            along + asymmetry_k * std::abs(along) + nonlinearity_k * along * along;
        weights[kGain][k] = slope * centred;
        weights[kOffset][k] = slope;
        weights[kAbsolute][k] = std::abs(along);
        weights[kSquare][k] = along * along;
        weights[kForce][k] = samples_.specific_force[j][k];
      }
      for (int kind = 0; kind < kKinds; ++kind) {
        if ((kind == kAbsolute && !asymmetry) || (kind == kSquare && !nonlinearity) ||
            (kind == kForce && !g_sensitivity)) {
          continue;
        }
        for (int i = 0; i < 3; ++i)
          for (int a = 0; a < 3; ++a)
            for (int c = 0; c < 3; ++c) sums[kind][i][a][c] += here[3 * i + a] * weights[kind][c];
      }
    }
    // transported[kind][r][a][c] = sum_j (c_j R_N^T R_j)(r, a) weight_j(c).
    double end[9];
    QuaternionToRotationMatrix(path.back().data(), end);
    double transported[kKinds][3][3][3];
    for (int kind = 0; kind < kKinds; ++kind)
      for (int r = 0; r < 3; ++r)
        for (int a = 0; a < 3; ++a)
          for (int c = 0; c < 3; ++c)
            transported[kind][r][a][c] = end[r] * sums[kind][0][a][c] +
                                         end[3 + r] * sums[kind][1][a][c] +
                                         end[6 + r] * sums[kind][2][a][c];
    // T and dT/dp (T is linear in the 6 angles; one Jet evaluation gives every entry's slope).
    using AngleJet = ceres::Jet<double, kGyroscopeParameterCount>;
    AngleJet angle_parameters[kGyroscopeParameterCount], angle_matrix[9];
    for (int i = 0; i < kGyroscopeParameterCount; ++i)
      angle_parameters[i] = AngleJet(parameters[i], i);
    GyroscopeMisalignmentMatrix(angle_parameters, angle_matrix);
    // D(:, u) = sum_j c_j R_N^T R_j dw_j/du.
    auto per_axis = [&](int kind, int k, double factor, double* d) {
      for (int r = 0; r < 3; ++r) {
        d[r] = factor * (angle_matrix[k].a * transported[kind][r][0][k] +
                         angle_matrix[3 + k].a * transported[kind][r][1][k] +
                         angle_matrix[6 + k].a * transported[kind][r][2][k]);
      }
    };
    for (int u = 0; u < index; ++u) {
      const int unknown = column[u];
      double* d = memo_.sums[u];
      for (int r = 0; r < 3; ++r) d[r] = 0.0;
      if (unknown < kGyroscopeGainX) {  // an angle: dT/dp v'
        for (int r = 0; r < 3; ++r)
          for (int a = 0; a < 3; ++a)
            for (int c = 0; c < 3; ++c)
              d[r] += angle_matrix[3 * a + c].v[unknown] * transported[kPrimed][r][a][c];
      } else if (unknown < kGyroscopeParameterCount) {
        per_axis(kGain, unknown - kGyroscopeGainX, 1.0, d);
      } else if (unknown < kGyroscopeCalibrationUnknowns) {
        const int k = unknown - kGyroscopeParameterCount;
        per_axis(kOffset, k, -parameters[kGyroscopeGainX + k], d);
      } else {
        const int c = unknown - kGyroscopeCalibrationUnknowns;
        if (c < kGyroscopeScaleAsymmetry) {  // G(q, k): -f_k e_q
          for (int r = 0; r < 3; ++r) d[r] = -transported[kForce][r][c / 3][c % 3];
        } else if (c < kGyroscopeScaleNonlinearity) {
          per_axis(kAbsolute, c - kGyroscopeScaleAsymmetry, 1.0, d);
        } else {
          per_axis(kSquare, c - kGyroscopeScaleNonlinearity, 1.0, d);
        }
      }
    }
    memo_.derivative_count = index;
    memo_.derivatives = N;
  }

  // R (row-major) at the blocks' values, through the memo.
  void RotationAt(double const* const* blocks, double* rotation) const {
    std::lock_guard<std::mutex> lock(memo_mutex_);
    const Memo& memo = Integrated(blocks);
    for (int i = 0; i < 9; ++i) rotation[i] = memo.rotation[i];
  }

  // R (row-major) at the given unknowns.
  template <typename T>
  void Rotation(const T* parameters, const T* offset, const T* effects, T* rotation) const {
    IntegrateAngularRateHermite(
        static_cast<int>(samples_.raw.size()),
        [&](int j, T* rate) {
          GyroscopeCorrectedRate(parameters, offset, effects, samples_.raw[j].data(),
                                 samples_.specific_force[j].data(), rate);
        },
        samples_.step_s, rotation);
  }

  bool Evaluate(double const* const* blocks, double* residuals, double** jacobians) const override {
    const double* before = blocks[3];
    const double* after = blocks[4];
    double rotation[9];
    double rotated_jacobian[3][kUnknowns];
    const bool gyroscope_jacobian =
        jacobians != nullptr &&
        (jacobians[0] != nullptr || jacobians[1] != nullptr || jacobians[2] != nullptr);
    if (gyroscope_jacobian && jacobians[2] == nullptr) {
      // The effects held (the model without them, or constant): 12 unknowns' derivatives.
      Derivatives<kGyroscopeCalibrationUnknowns>(blocks, before, rotation, rotated_jacobian);
    } else if (gyroscope_jacobian) {
      // Derivatives by the estimated effects' coefficients only (held ones have zero columns).
      switch (estimated_.size()) {
        case 3:
          Derivatives<kGyroscopeCalibrationUnknowns + 3>(blocks, before, rotation,
                                                         rotated_jacobian);
          break;
        case 6:
          Derivatives<kGyroscopeCalibrationUnknowns + 6>(blocks, before, rotation,
                                                         rotated_jacobian);
          break;
        case 9:
          Derivatives<kGyroscopeCalibrationUnknowns + 9>(blocks, before, rotation,
                                                         rotated_jacobian);
          break;
        case 12:
          Derivatives<kGyroscopeCalibrationUnknowns + 12>(blocks, before, rotation,
                                                          rotated_jacobian);
          break;
        default:
          Derivatives<kUnknowns>(blocks, before, rotation, rotated_jacobian);
      }
    } else {
      RotationAt(blocks, rotation);
    }
    double difference[3];
    for (int k = 0; k < 3; ++k) {
      difference[k] = rotation[k] * before[0] + rotation[3 + k] * before[1] +
                      rotation[6 + k] * before[2] - after[k];
    }
    // M = W E^T (2 x 3): r = M (R^T n_p - n_p+1).
    double m[2][3];
    for (int row = 0; row < 2; ++row) {
      for (int k = 0; k < 3; ++k) {
        m[row][k] = whitening_[2 * row] * basis_[0][k] + whitening_[2 * row + 1] * basis_[1][k];
      }
    }
    for (int row = 0; row < 2; ++row) {
      residuals[row] =
          m[row][0] * difference[0] + m[row][1] * difference[1] + m[row][2] * difference[2];
    }
    if (jacobians == nullptr) return true;
    if (gyroscope_jacobian) {
      const int sizes[3] = {kGyroscopeParameterCount, 3, kGyroscopeEffectCoefficientCount};
      int first = 0;
      for (int block = 0; block < 3; ++block) {
        if (jacobians[block] != nullptr) {
          for (int row = 0; row < 2; ++row) {
            for (int u = 0; u < sizes[block]; ++u) {
              jacobians[block][row * sizes[block] + u] =
                  m[row][0] * rotated_jacobian[0][first + u] +
                  m[row][1] * rotated_jacobian[1][first + u] +
                  m[row][2] * rotated_jacobian[2][first + u];
            }
          }
        }
        first += sizes[block];
      }
    }
    if (jacobians[3] != nullptr) {  // d/d n_p = M R^T
      for (int row = 0; row < 2; ++row) {
        for (int c = 0; c < 3; ++c) {
          jacobians[3][row * 3 + c] = m[row][0] * rotation[3 * c] +
                                      m[row][1] * rotation[3 * c + 1] +
                                      m[row][2] * rotation[3 * c + 2];
        }
      }
    }
    if (jacobians[4] != nullptr) {  // d/d n_p+1 = -M
      for (int row = 0; row < 2; ++row)
        for (int c = 0; c < 3; ++c) jacobians[4][row * 3 + c] = -m[row][c];
    }
    return true;
  }

 private:
  const GyroscopeTurnSamples samples_;
  const std::array<std::array<double, 3>, 2> basis_;
  const std::array<double, 4> whitening_;
  const std::vector<int> estimated_;
  bool exact_derivatives_ = false;

  // The last point the turn was integrated at (the 27 gyroscope unknowns), its attitude at every
  // sample and R, and the sums D for the last N asked: Ceres evaluates the cost at a candidate
  // point and, when it accepts it, the Jacobian at the same point; the rank check, the residuals
  // and the covariance after the solve ask again at the solution. Each is integrated once.
  struct Memo {
    bool valid = false;
    std::array<double, kUnknowns> point{};
    std::vector<std::array<double, 4>> path;
    double rotation[9] = {};
    int derivatives = 0;  // the N the sums are for (0: none)
    int derivative_count = 0;
    int column[kUnknowns] = {};
    double sums[kUnknowns][3] = {};
  };
  mutable std::mutex memo_mutex_;
  mutable Memo memo_;

  // The memo at the blocks' values (integrating when they changed). memo_mutex_ held.
  const Memo& Integrated(double const* const* blocks) const {
    std::array<double, kUnknowns> point;
    std::copy(blocks[0], blocks[0] + kGyroscopeParameterCount, point.begin());
    std::copy(blocks[1], blocks[1] + 3, point.begin() + kGyroscopeParameterCount);
    std::copy(blocks[2], blocks[2] + kGyroscopeEffectCoefficientCount,
              point.begin() + kGyroscopeCalibrationUnknowns);
    // Bit for bit (memcmp): -0.0 and 0.0 differ, NaN equals itself; a new point integrates.
    if (memo_.valid && std::memcmp(point.data(), memo_.point.data(), sizeof(point)) == 0)
      return memo_;
    memo_.valid = false;
    memo_.derivatives = 0;
    IntegrateAngularRateHermite(
        static_cast<int>(samples_.raw.size()),
        [&](int j, double* rate) {
          GyroscopeCorrectedRate(blocks[0], blocks[1], blocks[2], samples_.raw[j].data(),
                                 samples_.specific_force[j].data(), rate);
        },
        samples_.step_s, memo_.rotation, &memo_.path);
    memo_.point = point;
    memo_.valid = true;
    return memo_;
  }
};

}  // namespace accelcal

#endif  // ACCELCAL_RESIDUALS_GYROSCOPE_RESIDUALS_H_
