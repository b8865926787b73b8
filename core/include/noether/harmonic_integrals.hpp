#pragma once
// Inertia integrals modulo traces (docs/equations.md (13.9)–(13.11)).
//
// The series (13.2) pairs every T^β of degree q only with derivatives D^{α+β}(1/r) of a harmonic
// function, and D^{γ+2e_x} + D^{γ+2e_y} + D^{γ+2e_z} = 0. So what enters is the class of T modulo
// traces: of the polynomial p(u) = Σ_β T^β u^β / β! = ∫ (u·x)^q dm / q! modulo r² = u·u. Each class
// has one representative with no power of z above 1 (z² → −(x² + y²), (13.9)): 2q + 1 numbers per
// degree, against (q + 1)(q + 2)/2. A rotation maps classes to classes (r² is invariant), so the
// reduced integrals turn by a (2q + 1)² matrix per degree (13.10) instead of a square one of side
// (q + 1)(q + 2)/2, and the series' sums run over the reduced multi-indices only (13.11).
//
// Reduced integrals are stored in the layout of InertiaIntegrals (multi_index), zero at every
// multi-index whose power of z exceeds 1 ("free": (l, m, 0) and (l, m, 1)).
#include <noether/inertia_integrals.hpp>
#include <noether/lie.hpp>

#include <vector>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

// X → its representative modulo traces (13.9), in place, for the degrees ≤ order of X (stored as
// T is, X[multi_index::index(l, m, n)]): for n from the degree down to 2,
//   X^{l+2,m,n−2} −= (l+2)(l+1)/(n(n−1)) X^{lmn},  X^{l,m+2,n−2} −= (m+2)(m+1)/(n(n−1)) X^{lmn},  X^{lmn} = 0.
class TraceReduction {
 public:
  explicit TraceReduction(int order);
  void apply(double* X, int order) const;

 private:
  struct Step {
    int from, to_x, to_y;
    double f_x, f_y;
  };
  std::vector<Step> steps_;               // by degree, then decreasing n
  std::vector<std::size_t> end_of_degree_;  // steps_[0, end_of_degree_[d]) reduce degrees ≤ d
};

// T' = the integrals seen in axes rotated by C (12.6), modulo traces: from the reduced integrals of
// T, with p_{T'}(u) = p_T(Cᵀu) reduced degree by degree (13.10). Holds its scratch: one per thread.
class HarmonicRotation {
 public:
  explicit HarmonicRotation(int order);
  // `out`: the reduced T' for the degrees ≤ min(T.order, max_degree) (all of T when max_degree < 0).
  // T may be any integrals; it is reduced first.
  void apply(const Mat3& C, const InertiaIntegrals& T, InertiaIntegrals& out, int max_degree = -1);

 private:
  int order_;
  TraceReduction reduction_;
  std::vector<double> reduced_;                 // T reduced
  std::vector<std::vector<int>> global_;        // per degree q: the multi-index of each free local index
  std::vector<std::vector<double>> factorial_;  // per degree q: γ! of each free local index
  std::vector<std::vector<int>> parent_;        // per degree q: the local index of γ − e_k in degree q − 1
  std::vector<std::vector<int>> axis_;          // per degree q: that k
  std::vector<std::vector<double>> K_;          // per degree q: (2q+1)², column j = reduced (Cᵀu)^{γ_j}
};

}  // namespace noether

#pragma GCC visibility pop
