#include <noether/force_jacobian.hpp>
#include <noether/lie.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace noether {

namespace {

// The forces and moments at `state` as one vector (f_1 … f_n, M_1 … M_m).
Eigen::VectorXd generalised_forces(const Potential& potential, const State& state, Workspace& workspace,
                                   Forces& forces) {
  potential.evaluate(state, forces, workspace);
  const Eigen::Index n = forces.f.cols(), m = forces.M.cols();
  Eigen::VectorXd g(3 * (n + m));
  g.head(3 * n) = Eigen::Map<const Eigen::VectorXd>(forces.f.data(), 3 * n);
  g.tail(3 * m) = Eigen::Map<const Eigen::VectorXd>(forces.M.data(), 3 * m);
  return g;
}

double position_step(const State& s) {
  double d = std::numeric_limits<double>::infinity(), size = 0.0;
  for (Eigen::Index i = 0; i < s.x.cols(); ++i) {
    size = std::max(size, s.x.col(i).norm());
    for (Eigen::Index j = i + 1; j < s.x.cols(); ++j) d = std::min(d, (s.x.col(i) - s.x.col(j)).norm());
  }
  const double L = std::isfinite(d) && d > 0 ? d : (size > 0 ? size : 1.0);
  return 1e-5 * L;
}

}  // namespace

Eigen::MatrixXd differenced_force_jacobian(const Potential& potential, const State& state, Workspace& workspace) {
  const Eigen::Index n = state.x.cols(), m = static_cast<Eigen::Index>(state.R.size());
  Forces forces;
  forces.f.resize(3, n);
  forces.M.resize(3, m);
  Eigen::MatrixXd K(3 * (n + m), 3 * (n + m));
  const double hx = position_step(state), hR = 1e-5;
  State s = state;
  for (Eigen::Index i = 0; i < n; ++i)  // ∂/∂x_i: columns 3i + a
    for (int a = 0; a < 3; ++a) {
      s.x(a, i) = state.x(a, i) + hx;
      const Eigen::VectorXd plus = generalised_forces(potential, s, workspace, forces);
      s.x(a, i) = state.x(a, i) - hx;
      const Eigen::VectorXd minus = generalised_forces(potential, s, workspace, forces);
      s.x(a, i) = state.x(a, i);
      K.col(3 * i + a) = (plus - minus) / (2 * hx);
    }
  for (Eigen::Index k = 0; k < m; ++k)  // ∂/∂θ_k along R_k exp(S(θ)): columns 3n + 3k + a
    for (int a = 0; a < 3; ++a) {
      const auto r = static_cast<std::size_t>(k);
      s.R[r] = state.R[r] * exp_so3(hR * Vec3::Unit(a));
      const Eigen::VectorXd plus = generalised_forces(potential, s, workspace, forces);
      s.R[r] = state.R[r] * exp_so3(-hR * Vec3::Unit(a));
      const Eigen::VectorXd minus = generalised_forces(potential, s, workspace, forces);
      s.R[r] = state.R[r];
      K.col(3 * n + 3 * k + a) = (plus - minus) / (2 * hR);
    }
  return K;
}

ForceJacobian force_jacobian(const Potential& potential, const State& state, Workspace& workspace) {
  const Eigen::Index size = 3 * (state.x.cols() + static_cast<Eigen::Index>(state.R.size()));
  ForceJacobian J;
  J.K.setZero(size, size);
  J.analytic = potential.force_jacobian(state, J.K, workspace);
  if (!J.analytic) J.K = differenced_force_jacobian(potential, state, workspace);
  return J;
}

}  // namespace noether
