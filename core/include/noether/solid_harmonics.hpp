#pragma once
// Real regular solid harmonics r^n P_n^m(cos θ) {cos mφ, sin mφ}, Schmidt semi-normalised
// (docs/equations.md (37.1)): their values at a point by a recursion in Cartesian coordinates
// (no division by r), their coefficients as homogeneous polynomials (from the Q_nm of
// stokes_coefficients.hpp), a body's moments of them, and the sampling of a sphere that
// projects a harmonic function onto them (37.3).
#include <noether/inertia_integrals.hpp>
#include <noether/lie.hpp>

#include <vector>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

namespace harmonic {
// Harmonic j of degree n, order m: j = n² for m = 0; n² + 2m − 1 (cosine) and n² + 2m (sine).
constexpr int count(int degree) { return (degree + 1) * (degree + 1); }  // all of degree ≤ N
constexpr int index(int n, int m, bool sine) { return n * n + (m == 0 ? 0 : 2 * m - 1 + (sine ? 1 : 0)); }
int degree(int j);
constexpr int kMaxDegree = 40;  // the polynomial coefficients need inertia integrals to this degree
}  // namespace harmonic

// The values of every harmonic of degree ≤ N at x, in the order of harmonic::index.
void solid_harmonic_values(const Vec3& x, int degree, double* values);

// Each harmonic as a homogeneous polynomial: coefficients of x^l y^m z^k in the order of
// multi_index within its degree (inertia_integrals.hpp), for degrees ≤ N ≤ kMaxDegree.
struct SolidHarmonicPolynomials {
  int degree = -1;
  std::vector<std::vector<double>> coefficients;  // [j][multi_index::index(l,m,k) − first_of_degree(n)]
};
SolidHarmonicPolynomials solid_harmonic_polynomials(int degree);

// A body's moments of the harmonics scaled to a radius a, from its inertia integrals T (of
// degree ≥ N; about its centre of mass): for Φ(x) = Σ_j c_j R_j(x/a),
//   ∫ Φ dm = Σ_j c_j mass_j,  ∫ ∇Φ dm = Σ_j c_j gradient_j,  ∫ x × ∇Φ dm = Σ_j c_j moment_j   (37.4)
struct SolidHarmonicMoments {
  int degree = -1;
  double radius = 1.0;
  Eigen::VectorXd mass;       // ∫ R_j(x/a) dm
  Eigen::Matrix3Xd gradient;  // ∫ ∇_x R_j(x/a) dm
  Eigen::Matrix3Xd moment;    // ∫ x × ∇_x R_j(x/a) dm
};
SolidHarmonicMoments solid_harmonic_moments(const InertiaIntegrals& T, double radius,
                                            const SolidHarmonicPolynomials& polynomials);

// Nodes ξ_k on the unit sphere (Gauss–Legendre in cos θ, N + 2 of them, times 2N + 2 equally
// spaced φ) and the projection P (count(N) × nodes) that gives the coefficients c = P f of a
// function sampled there, f(ξ_k) = Σ_j c_j R_j(ξ_k), exactly when f is a harmonic polynomial of
// degree ≤ N (37.3).
class SphereProjection {
 public:
  explicit SphereProjection(int degree);
  int degree() const { return degree_; }
  const std::vector<Vec3>& nodes() const { return nodes_; }
  // samples: one row per node, one column per function; returns one row per harmonic.
  Eigen::MatrixXd project(const Eigen::MatrixXd& samples) const { return projection_ * samples; }

 private:
  int degree_;
  std::vector<Vec3> nodes_;
  Eigen::MatrixXd projection_;
};

}  // namespace noether

#pragma GCC visibility pop
