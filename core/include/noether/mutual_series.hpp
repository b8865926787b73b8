#pragma once
// The mutual potential of two extended bodies to total degree N in their inertia integrals
// (docs/equations.md §13; Hou, Scheeres & Xin 2017 Eq. 17–18, evaluated in the equivalent
// Cartesian-Taylor form (13.2)), with ∂U/∂R and both torques.
//
// Frames: everything is in body A's frame. R is B's centre of mass minus A's, C rotates
// B's frame into A's (x_A = C x_B). U is the potential energy (negative).
#include <noether/harmonic_integrals.hpp>
#include <noether/inertia_integrals.hpp>
#include <noether/lie.hpp>

#include <array>
#include <vector>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

struct MutualTerms {
  double U = 0.0;
  Vec3 dU_dR = Vec3::Zero();     // ∂U/∂R: the force on A (the force on B is −∂U/∂R)
  Vec3 torque_A = Vec3::Zero();  // on A about its centre of mass, A frame
  Vec3 torque_B = Vec3::Zero();  // on B about its centre of mass, A frame
};

// The derivatives of MutualTerms' ∂U/∂R (g), τ_A and τ_B, all in A's frame, with respect to R and
// to a rotation φ of B about its centre of mass, in A's axes (B's integrals T' → exp(S(φ)) T'):
// the second derivatives of the series (docs/equations.md §25).
struct MutualJacobian {
  Mat3 g_R = Mat3::Zero(), g_phi = Mat3::Zero();
  Mat3 tauA_R = Mat3::Zero(), tauA_phi = Mat3::Zero();
  Mat3 tauB_R = Mat3::Zero(), tauB_phi = Mat3::Zero();
};

// One evaluator per order; it keeps its scratch, so use one per thread.
class MutualSeries {
 public:
  explicit MutualSeries(int order);
  int order() const { return order_; }

  // T_A and T_B in their own body frames, of order ≥ the series order (or a point mass,
  // order 0). B's integrals are rotated into A's frame here.
  MutualTerms evaluate(double G, const InertiaIntegrals& TA, const InertiaIntegrals& TB,
                       const Vec3& R, const Mat3& C);
  // The same with B's integrals already in A's frame (T'_B).
  MutualTerms evaluate_rotated(double G, const InertiaIntegrals& TA, const InertiaIntegrals& TB_in_A,
                               const Vec3& R);
  // The terms and their derivatives J (25.1–25.5), from the same recurrence one degree higher.
  MutualTerms jacobian(double G, const InertiaIntegrals& TA, const InertiaIntegrals& TB, const Vec3& R,
                       const Mat3& C, MutualJacobian& J);

 private:
  struct Pair {
    int alpha, gamma;            // α and γ = α + β
    std::array<int, 3> gamma_e;  // γ + e_x, γ + e_y, γ + e_z
  };
  // One step of the recurrence (13.4) for D^γ: γ − e_c and γ − 2e_c, and the factor γ_c − 1.
  struct Recurrence {
    int gamma, component, minus1, minus2;
    double factor;
  };
  // (Ô_c X)_t += coefficient × X_s: the in-degree rotation generator (13.6) about axis c followed by
  // the reduction (13.9), from reduced integrals to reduced integrals (13.11); sorted by t.
  struct GeneratorTerm {
    int target, source;
    double coefficient;
  };
  // evaluate_rotated with D^γ computed to degree L_max ≥ N + 1 (the jacobian's N + 2);
  // `B_is_class`: TB_in_A is already reduced (13.9), as HarmonicRotation leaves it.
  MutualTerms evaluate_scaled(double G, const InertiaIntegrals& TA, const InertiaIntegrals& TB_in_A, const Vec3& R,
                              int L_max, bool B_is_class);
  // D^γ(1/r) at the unit vector e for |γ| ≤ L (13.4), in Rj_ (stride count(L)).
  const double* derivatives_at(const Vec3& e, int L);
  // out = Ô_c X on the reduced multi-indices below n (zero elsewhere).
  void turn_reduced(const std::vector<double>& X, int c, int n, std::vector<double>& out) const;

  int order_;
  std::vector<int> free_;                 // the reduced multi-indices β (power of z ≤ 1), |β| ≤ N, ascending
  std::vector<std::vector<Pair>> pairs_;  // per reduced β: every reduced α with |α| ≤ N − |β|, by α
  std::vector<std::vector<std::array<int, 6>>> second_;  // beside pairs_: γ + e_i + e_j, ij = xx yy zz xy xz yz
  std::vector<double> sign_over_factorial_;  // (−1)^{|α|}/α!
  std::vector<double> inverse_factorial_;    // 1/β!
  std::vector<int> first_of_degree_;         // index of the first multi-index of each degree
  std::vector<Recurrence> recurrence_;       // for |γ| ≤ N + 2, by degree
  std::array<std::vector<GeneratorTerm>, 3> generator_;
  TraceReduction reduction_;
  HarmonicRotation rotation_;
  InertiaIntegrals rotated_;
  std::vector<double> Rj_, A_, S_, B_, L_, M_;
  std::vector<Vec3> l_;                    // l_β,i = Σ_α A_α D^{α+β+e_i}, kept for the jacobian
  std::vector<double> OB_[3], OOB_[3][3];  // Ô_c B and Ô_d Ô_c B (jacobian)
};

}  // namespace noether

#pragma GCC visibility pop
