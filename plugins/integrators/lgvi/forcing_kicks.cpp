// The kicks of the forces beyond the potential (docs/equations.md (33.1), (33.2), (33.4)) and
// their tangent maps ((33.6), (33.7), (33.9)).
#include "forcing_kicks.hpp"

#include <noether/error.hpp>
#include <noether/variational_equations.hpp>

#include <Eigen/LU>

#include <sstream>

namespace lgvi {

void closing_kick_failed(double t, double h, double change) {
  std::ostringstream msg;
  msg << "lgvi: the closing kick of the forces (docs/equations.md eq. 33.2) did not converge at t = " << t
      << " with step h = " << h << " (relative change " << change
      << " after 50 iterations): the forces change the momenta too much within a step; reduce integrator.step";
  throw noether::IntegrationError(msg.str(), t);
}

void ForcingKicks::open(State& s, double h) {
  kick_from_ = s;
  s.p += (0.5 * h) * evaluate_.total().f;
  s.Pi += (0.5 * h) * evaluate_.total().M;
  evaluate_.add_kick(kick_from_, s, 0.5 * h, s.force_balance);
}

void ForcingKicks::close(State& s, double h) {
  kick_from_ = s;
  const Eigen::Index n = s.p.cols(), m = s.Pi.cols();
  y_.resize(3, n + m);  // the momenta (γ, Π) as columns
  y_.leftCols(n) = s.p;
  y_.rightCols(m) = s.Pi;
  auto kick = [&](const Eigen::Matrix3Xd& y, Eigen::Matrix3Xd& out) {
    s.p = y.leftCols(n);
    s.Pi = y.rightCols(m);
    evaluate_(s);
    out.resize(3, n + m);
    out.leftCols(n) = kick_from_.p + (0.5 * h) * evaluate_.total().f;
    out.rightCols(m) = kick_from_.Pi + (0.5 * h) * evaluate_.total().M;
  };
  const bool again = solve_closing_kick(y_, trial_, evaluate_.depends_on_momenta(), kick, s.t, h);
  s.p = y_.leftCols(n);
  s.Pi = y_.rightCols(m);
  evaluate_.add_kick(kick_from_, s, 0.5 * h, s.force_balance);
  if (again) evaluate_(s);  // the next opening kick's forces, at z_{k+1} itself
}

void ForcingKicks::open_tangent(const State& z, double h, TangentCarrier& carrier, Eigen::MatrixXd& V) {
  if (!jacobian_valid_) {
    evaluate_.jacobian(z, jacobian_);
    carrier.forcing_parameters_at(z);
  }
  jacobian_valid_ = false;
  noether::add_forcing_tangent(system_, jacobian_, 0.5 * h, V, V);
  carrier.add_forcing_parameters(0.5 * h, V);
}

void ForcingKicks::close_tangent(const State& z, double h, TangentCarrier& carrier, Eigen::MatrixXd& V) {
  evaluate_.jacobian(z, jacobian_);
  carrier.forcing_parameters_at(z);
  const Eigen::Index N = V.rows();
  closing_ = Eigen::MatrixXd::Identity(N, N);
  noether::add_forcing_tangent(system_, jacobian_, -0.5 * h, closing_, closing_);
  carrier.add_forcing_parameters(0.5 * h, V);
  V = closing_.partialPivLu().solve(V);
  jacobian_valid_ = true;  // the next opening kick's (K^F, G^F), at z_{k+1}
}

}  // namespace lgvi
