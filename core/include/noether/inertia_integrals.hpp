#pragma once
// Inertia integrals T^{lmn} = ∫ x^l y^m z^n dm of a body about its centre of mass, in its
// body frame, for l + m + n ≤ N (docs/equations.md §12; Hou, Scheeres & Xin 2017 Eq. 16, 20).
// Not mass-normalised: T^{000} = M, and the second moments give the inertia tensor.
#include <noether/lie.hpp>
#include <noether/mesh.hpp>

#include <array>
#include <vector>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

// Multi-indices α = (l, m, n) of total degree ≤ N in one fixed order: by degree, then by
// decreasing l, then by decreasing m. The order does not depend on N, so a table of
// order N is a prefix of the table of order N + 1.
namespace multi_index {
constexpr int kMaxDegree = 40;
constexpr int count(int N) { return (N + 1) * (N + 2) * (N + 3) / 6; }        // |α| ≤ N
constexpr int count_of_degree(int d) { return (d + 1) * (d + 2) / 2; }         // |α| = d
constexpr int first_of_degree(int d) { return d * (d + 1) * (d + 2) / 6; }
constexpr int index(int l, int m, int n) {
  const int d = l + m + n, r = d - l;
  return first_of_degree(d) + r * (r + 1) / 2 + n;
}
// (l, m, n) of every index below count(kMaxDegree).
const std::array<int, 3>& exponents(int index);
int degree(int index);
// n! for n ≤ 2 kMaxDegree + 3, as a double.
double factorial(int n);
}  // namespace multi_index

struct InertiaIntegrals {
  int order = -1;
  std::vector<double> T;  // T[multi_index::index(l, m, n)]

  double operator()(int l, int m, int n) const { return T[static_cast<std::size_t>(multi_index::index(l, m, n))]; }
  double mass() const { return T[0]; }
  // ∫ x xᵀ dm, from the degree-2 integrals.
  Mat3 second_moment() const;
};

// Homogeneous ellipsoid with semi-axes (a, b, c) along (x, y, z) (Hou et al. 2017 Eq. 26):
// T^{lmn} = 3M (l−1)!! (m−1)!! (n−1)!! a^l b^m c^n / (l+m+n+3)!! when l, m, n are all even.
InertiaIntegrals ellipsoid_integrals(double mass, const Vec3& semi_axes, int order);

// Homogeneous polyhedron of density ρ, exactly, as a sum over the signed tetrahedra
// (origin, v1, v2, v3) of its faces: correct for non-star-shaped bodies. About the origin
// of the mesh's coordinates (docs/equations.md (12.4)).
InertiaIntegrals polyhedron_integrals(const Mesh& mesh, double density, int order);

// Point masses m_p at ρ_p: T^α = Σ m_p ρ_p^α.
InertiaIntegrals point_integrals(const std::vector<double>& masses,
                                             const std::vector<Vec3>& positions, int order);

// Integrals of degree ≤ 2 of a body known only by its mass and inertia tensor J (about
// its centre of mass): ∫ x xᵀ dm = ½ tr(J) I − J.
InertiaIntegrals integrals_from_inertia(double mass, const Mat3& J);

// The integrals of degree ≤ 2 (order ≤ 2 of T) seen in axes rotated by C: C t and C S Cᵀ (12.6);
// `out` is resized to count(order).
void rotate_low_degrees(const Mat3& C, const InertiaIntegrals& T, InertiaIntegrals& out, int order);

// T'^α = ∫ (C x)^α dm: the integrals of a body seen in axes rotated by C (Hou et al. 2017
// Eq. 21). Each degree maps onto itself through the coefficients of the monomials of y = Cx,
// built degree by degree (y^α = y_k y^{α − e_k}). Holds its scratch: one per thread.
class IntegralRotation {
 public:
  explicit IntegralRotation(int order);
  // `out` is resized to min(T.order, max_degree) (all of T when max_degree < 0).
  void apply(const Mat3& C, const InertiaIntegrals& T, InertiaIntegrals& out, int max_degree = -1);

 private:
  int order_;
  std::vector<std::vector<double>> K_;                  // per degree, n_d × n_d, row = α
  std::vector<std::vector<std::array<int, 3>>> plus_;   // per degree d: (β + e_j) within d + 1
  std::vector<std::vector<std::pair<int, int>>> lower_; // per degree d ≥ 1: (α − e_k, k) in d − 1
};

}  // namespace noether

#pragma GCC visibility pop
