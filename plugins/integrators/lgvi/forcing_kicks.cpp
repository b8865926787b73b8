// The kicks of the forces beyond the potential (docs/equations.md (33.1), (33.2), (33.4)).
#include "forcing_kicks.hpp"

#include <noether/error.hpp>

#include <algorithm>
#include <limits>
#include <sstream>

namespace lgvi {

void ForcingKicks::open(State& s, double h) {
  kick_from_ = s;
  s.p += (0.5 * h) * evaluate_.total().f;
  s.Pi += (0.5 * h) * evaluate_.total().M;
  evaluate_.add_kick(kick_from_, s, 0.5 * h, s.force_balance);
}

void ForcingKicks::close(State& s, double h) {
  kick_from_ = s;
  const double eps = std::numeric_limits<double>::epsilon();
  for (int iteration = 0;; ++iteration) {
    evaluate_(s);
    trial_p_ = kick_from_.p + (0.5 * h) * evaluate_.total().f;
    trial_Pi_ = kick_from_.Pi + (0.5 * h) * evaluate_.total().M;
    if (!evaluate_.depends_on_momenta() || (trial_p_ == s.p && trial_Pi_ == s.Pi)) {
      s.p = trial_p_;
      s.Pi = trial_Pi_;
      evaluate_.add_kick(kick_from_, s, 0.5 * h, s.force_balance);
      return;
    }
    double change = 0.0;  // the largest change of a body's momentum, relative to it
    for (Eigen::Index i = 0; i < s.p.cols(); ++i)
      change = std::max(change, (trial_p_.col(i) - s.p.col(i)).norm() / std::max(trial_p_.col(i).norm(), 1e-300));
    for (Eigen::Index k = 0; k < s.Pi.cols(); ++k)
      change = std::max(change, (trial_Pi_.col(k) - s.Pi.col(k)).norm() / std::max(trial_Pi_.col(k).norm(), 1e-300));
    s.p = trial_p_;
    s.Pi = trial_Pi_;
    if (change <= 8 * eps) {
      evaluate_.add_kick(kick_from_, s, 0.5 * h, s.force_balance);
      evaluate_(s);  // the next opening kick's forces, at z_{k+1} itself
      return;
    }
    if (iteration == 50) {
      std::ostringstream msg;
      msg << "lgvi: the closing kick of the forces (docs/equations.md eq. 33.2) did not converge at t = " << s.t
          << " with step h = " << h << " (relative change " << change
          << " after 50 iterations): the forces change the momenta too much within a step; reduce integrator.step";
      throw noether::IntegrationError(msg.str(), s.t);
    }
  }
}

}  // namespace lgvi
