#pragma once
// ChaosIndicators: MEGNO and the fast Lyapunov indicator of a run (run.chaos; docs/derivatives.md,
// docs/equations.md §23), from one deviation vector δ(t) = M(t) δ0 that the integrator's tangent
// map carries beside the state (a column of State::tangent). Internal to libnoether: the stepping
// loop hands it δ after every step (Schedule::after_step), the output writes its values at every
// frame, the summary its last ones.
#include <noether/chaos_values.hpp>
#include <noether/state.hpp>
#include <noether/system.hpp>

#include <Eigen/Dense>

namespace noether {

class ChaosIndicators {
 public:
  // The norm's scales (eq. 23.1) from the system and its state at t0: a length L (the largest
  // distance between two centres; 1 for a single body), a time T = √(L³ / G M) (1 without
  // gravity), each body's momentum scale m L / T and each rigid body's angular momentum scale
  // tr(J)/3 / T; attitudes are radians.
  ChaosIndicators(const System& system, const State& initial);

  // δ0: a fixed pseudo-random direction (the same for every run of the same system), of unit
  // weighted norm, as coordinates z (docs/equations.md eq. 21.1).
  Eigen::VectorXd initial_deviation() const;
  // Starts a segment at t0 from δ0 (the run's start, or Simulation::set_state).
  void start(double t0, const Eigen::VectorXd& delta0);
  // δ after a step to t (> the previous one; an earlier or equal t is ignored). A deviation that
  // is no longer finite (a chaotic run whose ‖δ‖ passed 1e308) stops the indicators there.
  void step(double t, const Eigen::VectorXd& delta);

  const ChaosValues& values() const { return values_; }
  // Its running numbers, for a checkpoint (a continued run's indicators are the uninterrupted
  // run's to the bit): the scales L and T, the segment's t0 and t, ln‖δ‖ and ln‖δ0‖, the two
  // integrals, Y, the FLI's maximum, then values()' six (overflowed as 0 or 1).
  static constexpr std::size_t kCheckpointSize = 16;
  void save(double* out) const;
  void restore(const System& system, const double* in);
  // values() as a checkpoint holds them.
  static ChaosValues values_of(const double* checkpoint);
  // ‖δ‖ in the scaled norm of eq. 23.1.
  double norm(const Eigen::VectorXd& delta) const { return weights_.cwiseProduct(delta).norm(); }
  double length_scale() const { return L_; }
  double time_scale() const { return T_; }

 private:
  void set_scales(const System& system, double L, double T);  // weights_ from L and T (eq. 23.1)

  Eigen::VectorXd weights_;  // 1 / the scale of each coordinate of z
  double L_ = 1.0, T_ = 1.0;
  double t0_ = 0.0, t_ = 0.0;
  double log_norm_ = 0.0, log_norm0_ = 0.0;  // ln ‖δ(t)‖, ln ‖δ0‖
  double weighted_sum_ = 0.0; // ∫ s d ln‖δ‖ (s = t − t0), eq. 23.2
  double y_integral_ = 0.0;   // ∫ Y ds, eq. 23.3
  double y_ = 0.0;
  double max_log10_ = 0.0;
  ChaosValues values_;
};

}  // namespace noether
