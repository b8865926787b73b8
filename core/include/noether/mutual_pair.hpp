#pragma once
// A pair of bodies seen from the first one's frame, and its mutual terms added into noether's
// forces and body-frame moments (docs/equations.md (13.7)): shared by the mutual-series and
// mutual-exact potentials.
#include <noether/forces.hpp>
#include <noether/mutual_series.hpp>
#include <noether/state.hpp>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

struct MutualPair {
  std::size_t a = 0, b = 0;   // body indices; the expansion frame is a's
  int rigid_a = -1, rigid_b = -1;
};

struct PairFrame {
  Mat3 Ra, Rb;  // attitudes (identity for a point mass)
  Vec3 R;       // R_aᵀ (x_b − x_a)
  Mat3 C;       // R_aᵀ R_b: b's frame → a's
};

PairFrame pair_frame(const State& s, const MutualPair& p);

// A pair's share of noether's forces (13.7), apart from their sum: U, the force on a, f_a = R_a
// ∂U/∂R (on b: −f_a), and the moments in each body's frame, M_a = τ_a, M_b = Cᵀ τ_b. Computed on
// any thread; added in pair order (add_pair_share), the sum is add_mutual_terms' bit for bit.
struct PairShare {
  double U = 0.0;
  Vec3 f_a = Vec3::Zero(), M_a = Vec3::Zero(), M_b = Vec3::Zero();
};
PairShare pair_share(const PairFrame& frame, const MutualTerms& t);
void add_pair_share(const MutualPair& p, const PairShare& share, Forces& out);

// out.U += U; f_a += R_a ∂U/∂R, f_b −= R_a ∂U/∂R; M_a += τ_a; M_b += Cᵀ τ_b.
void add_mutual_terms(const MutualPair& p, const PairFrame& frame, const MutualTerms& t, Forces& out);

// K += the pair's block of the force Jacobian ∂(f, M)/∂(x, θ) (docs/equations.md (20.0), (25.6))
// from its terms and their derivatives J; n bodies (K's attitude columns start at 3n).
void add_mutual_jacobian(const MutualPair& p, const PairFrame& frame, const MutualTerms& t, const MutualJacobian& J,
                         std::size_t n, Eigen::MatrixXd& K);

}  // namespace noether

#pragma GCC visibility pop
