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

Eigen::MatrixXd differenced_state_jacobian(const State& state, const Eigen::VectorXd& steps,
                                          const std::function<Eigen::VectorXd(const State&)>& g) {
  const Eigen::Index n = state.x.cols(), m = static_cast<Eigen::Index>(state.R.size());
  State s = state;
  // Moves coordinate c of (21.1) by d from the state's value (d = 0: back to it).
  const auto shift = [&](Eigen::Index c, double d) {
    const Eigen::Index kind = c < 3 * n ? 0 : c < 3 * n + 3 * m ? 1 : c < 6 * n + 3 * m ? 2 : 3;
    const Eigen::Index offset = kind == 0 ? c : kind == 1 ? c - 3 * n : kind == 2 ? c - 3 * n - 3 * m : c - 6 * n - 3 * m;
    const Eigen::Index item = offset / 3;
    const int a = static_cast<int>(offset % 3);
    switch (kind) {
      case 0: s.x(a, item) = state.x(a, item) + d; break;
      case 1: {
        const auto r = static_cast<std::size_t>(item);
        s.R[r] = d == 0.0 ? state.R[r] : Mat3(state.R[r] * exp_so3(d * Vec3::Unit(a)));
        break;
      }
      case 2: s.p(a, item) = state.p(a, item) + d; break;
      default: s.Pi(a, item) = state.Pi(a, item) + d; break;
    }
  };
  Eigen::MatrixXd J;
  for (Eigen::Index c = 0; c < steps.size(); ++c) {
    shift(c, steps(c));
    const Eigen::VectorXd plus = g(s);
    shift(c, -steps(c));
    const Eigen::VectorXd minus = g(s);
    shift(c, 0.0);
    if (c == 0) J.resize(plus.size(), steps.size());
    J.col(c) = (plus - minus) / (2 * steps(c));
  }
  return J;
}

Eigen::MatrixXd differenced_force_jacobian(const Potential& potential, const State& state, Workspace& workspace) {
  const Eigen::Index n = state.x.cols(), m = static_cast<Eigen::Index>(state.R.size());
  Forces forces;
  forces.f.resize(3, n);
  forces.M.resize(3, m);
  Eigen::VectorXd steps(3 * (n + m));
  steps.head(3 * n).setConstant(position_step(state));  // positions, then attitudes by 1e-5 rad
  steps.tail(3 * m).setConstant(1e-5);
  return differenced_state_jacobian(state, steps, [&](const State& s) {
    return generalised_forces(potential, s, workspace, forces);
  });
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
