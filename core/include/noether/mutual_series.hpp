#pragma once
// The mutual potential of two extended bodies to total degree N in their inertia integrals
// (docs/equations.md §12; Hou, Scheeres & Xin 2017 Eq. 17–18, evaluated in the equivalent
// Cartesian-Taylor form (12.2)), with ∂U/∂R and both torques.
//
// Frames: everything is in body A's frame. R is B's centre of mass minus A's, C rotates
// B's frame into A's (x_A = C x_B). U is the potential energy (negative).
#include <noether/export.hpp>
#include <noether/inertia_integrals.hpp>
#include <noether/lie.hpp>

#include <array>
#include <vector>

namespace noether {

struct MutualTerms {
  double U = 0.0;
  Vec3 dU_dR = Vec3::Zero();     // ∂U/∂R: the force on A (the force on B is −∂U/∂R)
  Vec3 torque_A = Vec3::Zero();  // on A about its centre of mass, A frame
  Vec3 torque_B = Vec3::Zero();  // on B about its centre of mass, A frame
};

// One evaluator per order; it keeps its scratch, so use one per thread.
class NOETHER_API MutualSeries {
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

 private:
  struct Pair {
    int alpha, gamma;            // α and γ = α + β
    std::array<int, 3> gamma_e;  // γ + e_x, γ + e_y, γ + e_z
  };
  int order_;
  std::vector<std::vector<Pair>> pairs_;  // per β (|β| ≤ N): every α with |α| ≤ N − |β|
  std::vector<double> sign_over_factorial_;  // (−1)^{|α|}/α!
  IntegralRotation rotation_;
  InertiaIntegrals rotated_;
  std::vector<double> D_, Rj_, A_, B_, L_;
};

// D^γ(1/r) at the unit vector e for |γ| ≤ L, by the Hermite (McMurchie–Davidson) recurrence
// (docs/equations.md (12.4)); D^γ(1/R) at R = |R| e is R^{−(|γ|+1)} times this.
// `scratch` holds the auxiliary orders; `D` is resized to count(L).
NOETHER_API void inverse_distance_derivatives(const Vec3& e, int L, std::vector<double>& D,
                                              std::vector<double>& scratch);

}  // namespace noether
