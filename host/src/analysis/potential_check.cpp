#include <noether/force_jacobian.hpp>
#include <noether/forces.hpp>
#include <noether/potential_check.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

namespace noether {

namespace {

// The smallest distance between two body centres: sets the finite-difference step.
double length_scale(const State& s) {
  double d = std::numeric_limits<double>::infinity();
  for (Eigen::Index i = 0; i < s.x.cols(); ++i)
    for (Eigen::Index j = i + 1; j < s.x.cols(); ++j) d = std::min(d, (s.x.col(i) - s.x.col(j)).norm());
  return std::isfinite(d) && d > 0 ? d : 1.0;
}

bool finite(const Forces& f) { return std::isfinite(f.U) && f.f.allFinite() && f.M.allFinite(); }

// The force Jacobian (docs/equations.md §20): the model's own against central differences of its
// forces (20.4), and — analytic or differenced — the symmetry of K − ½ diag(S(M_k)) (20.3): the
// forces and moments are the gradient of one U.
// `differenced` is (20.4) from the evaluations that checked the forces (no more are made).
void check_jacobian(const Potential& potential, const State& s, const Forces& f0, Workspace& workspace,
                    const Eigen::MatrixXd& differenced, const std::string& label, const PotentialCheckOptions& o,
                    std::vector<PotentialCheckRow>& rows) {
  ForceJacobian J;
  J.K.setZero(differenced.rows(), differenced.cols());
  J.analytic = potential.force_jacobian(s, J.K, workspace);
  if (!J.analytic) J.K = differenced;
  const double scale = std::max(differenced.cwiseAbs().maxCoeff(), 1e-300);
  if (J.analytic) {
    const double err = (J.K - differenced).cwiseAbs().maxCoeff() / scale;
    rows.push_back({label, "jacobian", "analytic vs FD", err, o.tolerance, err <= o.tolerance});
  }
  Eigen::MatrixXd sym = J.K;
  const Eigen::Index N = 3 * s.x.cols();
  for (Eigen::Index k = 0; k < f0.M.cols(); ++k) sym.block<3, 3>(N + 3 * k, N + 3 * k) -= 0.5 * hat(f0.M.col(k));
  const double asym = (sym - sym.transpose()).cwiseAbs().maxCoeff() / scale;
  // Analytic: to round-off; differenced: to the differences' accuracy.
  const double tol = J.analytic ? 1e-10 : o.tolerance;
  rows.push_back({label, "symmetry", J.analytic ? "K analytic" : "K differenced", asym, tol, asym <= tol});
}

void check_state(const System& sys, const Potential& potential, const State& s,
                 const std::string& label, const PotentialCheckOptions& o,
                 std::vector<PotentialCheckRow>& rows) {
  Forces f0, tmp;
  f0.resize(sys);
  tmp.resize(sys);
  // One workspace for the state and its neighbours: models that choose (orders from a
  // tolerance) choose once, at s.
  const auto workspace = potential.make_workspace();
  potential.evaluate(s, f0, *workspace);
  if (!finite(f0)) {
    rows.push_back({label, "finite", "all", NAN, 0.0, false});
    return;
  }
  // U at a neighbouring state; its forces and moments go into column c of the differenced
  // force Jacobian (20.4), with the sign of the step.
  const Eigen::Index n = s.x.cols(), m = f0.M.cols();
  Eigen::MatrixXd differenced = Eigen::MatrixXd::Zero(3 * (n + m), 3 * (n + m));
  auto U = [&](const State& st, Eigen::Index c, double sign, double h) {
    potential.evaluate(st, tmp, *workspace);
    differenced.col(c).head(3 * n) += sign / (2 * h) * Eigen::Map<const Eigen::VectorXd>(tmp.f.data(), 3 * n);
    differenced.col(c).tail(3 * m) += sign / (2 * h) * Eigen::Map<const Eigen::VectorXd>(tmp.M.data(), 3 * m);
    return tmp.U;
  };
  const double hx = 1e-5 * length_scale(s), hR = 1e-5;
  // Central differences of U cannot resolve less than about ε|U|/h: the round-off floor is
  // added to the tolerance so that a small force or moment is not failed on round-off alone.
  const double eps = std::numeric_limits<double>::epsilon();
  const double floor_x = 64 * eps * std::abs(f0.U) / hx, floor_R = 64 * eps * std::abs(f0.U) / hR;
  double fscale = 0, mscale = 0;
  for (Eigen::Index i = 0; i < f0.f.cols(); ++i) fscale = std::max(fscale, f0.f.col(i).norm());
  for (Eigen::Index k = 0; k < f0.M.cols(); ++k) mscale = std::max(mscale, f0.M.col(k).norm());
  for (std::size_t i = 0; i < sys.size(); ++i) {
    const auto c = static_cast<Eigen::Index>(i);
    Vec3 fd;
    for (int a = 0; a < 3; ++a) {  // f_i = −∂U/∂x_i
      State sp = s, sm = s;
      sp.x(a, c) += hx;
      sm.x(a, c) -= hx;
      fd[a] = -(U(sp, 3 * c + a, 1, hx) - U(sm, 3 * c + a, -1, hx)) / (2 * hx);
    }
    const double scale = std::max(fscale, floor_x);
    const double err = scale > 0 ? (fd - Vec3(f0.f.col(c))).norm() / scale : 0.0;
    const double tol = o.tolerance + floor_x / std::max(scale, 1e-300);
    rows.push_back({label, "force", sys.body(i).name, err, tol, err <= tol});
  }
  for (std::size_t k = 0; k < sys.rigid_count(); ++k) {
    Vec3 fd;
    for (int a = 0; a < 3; ++a) {  // η · M = −dU/dε along R exp(ε S(η))
      State sp = s, sm = s;
      sp.R[k] = s.R[k] * exp_so3(hR * Vec3::Unit(a));
      sm.R[k] = s.R[k] * exp_so3(-hR * Vec3::Unit(a));
      fd[a] = -(U(sp, 3 * n + 3 * static_cast<Eigen::Index>(k) + a, 1, hR) -
                U(sm, 3 * n + 3 * static_cast<Eigen::Index>(k) + a, -1, hR)) / (2 * hR);
    }
    const auto c = static_cast<Eigen::Index>(k);
    const double scale = std::max(mscale, floor_R);
    const double err = scale > 0 ? (fd - Vec3(f0.M.col(c))).norm() / scale : 0.0;
    const double tol = o.tolerance + floor_R / std::max(scale, 1e-300);
    rows.push_back({label, "moment", sys.body(sys.body_of_rigid(k)).name, err, tol, err <= tol});
  }
  check_jacobian(potential, s, f0, *workspace, differenced, label, o, rows);
  if (!o.third_law) return;
  Vec3 F = Vec3::Zero(), T = Vec3::Zero();
  double Fmag = 0, Tmag = 0;
  for (std::size_t i = 0; i < sys.size(); ++i) {
    const auto c = static_cast<Eigen::Index>(i);
    const Vec3 x = s.x.col(c), f = f0.f.col(c);
    F += f;
    Fmag += f.norm();
    T += x.cross(f);
    Tmag += x.norm() * f.norm();
    if (const int k = sys.rigid_index(i); k >= 0) {
      T += s.R[static_cast<std::size_t>(k)] * f0.M.col(k);
      Tmag += f0.M.col(k).norm();
    }
  }
  const double eF = Fmag > 0 ? F.norm() / Fmag : 0, eT = Tmag > 0 ? T.norm() / Tmag : 0;
  rows.push_back({label, "net force", "all", eF, o.third_law_tolerance, eF <= o.third_law_tolerance});
  rows.push_back({label, "net torque", "all", eT, o.third_law_tolerance, eT <= o.third_law_tolerance});
}

}  // namespace

bool PotentialCheckReport::passed() const {
  return !rows.empty() && std::all_of(rows.begin(), rows.end(), [](const auto& r) { return r.pass; });
}

std::string PotentialCheckReport::format() const {
  std::string out = "state        quantity    body              error       tolerance  result\n";
  char line[256];
  for (const auto& r : rows) {
    std::snprintf(line, sizeof line, "%-12s %-11s %-16s %11.3e %11.1e  %s\n", r.state.c_str(),
                  r.quantity.c_str(), r.body.c_str(), r.error, r.tolerance, r.pass ? "pass" : "FAIL");
    out += line;
  }
  out += passed() ? "all checks passed\n" : "CHECK FAILED\n";
  return out;
}

PotentialCheckReport check_potential(const System& system, const Potential& potential,
                                     const State& state, const PotentialCheckOptions& options) {
  PotentialCheckReport report;
  check_state(system, potential, state, "scene", options, report.rows);
  std::mt19937 rng(options.seed);
  std::normal_distribution<double> normal;
  const double L = length_scale(state);
  for (int k = 1; k <= options.perturbed_states; ++k) {
    State s = state;
    for (Eigen::Index i = 0; i < s.x.cols(); ++i)  // move centres by ~5% of the closest distance
      for (int a = 0; a < 3; ++a) s.x(a, i) += 0.05 * L * normal(rng);
    for (auto& R : s.R) {  // drawn one by one (argument order is unspecified), in g++'s former order
      const double wz = normal(rng), wy = normal(rng), wx = normal(rng);
      R = R * exp_so3(0.5 * Vec3(wx, wy, wz));
    }
    check_state(system, potential, s, "perturbed " + std::to_string(k), options, report.rows);
  }
  return report;
}

}  // namespace noether
