#pragma once
// Numerical helpers shared by the relative-equilibrium and relative-periodic-orbit code (not
// installed): Jacobians by central differences, orthonormal complements and Gauss–Newton.
#include <Eigen/Dense>

#include <algorithm>

namespace noether::detail {

// Columns of ∂f/∂u by central differences, step h in every (scaled) coordinate.
template <class F>
Eigen::MatrixXd jacobian_by_differences(F&& f, const Eigen::VectorXd& u, double h) {
  const Eigen::VectorXd f0 = f(u);
  Eigen::MatrixXd J(f0.size(), u.size());
  Eigen::VectorXd y = u;
  for (Eigen::Index j = 0; j < u.size(); ++j) {
    y[j] = u[j] + h;
    const Eigen::VectorXd plus = f(y);
    y[j] = u[j] - h;
    const Eigen::VectorXd minus = f(y);
    y[j] = u[j];
    J.col(j) = (plus - minus) / (2 * h);
  }
  return J;
}

// Orthonormal basis of the orthogonal complement of span(W) (columns normalised first, so that
// columns in different units count alike; singular values below `rank_tolerance` × the largest
// count as dependent).
inline Eigen::MatrixXd complement(Eigen::MatrixXd W, double rank_tolerance = 1e-10) {
  for (Eigen::Index j = 0; j < W.cols(); ++j) W.col(j) /= std::max(1e-300, W.col(j).norm());
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(W.transpose(), Eigen::ComputeFullV);
  const auto& s = svd.singularValues();
  Eigen::Index rank = 0;
  for (Eigen::Index i = 0; i < s.size(); ++i)
    if (s[i] > rank_tolerance * s[0]) ++rank;
  return svd.matrixV().rightCols(W.rows() - rank);
}

// Newton on F(u) = 0: minimum-norm Gauss–Newton steps (gauge directions, where F is flat, stay
// put), each halved up to 30 times until ‖F‖ falls. The Jacobian is `jacobian(u)`; directions
// whose rate is below `flat` × the largest (singular values of the Jacobian, as the complete
// orthogonal decomposition ranks them; 0: Eigen's default, ~ε × size) count as flat too. Stops at
// max |F| ≤ tolerance, after max_iterations, or when no halving helps.
struct NewtonResult {
  double first = 0, last = 0;  // max |F| at the start and at the end
  int iterations = 0;
};
template <class F, class Jacobian>
NewtonResult gauss_newton(F&& f, Jacobian&& jacobian, Eigen::VectorXd& u, double tolerance, int max_iterations,
                          double flat = 0) {
  Eigen::VectorXd res = f(u);
  NewtonResult out;
  out.first = out.last = res.cwiseAbs().maxCoeff();
  for (; out.iterations < max_iterations && out.last > tolerance; ++out.iterations) {
    const Eigen::MatrixXd J = jacobian(u);
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod;
    if (flat > 0) cod.setThreshold(flat);
    const Eigen::VectorXd step = cod.compute(J).solve(-res);
    bool improved = false;
    double lambda = 1;
    for (int halving = 0; halving < 30 && !improved; ++halving, lambda /= 2) {
      const Eigen::VectorXd trial = u + lambda * step;
      const Eigen::VectorXd r = f(trial);
      if (r.allFinite() && r.norm() < res.norm()) u = trial, res = r, improved = true;
    }
    out.last = res.cwiseAbs().maxCoeff();
    if (!improved) break;
  }
  return out;
}

// The same with the Jacobian by central differences (step 1e-6 in the scaled coordinates).
template <class F>
NewtonResult gauss_newton(F&& f, Eigen::VectorXd& u, double tolerance, int max_iterations) {
  return gauss_newton(f, [&](const Eigen::VectorXd& x) { return jacobian_by_differences(f, x, 1e-6); }, u, tolerance,
                      max_iterations);
}

}  // namespace noether::detail
