#pragma once
// SphericalHarmonicField: a body's exterior gravity field from its Stokes coefficients, evaluated
// by Cunningham's recursion for the solid harmonics V_nm + i W_nm = (R/r)^{n+1} P_nm(sin φ) e^{imλ}
// (Cunningham 1970; Montenbruck & Gill 2000, eqs. 3.29–3.33; docs/equations.md §32):
//     V(r) = (G M / R) Σ_{n ≤ N} Σ_{m ≤ n} (C_nm V_nm + S_nm W_nm)                             (32.1)
// A derivative of such a sum is a sum of the same kind one degree higher (32.2), so the gradient
// and the Hessian are sums over the degree-(N + 1) and (N + 2) harmonics with coefficients made
// once. O(N²) per point. The series
// converges outside the Brillouin sphere (the smallest sphere about the centre of mass that holds
// the body); inside it the values are those of the truncated series, not of the body.
#include <noether/lie.hpp>
#include <noether/stokes_coefficients.hpp>

#include <array>
#include <vector>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

class SphericalHarmonicField {
 public:
  // `cs` to degree N (any normalisation; held unnormalised, so N ≤ multi_index::kMaxDegree), GM
  // = G × cs.mass.
  SphericalHarmonicField(const StokesCoefficients& cs, double G);

  struct Value {
    double potential = 0.0;            // V > 0 (per unit mass: U = −m V for a point mass m)
    Vec3 acceleration = Vec3::Zero();  // ∇V
    Mat3 hessian = Mat3::Zero();       // ∇∇V, when asked for
  };
  // At r (body frame, from the centre of mass; r ≠ 0). Not thread-safe: scratch is held.
  Value operator()(const Vec3& r, bool with_hessian = false);

  int degree() const { return degree_; }
  double reference_radius() const { return R_; }

 private:
  // Σ (C_nm V_nm + S_nm W_nm) to `degree`, unnormalised, [n(n + 1)/2 + m].
  struct Sum {
    int degree = 0;
    std::vector<double> C, S;
  };
  static Sum derivative(const Sum& sum, int axis);  // R ∂/∂x_axis of the sum (32.2)
  double evaluate(const Sum& sum) const;             // at the harmonics computed last

  int degree_;
  double R_, GM_;
  Sum field_;
  std::array<Sum, 3> gradient_;  // R ∂/∂x_a
  std::array<Sum, 6> hessian_;   // R² ∂²/∂x_a∂x_b, (a, b) = xx, xy, xz, yy, yz, zz
  std::vector<double> V_, W_;    // to degree N + 2
};

}  // namespace noether

#pragma GCC visibility pop
