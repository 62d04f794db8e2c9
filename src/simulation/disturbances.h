#ifndef ACCELCAL_SIMULATION_DISTURBANCES_H_
#define ACCELCAL_SIMULATION_DISTURBANCES_H_

// Simulated truths that no parameter of the catalogue (../shared/spec/error-model.md,
// models/effects.h) represents: data on which the discovery procedure must say "something
// else" rather than name an effect it knows. Each axis k in {x, y} of a sample i outputs
//
//   m_k,i = (catalogue model)_k,i + n_k,i + o_k,i + a_k sin(n theta_i + phase)
//           + s_k [i >= floor(at N)] + c_k f_k,i^3 + w_k (sin(pi i/(N-1)) - mean)
//           + h_k d_i / 2 + p_k [i in the held position at floor(at_p N)]
//           - sign(f_k,i) max(0, |f_k,i| - L_k)                               [m/s^2]
//
//   n_k,i   noise_ar1, noise_student_t_dof: n_0 = sigma_k w_0,
//           n_i = rho_k n_{i-1} + sqrt(1 - rho_k^2) sigma_k w_i, in sample order, with
//           w_i the simulator's standard normal draw or, with nu degrees of freedom, a
//           Student-t draw scaled to unit variance (times sqrt((nu - 2) / nu)). sigma_k^2
//           is the true variance (stated times noise_variance_k); it stays the marginal
//           variance whatever rho_k and nu. Tilt test and vehicle run.
//   o_k,i   outlier_fraction f, outlier_sigma k: with probability f, independently per
//           sample and axis, +-k sigma_k (a random sign). Tilt test only.
//   a_k     theta_harmonic: n = order, theta_i the reported table angle. Tilt test only.
//   s_k     bias_step: a step at sample floor(at N) of the test's N. Tilt test only.
//   c_k     scale_cubic [1/(m/s^2)^2]: f_k the true force along the axis, the one the
//           model's scale acts on (models/sensor_model.h); in the run, the true
//           acceleration projected on the axis. Tilt test and vehicle run.
//   w_k     bias_warmup: a warm-up, then a cool-down, over the test: a half sine, less its
//           mean over the test (the bias is the test's mean bias, as with the catalogue's
//           drift, so the run is not moved). Tilt test only.
//   h_k     bias_hysteresis: up-sweeps minus down-sweeps, d_i the table's turn direction
//           (common/tilt_motion.h: +1 turning up, -1 down). Tilt test only.
//   p_k     position_offset: an offset on the held position (common/tilt_motion.h) that
//           contains sample floor(at_p N), at_p = position_offset_at; none when that sample
//           is in no held position. Tilt test only.
//   L_k     full_scale: the axis clips at +-L_k in the force along it (0: it does not).
//           Tilt test and vehicle run.
//
// With every disturbance neutral the simulator's output is bit for bit what it was
// without them: the AR(1) filter runs on the simulator's own normal draws (rho = 0 passes
// them through), and the Student-t denominators and the outliers' choices and signs come
// from random streams of their own, so no draw of the simulator's stream moves.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/status.h"
#include "common/tilt_motion.h"
#include "models/effect.h"
#include "simulation/random.h"

namespace accelcal {

// Every member neutral by default. Names are the --set names (io/scenario_json.h).
struct Disturbances {
  double noise_ar1_x = 0.0;          // rho_x [1], in (-0.99, 0.99)
  double noise_ar1_y = 0.0;          // rho_y
  double noise_student_t_dof = 0.0;  // nu, in (2, 1000]; 0: Gaussian noise
  double outlier_fraction = 0.0;     // f, in [0, 0.2]
  double outlier_sigma = 10.0;       // k [sigma_k], in [0, 1000]
  int theta_harmonic_order = 1;      // n, 1 to 20
  double theta_harmonic_x = 0.0;     // a_x [m/s^2]
  double theta_harmonic_y = 0.0;     // a_y
  double theta_harmonic_phase_rad = 0.0;
  double bias_step_at = 0.5;        // a fraction of the test's samples, in (0, 1)
  double bias_step_x = 0.0;         // s_x [m/s^2]
  double bias_step_y = 0.0;         // s_y
  double scale_cubic_x = 0.0;       // c_x [1/(m/s^2)^2]
  double scale_cubic_y = 0.0;       // c_y
  double bias_warmup_x = 0.0;       // w_x [m/s^2]
  double bias_warmup_y = 0.0;       // w_y
  double bias_hysteresis_x = 0.0;   // h_x [m/s^2]
  double bias_hysteresis_y = 0.0;   // h_y
  double position_offset_at = 0.5;  // at_p, a fraction of the test's samples, in (0, 1)
  double position_offset_x = 0.0;   // p_x [m/s^2]
  double position_offset_y = 0.0;   // p_y
  double full_scale_x = 0.0;        // L_x [m/s^2], 0: no clipping
  double full_scale_y = 0.0;        // L_y

  // Whether any disturbance changes the data (an order, phase, step position or outlier
  // size alone does not).
  bool any() const;
};

// The --set names, in the order of the struct: noise_ar1_x, ..., full_scale_y.
const std::vector<std::string>& DisturbanceNames();
bool IsDisturbanceName(const std::string& name);

// Sets one disturbance by its --set name. Only the harmonic's order is checked here (a whole
// number from 1 to 20, before it becomes an int); ValidateDisturbances checks the rest.
Status SetDisturbance(const std::string& name, double value, Disturbances* disturbances);

// One error naming the first value outside its range, the range and its unit.
Status ValidateDisturbances(const Disturbances& disturbances);

// Every value, by --set name (for truth.json).
nlohmann::json DisturbancesJson(const Disturbances& disturbances);

// Applies the disturbances to one phase's samples (the tilt test's or the run's), which must
// come in sample order: the AR(1) filter carries state from one sample to the next.
class SampleDisturber {
 public:
  // `seed` and `stream` are the simulator's for this phase; the disturber's own streams
  // are derived from them. `theta_rad` is the tilt test's reported angles (empty in the run).
  SampleDisturber(const Disturbances& disturbances, Phase phase, int sample_count, double sigma_x,
                  double sigma_y, uint64_t seed, uint64_t stream,
                  const std::vector<double>& theta_rad = {});

  // Whether Apply reads the forces along the axes (the cubic scale term and clipping).
  bool needs_forces() const { return needs_forces_; }

  // Turns sample i's noiseless outputs (*output_x, *output_y, from the catalogue's model)
  // into its measured outputs. normal_x and normal_y are the simulator's two standard normal
  // draws for the sample; force_along_x and force_along_y [m/s^2] are read only when
  // needs_forces(), theta_reported_rad only in the tilt test.
  void Apply(int sample_index, double theta_reported_rad, double force_along_x,
             double force_along_y, double normal_x, double normal_y, double* output_x,
             double* output_y);

  // The samples an outlier hit, ascending (tilt test only).
  const std::vector<int>& outlier_indices_x() const { return x_.outlier_indices; }
  const std::vector<int>& outlier_indices_y() const { return y_.outlier_indices; }

 private:
  // One axis's AR(1) noise state and its deterministic terms.
  struct Axis {
    double sigma = 0.0;
    double rho = 0.0;
    double innovation_sigma = 0.0;  // sqrt(1 - rho^2) sigma: keeps sigma^2 the marginal variance
    double previous_noise = 0.0;
    double harmonic_amplitude = 0.0;
    double step_size = 0.0;
    double scale_cubic = 0.0;
    double warmup = 0.0;
    double hysteresis = 0.0;
    double position_offset = 0.0;
    double full_scale = 0.0;
    bool started = false;  // n_0 = sigma w_0 has no predecessor
    std::vector<int> outlier_indices;
  };

  // A unit-variance innovation from the simulator's normal draw: the draw itself, or a
  // Student-t of nu degrees of freedom scaled to unit variance.
  double UnitInnovation(double normal);
  // sin(pi i/(N-1)): the warm-up and cool-down's shape at sample i, before its mean is taken.
  double WarmUp(int sample_index) const;
  void ApplyToAxis(int sample_index, double theta_reported_rad, double force_along_axis,
                   double normal, Axis* axis, double* output);

  const bool in_tilt_test_;
  const double student_t_dof_;
  const double outlier_fraction_;
  const double outlier_sigma_;
  const int harmonic_order_;
  const double harmonic_phase_rad_;
  const int step_sample_;
  const bool needs_forces_;
  double warmup_mean_ = 0.0;  // of sin(pi i/(N-1)) over the test
  int sample_count_ = 0;
  std::vector<double> turn_direction_;  // tilt test, with a hysteresis
  StaticPosition offset_position_;      // tilt test, with a position offset; empty: none
  RandomSource student_t_random_;
  RandomSource outlier_random_;
  Axis x_;
  Axis y_;
};

}  // namespace accelcal

#endif  // ACCELCAL_SIMULATION_DISTURBANCES_H_
