#ifndef ACCELCAL_RESIDUALS_GYROSCOPE_RESIDUALS_H_
#define ACCELCAL_RESIDUALS_GYROSCOPE_RESIDUALS_H_

// The two residuals of the gyroscope's maximum-likelihood calibration
// (estimation/gyroscope/gyroscope_ml_calibration.h, docs/gyroscope.md), both whitened:
//
// GyroscopeRestResidual, one per static pose p (3 components):
//   r = (ubar_p - u(w = 0, f = g n_p)) / sigma_p
// the gyroscope's mean output over the pose against what it reads at rest (its offset, and the
// effects' rates under the pose's specific force: a g-sensitivity's, the Earth's vertical rate),
// whitened by the mean's covariance. Blocks: the 9 parameters, the offset (3), the effect
// coefficients (kGyroscopeEffectCoefficientCount), the pose's unit gravity direction n_p (3).
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
#include "models/gyroscope_effect_list.h"

namespace accelcal {

class GyroscopeRestResidual {
 public:
  // `whitening`: W (row-major, 3 x 3), the inverse of the mean's covariance's Cholesky factor:
  // the residual is W (mean - predicted).
  // `output_rate`: the mean over the pose of the output's rate of change (the log's unit per s;
  // models/gyroscope_effect.h's context), 0 inside a still pose.
  GyroscopeRestResidual(const std::array<double, 3>& mean, const std::array<double, 9>& whitening,
                        double gravity_mps2, const std::array<double, 3>& output_rate = {})
      : mean_(mean),
        whitening_(whitening),
        gravity_mps2_(gravity_mps2),
        output_rate_(output_rate) {}

  // At rest the body does not turn against the ground: w = 0 (the Earth's vertical rate, which
  // the sensor reads at rest, is the effect block's earth_rate).
  template <typename T>
  bool operator()(const T* const parameters, const T* const offset, const T* const effects,
                  const T* const direction, T* residual) const {
    const T rate[3] = {T(0.0), T(0.0), T(0.0)};
    const T force[3] = {T(gravity_mps2_) * direction[0], T(gravity_mps2_) * direction[1],
                        T(gravity_mps2_) * direction[2]};
    const T output_rate[3] = {T(output_rate_[0]), T(output_rate_[1]), T(output_rate_[2])};
    GyroscopeSampleContext<T> context;
    context.specific_force = force;
    context.output_rate = output_rate;
    T raw[3];
    GyroscopeRawWithEffects(parameters, offset, effects, rate, context, raw);
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
                                     const std::array<double, 9>& whitening, double gravity_mps2,
                                     const std::array<double, 3>& output_rate = {}) {
    return new ceres::AutoDiffCostFunction<GyroscopeRestResidual, 3, kGyroscopeParameterCount, 3,
                                           kGyroscopeEffectCoefficientCount, 3>(
        new GyroscopeRestResidual(mean, whitening, gravity_mps2, output_rate));
  }

 private:
  const std::array<double, 3> mean_;
  const std::array<double, 9> whitening_;
  const double gravity_mps2_;
  const std::array<double, 3> output_rate_;
};

// The samples of one turn: outputs, the calibrated specific force at each (m/s^2), the steps,
// and the output's rate of change at each (central differences; empty: 0).
struct GyroscopeTurnSamples {
  std::vector<std::array<double, 3>> raw;
  std::vector<std::array<double, 3>> specific_force;
  std::vector<double> step_s;  // step_s[j]: from sample j to j + 1
  std::vector<std::array<double, 3>> output_rate;
};

class GyroscopeTurnResidual
    : public ceres::SizedCostFunction<2, kGyroscopeParameterCount, 3,
                                      kGyroscopeEffectCoefficientCount, 3, 3> {
 public:
  static constexpr int kGyroscopeCalibrationUnknowns = kGyroscopeParameterCount + 3;
  static constexpr int kUnknowns = kGyroscopeCalibrationUnknowns + kGyroscopeEffectCoefficientCount;

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

  // How the derivatives are computed: by transport (the default, TransportedJacobian) or through
  // the Runge-Kutta stages (RotationJacobian, the reference the tests compare it with).
  void set_exact_derivatives(bool exact) { exact_derivatives_ = exact; }

  // The unknowns differentiated: the 9 parameters and the 3 offsets, then (with `effects`) the
  // effect coefficients the fit estimates, as indices of the kUnknowns (block order) in
  // column[0 .. returned count).
  int DifferentiatedColumns(bool effects, int* column) const {
    int index = 0;
    for (int i = 0; i < kGyroscopeCalibrationUnknowns; ++i) column[index++] = i;
    if (effects)
      for (const int c : estimated_) column[index++] = kGyroscopeCalibrationUnknowns + c;
    return index;
  }

  // R at the blocks' values, and the derivatives of R^T n_before by the differentiated unknowns
  // (the others' columns 0), every unknown a ceres::Jet through the Runge-Kutta stages.
  void RotationJacobian(double const* const* blocks, bool effects, const double* before,
                        double* rotation, double (*rotated_jacobian)[kUnknowns]) const {
    using Jet = ceres::Jet<double, kUnknowns>;
    Jet parameters[kGyroscopeParameterCount], offset[3],
        coefficients[kGyroscopeEffectCoefficientCount];
    for (int i = 0; i < kGyroscopeParameterCount; ++i) parameters[i] = Jet(blocks[0][i], i);
    for (int i = 0; i < 3; ++i) offset[i] = Jet(blocks[1][i], kGyroscopeParameterCount + i);
    for (int i = 0; i < kGyroscopeEffectCoefficientCount; ++i)
      coefficients[i] = Jet(blocks[2][i], kGyroscopeCalibrationUnknowns + i);
    Jet jet_rotation[9];
    Rotation(parameters, offset, coefficients, jet_rotation);
    for (int i = 0; i < 9; ++i) rotation[i] = jet_rotation[i].a;
    int column[kUnknowns];
    const int count = DifferentiatedColumns(effects, column);
    for (int k = 0; k < 3; ++k) {
      for (int u = 0; u < kUnknowns; ++u) rotated_jacobian[k][u] = 0.0;
      for (int i = 0; i < count; ++i) {
        const int u = column[i];
        rotated_jacobian[k][u] = jet_rotation[k].v[u] * before[0] +
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
  // it). The rate's derivatives dw_j/du come from the composition of
  // models/gyroscope_effect.h: by the angles dT/dp v', by gain k T S e_k (u'_k - b_k), by offset k
  // -T S e_k gain_k (S = dv'/dv, a Jet of 3 through the kAxis terms when one is non-zero), by an
  // effect's coefficients a ceres::Jet of the effect's own size through its term alone, carried
  // to v' or the rate by its stage; no Jet through the integration.
  void TransportedJacobian(double const* const* blocks, bool effects, const double* before,
                           double* rotation, double (*rotated_jacobian)[kUnknowns]) const {
    std::lock_guard<std::mutex> lock(memo_mutex_);
    const Memo& memo = Integrated(blocks);
    for (int i = 0; i < 9; ++i) rotation[i] = memo.rotation[i];
    const int wanted = effects ? 2 : 1;
    if (memo.derivatives != wanted) RateSums(blocks, effects);
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

  // The sample's context (its force and the output's rate of change).
  GyroscopeSampleContext<double> ContextAt(int j) const {
    GyroscopeSampleContext<double> context;
    context.specific_force = samples_.specific_force[j].data();
    if (!samples_.output_rate.empty()) context.output_rate = samples_.output_rate[j].data();
    return context;
  }

  // The derivatives of one effect's term by its coefficients at a sample (d_term[i][k]: of the
  // term's component k by coefficient i), v and the context given: a ceres::Jet of the effect's
  // own size through its Apply alone.
  template <typename Effect>
  static void EffectTermDerivatives(const double* coefficients,
                                    const GyroscopeSampleContext<double>& context,
                                    const std::array<double, 3>& along, double (*d_term)[3]) {
    constexpr int kCount = Effect::kInfo.coefficients;
    using Jet = ceres::Jet<double, kCount>;
    Jet c[kCount];
    for (int i = 0; i < kCount; ++i) c[i] = Jet(coefficients[i], i);
    const GyroscopeContextAs<Jet> as(context);
    GyroscopeRateTerms<Jet> terms;
    for (int k = 0; k < 3; ++k) terms.along[k] = Jet(along[k]);
    Effect::Apply(c, as.context, &terms);
    const std::array<Jet, 3>& term =
        Effect::kInfo.stage == GyroscopeEffectStage::kOutput ? terms.output_shift
        : Effect::kInfo.stage == GyroscopeEffectStage::kAxis ? terms.per_axis
                                                             : terms.rate_shift;
    for (int i = 0; i < kCount; ++i)
      for (int k = 0; k < 3; ++k) d_term[i][k] = term[k].v[i];
  }

  // S = dv'/dv at a sample (row-major), the kAxis terms' slope: a ceres::Jet of 3 seeded on v.
  static void AxisSlope(const double* coefficients, const GyroscopeSampleContext<double>& context,
                        const std::array<double, 3>& along, double* s) {
    using Jet = ceres::Jet<double, 3>;
    Jet c[kGyroscopeEffectCoefficientCount];
    for (int i = 0; i < kGyroscopeEffectCoefficientCount; ++i) c[i] = Jet(coefficients[i]);
    const GyroscopeContextAs<Jet> as(context);
    GyroscopeRateTerms<Jet> terms;
    for (int k = 0; k < 3; ++k) terms.along[k] = Jet(along[k], k);
    ApplyGyroscopeEffects<GyroscopeEffectStage::kAxis>(c, as.context, &terms);
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) s[3 * i + k] = (i == k ? 1.0 : 0.0) + terms.per_axis[i].v[k];
  }

  // For the differentiated coefficients at a sample: dprimed[m] = dv'/dc_m (kOutput: S diag(gain)
  // dshift/dc; kAxis: the term's own) and drate[m] = the kRate term's derivative.
  void EffectDerivatives(double const* const* blocks, const GyroscopeSampleContext<double>& context,
                         const std::array<double, 3>& along, const double* s, const int* slot,
                         double (*dprimed)[3], double (*drate)[3]) const {
    const double* parameters = blocks[0];
    int first = 0;
    auto one = [&](auto effect) {
      using Effect = decltype(effect);
      constexpr int kCount = Effect::kInfo.coefficients;
      bool wanted = false;
      for (int i = 0; i < kCount; ++i) wanted = wanted || slot[first + i] >= 0;
      if (wanted) {
        double d_term[kCount][3];
        EffectTermDerivatives<Effect>(blocks[2] + first, context, along, d_term);
        for (int i = 0; i < kCount; ++i) {
          const int m = slot[first + i];
          if (m < 0) continue;
          for (int k = 0; k < 3; ++k) dprimed[m][k] = drate[m][k] = 0.0;
          if (Effect::kInfo.stage == GyroscopeEffectStage::kOutput) {
            for (int r = 0; r < 3; ++r)
              for (int k = 0; k < 3; ++k)
                dprimed[m][r] += s[3 * r + k] * parameters[kGyroscopeGainX + k] * d_term[i][k];
          } else if (Effect::kInfo.stage == GyroscopeEffectStage::kAxis) {
            for (int k = 0; k < 3; ++k) dprimed[m][k] = d_term[i][k];
          } else {
            for (int k = 0; k < 3; ++k) drate[m][k] = d_term[i][k];
          }
        }
      }
      first += kCount;
    };
    std::apply([&](auto... effect) { (one(effect), ...); }, GyroscopeEffects{});
  }

  // The memo's sums D(:, u) = sum_j c_j R_N^T R_j dw_j/du for the differentiated unknowns, from
  // its path. Called with memo_mutex_ held, after Integrated(blocks).
  void RateSums(double const* const* blocks, bool effects) const {
    const double* parameters = blocks[0];
    const int count = static_cast<int>(samples_.raw.size());
    const std::vector<std::array<double, 4>>& path = memo_.path;
    int* column = memo_.column;
    const int index = DifferentiatedColumns(effects, column);
    const int differentiated = index - kGyroscopeCalibrationUnknowns;
    const bool any_effect = std::any_of(blocks[2], blocks[2] + kGyroscopeEffectCoefficientCount,
                                        [](double c) { return c != 0.0; });
    const bool axis_active = GyroscopeStageActive(blocks[2], GyroscopeEffectStage::kAxis);
    // slot[c]: the place of coefficient c among those differentiated, -1 when it is not.
    int slot[kGyroscopeEffectCoefficientCount];
    std::fill(slot, slot + kGyroscopeEffectCoefficientCount, -1);
    for (int m = 0; m < differentiated; ++m) slot[estimated_[m]] = m;
    // T and dT/dp (T is linear in the 6 angles; one Jet evaluation gives every entry's slope).
    using AngleJet = ceres::Jet<double, kGyroscopeParameterCount>;
    AngleJet angle_parameters[kGyroscopeParameterCount], angle_matrix[9];
    for (int i = 0; i < kGyroscopeParameterCount; ++i)
      angle_parameters[i] = AngleJet(parameters[i], i);
    GyroscopeMisalignmentMatrix(angle_parameters, angle_matrix);
    double t[9];
    for (int i = 0; i < 9; ++i) t[i] = angle_matrix[i].a;
    // acc[u] = sum_j c_j R_j dw_j/du (the start's frame), carried to the end below.
    std::vector<std::array<double, 3>> acc(index, {0.0, 0.0, 0.0});
    double dprimed[kGyroscopeEffectCoefficientCount][3], drate[kGyroscopeEffectCoefficientCount][3];
    for (int j = 0; j < count; ++j) {
      const double weight = 0.5 * ((j > 0 ? samples_.step_s[j - 1] : 0.0) +
                                   (j + 1 < count ? samples_.step_s[j] : 0.0));
      double here[9];
      QuaternionToRotationMatrix(path[j].data(), here);
      for (double& h : here) h *= weight;
      double primed[3], s[9] = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0}, centred[3];
      const GyroscopeSampleContext<double> context = ContextAt(j);
      GyroscopeRateTerms<double> terms;
      GyroscopeRateTermsAt(parameters, blocks[1], any_effect ? blocks[2] : nullptr,
                           samples_.raw[j].data(), context, &terms);
      for (int k = 0; k < 3; ++k) {
        primed[k] = terms.along[k] + terms.per_axis[k];
        centred[k] = samples_.raw[j][k] + terms.output_shift[k] - blocks[1][k];
      }
      if (axis_active) AxisSlope(blocks[2], context, terms.along, s);
      if (differentiated > 0)
        EffectDerivatives(blocks, context, terms.along, s, slot, dprimed, drate);
      // M = c_j R_j T: a change of v' carried to the start's frame.
      double m[9];
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
          m[3 * r + c] =
              here[3 * r] * t[c] + here[3 * r + 1] * t[3 + c] + here[3 * r + 2] * t[6 + c];
      auto add = [&](int u, const double* through_t, const double* direct) {
        for (int r = 0; r < 3; ++r) {
          double value = 0.0;
          if (through_t != nullptr)
            value +=
                m[3 * r] * through_t[0] + m[3 * r + 1] * through_t[1] + m[3 * r + 2] * through_t[2];
          if (direct != nullptr)
            value +=
                here[3 * r] * direct[0] + here[3 * r + 1] * direct[1] + here[3 * r + 2] * direct[2];
          acc[u][r] += value;
        }
      };
      for (int p = 0; p < kGyroscopeGainX; ++p) {  // an angle: dT/dp v'
        double dw[3];
        for (int a = 0; a < 3; ++a) {
          dw[a] = angle_matrix[3 * a].v[p] * primed[0] + angle_matrix[3 * a + 1].v[p] * primed[1] +
                  angle_matrix[3 * a + 2].v[p] * primed[2];
        }
        add(p, nullptr, dw);
      }
      for (int k = 0; k < 3; ++k) {
        const double column_k[3] = {s[k], s[3 + k], s[6 + k]};
        const double gain_k[3] = {column_k[0] * centred[k], column_k[1] * centred[k],
                                  column_k[2] * centred[k]};
        add(kGyroscopeGainX + k, gain_k, nullptr);
        const double g = -parameters[kGyroscopeGainX + k];
        const double offset_k[3] = {column_k[0] * g, column_k[1] * g, column_k[2] * g};
        add(kGyroscopeParameterCount + k, offset_k, nullptr);
      }
      for (int e = 0; e < differentiated; ++e)
        add(kGyroscopeCalibrationUnknowns + e, dprimed[e], drate[e]);
    }
    // D(:, u) = R_N^T acc[u].
    double end[9];
    QuaternionToRotationMatrix(path.back().data(), end);
    for (int u = 0; u < index; ++u) {
      for (int r = 0; r < 3; ++r)
        memo_.sums[u][r] = end[r] * acc[u][0] + end[3 + r] * acc[u][1] + end[6 + r] * acc[u][2];
    }
    memo_.derivative_count = index;
    memo_.derivatives = effects ? 2 : 1;
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
          const GyroscopeContextAs<T> as(ContextAt(j));
          GyroscopeCorrectedRate(parameters, offset, effects, samples_.raw[j].data(), as.context,
                                 rate);
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
    if (gyroscope_jacobian) {
      // Without the effects' block (the model without them, or constant): the 12 unknowns'
      // derivatives; with it, those by the estimated coefficients too (held ones have zero
      // columns).
      const bool effects = jacobians[2] != nullptr;
      if (exact_derivatives_) {
        RotationJacobian(blocks, effects, before, rotation, rotated_jacobian);
      } else {
        TransportedJacobian(blocks, effects, before, rotation, rotated_jacobian);
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

  // The last point the turn was integrated at (the gyroscope's unknowns), its attitude at every
  // sample and R, and the sums D last asked for: Ceres evaluates the cost at a candidate point
  // and, when it accepts it, the Jacobian at the same point; the rank check, the residuals and
  // the covariance after the solve ask again at the solution. Each is integrated once.
  struct Memo {
    bool valid = false;
    std::array<double, kUnknowns> point{};
    std::vector<std::array<double, 4>> path;
    double rotation[9] = {};
    int derivatives = 0;  // 0: none; 1: the 12 unknowns'; 2: and the estimated effects'
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
                                 ContextAt(j), rate);
        },
        samples_.step_s, memo_.rotation, &memo_.path);
    memo_.point = point;
    memo_.valid = true;
    return memo_;
  }
};

}  // namespace accelcal

#endif  // ACCELCAL_RESIDUALS_GYROSCOPE_RESIDUALS_H_
