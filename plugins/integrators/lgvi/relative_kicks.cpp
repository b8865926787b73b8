// The forces' kicks in the relative frame's reduced momenta (docs/equations.md (33.11)).
#include "relative_kicks.hpp"

namespace lgvi {

namespace {

void set_momenta(Reduced& r, const Eigen::Matrix3Xd& y) {
  r.Gamma = y.col(0);
  r.gamma2 = y.col(1);
  r.Pi = y.col(2);
  r.Pi2 = y.col(3);
}

}  // namespace

RelativeKicks::RelativeKicks(const RelativeFrame& frame, std::shared_ptr<const noether::Forcing> forcing)
    : frame_(frame), kicks_(frame.system(), std::move(forcing)) {}

void RelativeKicks::start(const State& s, const Reduced& r) {
  kicks_.evaluator().check_balance(s, "lgvi");
  balance_ = s.force_balance;
  at(r);
  kicks_.forget_tangent();
}

void RelativeKicks::at(const Reduced& r) {
  frame_.reconstruct(r, z_);
  kicks_.at(z_);
}

ReducedForcing RelativeKicks::rates(const Reduced& r) const {
  const Forces& F = kicks_.total();
  ReducedForcing rate;
  rate.Gamma = frame_.m * (r.R2.transpose() * Vec3(F.f.col(0) / frame_.m1 - F.f.col(1) / frame_.m2));
  rate.gamma2 = F.f.col(1);
  rate.Pi = r.R * Vec3(F.M.col(0));
  rate.Pi2 = F.M.col(1);
  return rate;
}

void RelativeKicks::kick(Reduced& r, const ReducedForcing& rate, double tau) const {
  r.Gamma += tau * rate.Gamma;
  r.gamma2 += tau * rate.gamma2;
  r.Pi += tau * rate.Pi;
  r.Pi2 += tau * rate.Pi2;
}

void RelativeKicks::add_balance(const Reduced& before, const Reduced& after, double tau) {
  frame_.reconstruct(before, before_);
  frame_.reconstruct(after, after_);
  kicks_.evaluator().add_kick(before_, after_, tau, balance_);
}

void RelativeKicks::open(Reduced& r, double h) {
  kick_from_ = r;
  kick(r, rates(r), 0.5 * h);
  add_balance(kick_from_, r, 0.5 * h);
}

void RelativeKicks::close(Reduced& r, double h) {
  kick_from_ = r;
  y_ << r.Gamma, r.gamma2, r.Pi, r.Pi2;
  auto kicked = [&](const Eigen::Matrix3Xd& y, Eigen::Matrix3Xd& out) {
    set_momenta(r, y);
    at(r);
    Reduced trial = kick_from_;
    kick(trial, rates(r), 0.5 * h);
    out << trial.Gamma, trial.gamma2, trial.Pi, trial.Pi2;
  };
  const bool again = solve_closing_kick(y_, trial_, kicks_.evaluator().depends_on_momenta(), kicked, r.t, h);
  set_momenta(r, y_);
  add_balance(kick_from_, r, 0.5 * h);
  if (again) at(r);  // the next opening kick's forces, at r_{k+1} itself
}

void RelativeStepStart::keep(const Reduced& r, const ReducedForces& forces, const RelativeKicks& kicks,
                             const RelativeTangent& tangent) {
  r_ = r;
  forces_ = forces;
  balance_ = kicks.balance();
  if (tangent.carried()) tangent_ = tangent.tangent();
}

void RelativeStepStart::restore(Reduced& r, ReducedForces& forces, RelativeKicks& kicks,
                                RelativeTangent& tangent) const {
  kicks.inertial().forget_tangent();
  r = r_;
  forces = forces_;
  kicks.set_balance(balance_);
  if (tangent.carried()) tangent.set_tangent(tangent_);
  try {
    kicks.at(r);
  } catch (...) {  // it was evaluated there before
  }
}

void relative_current(const RelativeFrame& frame, const Reduced& r, const ReducedForces& forces,
                      const RelativeTangent& tangent, const RelativeKicks* kicks, State& s, Forces& f) {
  frame.reconstruct(r, s);
  s.tangent = tangent.tangent();
  if (kicks) s.force_balance = kicks->balance();
  frame.inertial_forces(r, forces, f);
}

}  // namespace lgvi
