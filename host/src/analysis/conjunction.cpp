// Conjunctions on the sky (docs/equations.md §30).
#include <noether/conjunction.hpp>
#include <noether/error.hpp>

#include <cmath>
#include <limits>
#include <sstream>

namespace noether {

namespace {

using Eigen::Vector3d;

// g(t) = (P r)·(P u) (30.1) of a trajectory at t.
struct Projected {
  const Trajectory& trajectory;
  Eigen::Index a, b;
  Eigen::Matrix3d P;
  double g(double t) const {
    Eigen::Matrix3Xd x, v;
    trajectory.sample(t, x, v);
    return (P * (x.col(a) - x.col(b))).dot(P * (v.col(a) - v.col(b)));
  }
};

}  // namespace

std::vector<Conjunction> conjunctions(const Trajectory& trajectory, std::size_t target, std::size_t center,
                                      const Vector3d& line_of_sight) {
  const Vector3d l = line_of_sight.normalized();
  const Projected f{trajectory, static_cast<Eigen::Index>(target), static_cast<Eigen::Index>(center),
                    Eigen::Matrix3d::Identity() - l * l.transpose()};
  const auto& t = trajectory.times();
  std::vector<Conjunction> out;
  for (std::size_t k = 0; k + 1 < t.size(); ++k) {
    if (!(t[k + 1] > t[k])) continue;  // an impulse's two frames
    // The interval (t_k, t_k+1]: the sample at t_k is the state after an impulse there.
    double lo = t[k], hi = t[k + 1], g_lo = f.g(lo), g_hi = f.g(hi);
    if (!(g_lo < 0 && g_hi >= 0)) continue;
    // Illinois regula falsi: superlinear, bracketed.
    const double tolerance = 1e-9 * (hi - lo);
    int side = 0;
    double root = hi;
    for (int it = 0; it < 200 && hi - lo > tolerance; ++it) {
      root = (lo * g_hi - hi * g_lo) / (g_hi - g_lo);
      if (!(root > lo && root < hi)) root = 0.5 * (lo + hi);
      const double g = f.g(root);
      if (g < 0) {
        lo = root, g_lo = g;
        if (side == -1) g_hi *= 0.5;
        side = -1;
      } else {
        hi = root, g_hi = g;
        if (side == +1) g_lo *= 0.5;
        side = +1;
      }
    }
    Conjunction c;
    c.t = g_hi == 0 ? hi : root;
    Eigen::Matrix3Xd x, v;
    Eigen::MatrixXd dx, dv;
    if (trajectory.has_derivatives())
      trajectory.sample(c.t, x, v, dx, dv);
    else
      trajectory.sample(c.t, x, v);
    const Vector3d r = x.col(f.a) - x.col(f.b), u = v.col(f.a) - v.col(f.b);
    c.separation = (f.P * r).norm();
    c.target_in_front = r.dot(l) < 0;
    if (trajectory.has_derivatives()) {  // (30.2)
      const Eigen::MatrixXd dr = dx.middleRows(3 * f.a, 3) - dx.middleRows(3 * f.b, 3);
      const Eigen::MatrixXd du = dv.middleRows(3 * f.a, 3) - dv.middleRows(3 * f.b, 3);
      const Eigen::RowVectorXd dg = (f.P * u).transpose() * dr + (f.P * r).transpose() * du;
      const double h = 1e-4 * (t[k + 1] - t[k]);
      const double g_dot = (f.g(std::min(c.t + h, t[k + 1])) - f.g(std::max(c.t - h, t[k]))) /
                           (std::min(c.t + h, t[k + 1]) - std::max(c.t - h, t[k]));
      c.dt_dp = -dg / g_dot;
    }
    out.push_back(c);
  }
  return out;
}

Conjunction nearest_conjunction(const Trajectory& trajectory, std::size_t target, std::size_t center,
                                const Vector3d& line_of_sight, double t) {
  return nearest_conjunction(conjunctions(trajectory, target, center, line_of_sight), trajectory, target, center, t);
}

Conjunction nearest_conjunction(const std::vector<Conjunction>& all, const Trajectory& trajectory, std::size_t target,
                                std::size_t center, double t) {
  std::ostringstream why;
  why.precision(10);
  if (all.empty()) {
    why << "no conjunction of '" << trajectory.names.at(target) << "' and '" << trajectory.names.at(center)
        << "' on the sky in the run (" << trajectory.t_first() << " … " << trajectory.t_last() << ")";
    throw SceneError(why.str());
  }
  const Conjunction* best = &all.front();
  for (const auto& c : all)
    if (std::abs(c.t - t) < std::abs(best->t - t)) best = &c;
  const double distance = std::abs(best->t - t);
  if (trajectory.t_last() - t < distance || t - trajectory.t_first() < distance) {
    why << "t = " << t << ": the nearest conjunction in the run is at " << best->t
        << ", but the run ends (or starts) nearer to t; a conjunction beyond it could be the one meant";
    throw SceneError(why.str());
  }
  return *best;
}

}  // namespace noether
