// jm-hybrid: the hybrid variational integrator of Nair, Ober-Blöbaum & Marsden 2009 (docs/equations.md §7) for natural systems of
// point masses, L = ½ q̇ᵀ M q̇ − V(q), q ∈ R^{3N}, M the mass matrix.
//
//  * K < Kc: the variational integrator of the trapezoidal discrete Lagrangian (Störmer–Verlet)
//    with a fixed step h; its discrete energy E_d(q_k, q_{k+1}) = ½‖(q_{k+1} − q_k)/h‖²_M
//    + ½(V(q_k) + V(q_{k+1})).
//  * K > Kc: the Jacobi–Maupertuis integrator at fixed energy E. A parameter coordinate q^c
//    advances by ±θ per step; the discrete action
//        A_d(q_k, q_{k+1}) = W(q̄) ‖q_{k+1} − q_k‖_M,  W = √(2(E − V)),  q̄ = (q_k + q_{k+1})/2,
//    and the discrete Euler–Lagrange equations D2 A_d(q_{k−1}, q_k) + D1 A_d(q_k, q_{k+1}) = 0
//    in the other n − 1 coordinates (Nair, Ober-Blöbaum & Marsden 2009 eq. (10)) give q_{k+1} by Newton's method, with
//        D1 A_d = ½ ∇W(q̄) L − W M Δ / L,  D2 A_d = ½ ∇W(q̄) L + W M Δ / L,
//        Δ = q_{k+1} − q_k, L = ‖Δ‖_M, ∇W = −∇V / W.
//    Time per step (seed eq. (11)): Δt_k = L / W(q̄); the momentum at q_{k+1} is D2 A_d.
//
// Decisions where the paper is silent (docs/jm-hybrid.md):
//  * Entering JM after a VI step: E := the discrete energy of that last VI step, and the JM map
//    starts from the last two VI points (so the discrete energy is continuous at the switch).
//    The parameter coordinate is the one with the largest |Δ_i| of that step.
//  * Leaving JM when E − V(q_k) < Kc: with the last two JM points q0, q1 and h0 = Δt of that step,
//    (8) with steps h0 and h gives q2 = q1 + h M⁻¹(P − (h/2)∇V(q1)), P = M(q1 − q0)/h0 −
//    (h0/2)∇V(q1); h is the root of E_d(q1, q2; h) = E (a scalar equation, secant method), and
//    stays the VI step until the next JM phase.
//  * The parameter coordinate is re-chosen after a JM step when another |Δ_j| exceeds
//    `rechoose_ratio` |Δ_c|.
//  * The Jacobian of the JM equations is by forward differences (n − 1 potential evaluations per
//    Newton iteration): the Potential interface gives forces, not Hessians.
//  * Dense output (the host's output times and events) by cubic Hermite interpolation of
//    (q, q̇) over the last step (third order, above the method's second).
#include <noether/error.hpp>
#include <noether/plugin.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <limits>
#include <sstream>

namespace {

using noether::IntegrationError;
using noether::Params;
using noether::SceneError;
using Vec = Eigen::VectorXd;

enum Phase { kVI = 0, kJM = 1 };

class JmHybrid final : public noether::Integrator {
 public:
  JmHybrid(const noether::System& system, std::shared_ptr<const noether::Potential> potential,
           const Params& p)
      : system_(system), evaluate_(std::move(potential)) {
    if (system.rigid_count() > 0)
      throw SceneError(p.here() + "jm-hybrid integrates natural systems of point masses; body '" +
                       system.body(system.body_of_rigid(0)).name +
                       "' is rigid. Remove its inertia, or use lgvi (rigid bodies)");
    h_ = p.at("step").as_double();
    theta_ = p.get("theta", h_);
    Kc_ = p.at("Kc").as_double();
    tol_ = p.at("newton_tolerance").as_double();
    max_iter_ = static_cast<int>(p.at("newton_max_iterations").as_int());
    ratio_ = p.at("rechoose_ratio").as_double();
    record_ = p.at("record_steps").as_bool();
    if (!(h_ > 0) || !(theta_ > 0) || !(tol_ > 0) || max_iter_ < 1 || !(ratio_ >= 1))
      throw SceneError(p.here() + "jm-hybrid: step, theta, newton_tolerance must be positive, "
                                  "rechoose_ratio ≥ 1");
    n_ = 3 * system.size();
    minv_.resize(static_cast<Eigen::Index>(n_));
    mass_.resize(static_cast<Eigen::Index>(n_));
    for (std::size_t i = 0; i < system.size(); ++i)
      for (int a = 0; a < 3; ++a) {
        mass_[static_cast<Eigen::Index>(3 * i + a)] = system.body(i).mass;
        minv_[static_cast<Eigen::Index>(3 * i + a)] = 1.0 / system.body(i).mass;
      }
    state_ = noether::State::zeros(system);
    forces_.resize(system);
  }

  void start(const noether::State& state) override {
    t_ = t_prev_ = state.t;
    q_ = q_prev_ = flat(state.x);
    p_ = p_prev_ = flat(state.p);
    V_ = evaluate(q_, grad_);
    phase_ = kVI;
    h_now_ = h_;
  }

  // One step of the current phase; its length is the method's (a JM step's Δt is an outcome),
  // so it may pass t_max: outputs and events inside it come from interpolate().
  void step(double) override {
    // The step's start, kept for interpolation and to stay there if the step fails.
    q_prev_ = q_;
    p_prev_ = p_;
    t_prev_ = t_;
    const Vec& q0 = q_prev_;
    const Vec grad0 = grad_;
    const double V0 = V_, V0_prev = V_prev_;
    try {
      if (phase_ == kVI) {
        vi_step(h_now_);
        record(kVI, -1, h_now_);
        if (kinetic(p_) > Kc_) {  // enter JM at the discrete energy of this VI step
          const Vec D = (q_ - q0) / h_now_;
          E_ = 0.5 * D.dot(mass_.cwiseProduct(D)) + 0.5 * (V_prev_ + V_);
          qm1_ = q0;
          choose(q_ - q0, c_, sign_);
          phase_ = kJM;
        }
      } else {
        Vec q_next;
        jm_step(qm1_, E_, c_, sign_, q_next);
        qm1_ = q_;
        q_ = q_next;
        record(kJM, c_, last_dt_);
        // Re-choose the parameter coordinate when another one dominates.
        const Vec D = q_ - qm1_;
        Eigen::Index j;
        D.cwiseAbs().maxCoeff(&j);
        if (std::abs(D[j]) > ratio_ * std::abs(D[c_])) choose(D, c_, sign_);
        if (E_ - V_ < Kc_) {  // leave JM: re-solve h from the discrete energy (Nair, Ober-Blöbaum & Marsden 2009)
          h_now_ = leave_jm(qm1_, E_);
          phase_ = kVI;
        }
      }
    } catch (const IntegrationError&) {
      q_ = q_prev_, p_ = p_prev_, grad_ = grad0, t_ = t_prev_, V_ = V0, V_prev_ = V0_prev;  // the last valid state
      throw;
    }
  }

  double time() const override { return t_; }
  int order() const override { return 2; }  // (the Verlet map in the Jacobi–Maupertuis time)

  void current(noether::State& state, noether::Forces& forces) override {
    state = noether::State::zeros(system_);
    unflatten(q_, p_, t_, state);
    forces.resize(system_);
    evaluate_(state, forces);  // for output; not counted as work
  }

  noether::PotentialEvaluator* potential_evaluator() override { return &evaluate_; }
  // Forces beyond the potential are refused by design, not for want of time: the Jacobi–Maupertuis
  // phase integrates the geodesics of W = √(2(E − V)) at a fixed energy E of an autonomous V, and a
  // force that does work (or depends on time, as a prescribed body does) has no fixed E — its
  // kicks would make the two phases two different dynamics.
  std::string add_forcing(std::shared_ptr<const noether::Forcing>) override {
    return "jm-hybrid's Jacobi–Maupertuis phase integrates at a fixed energy, which a force that does work (or "
           "depends on time) changes; integrate forced point masses with lgvi or rk (rkf78 for close encounters)";
  }

  void current_state(noether::State& state) override {
    state = noether::State::zeros(system_);
    unflatten(q_, p_, t_, state);
  }

  // Cubic Hermite interpolation of (q, q̇) between the two ends of the last step: third
  // order, above the method's second.
  bool interpolate(double t, noether::State& state) override {
    Vec q, p;
    hermite(t_prev_, q_prev_, p_prev_, t_, q_, p_, t, q, p);
    state = noether::State::zeros(system_);
    unflatten(q, p, t, state);
    return true;
  }

  std::vector<noether::StepSeries> take_step_series() override {
    if (!record_) return {};
    std::vector<double> rows;
    rows.swap(steps_);
    return {{"steps", 4 + n_, std::move(rows),
             "per step: t at its end, its duration Δt, phase (0 = variational, 1 = "
             "Jacobi–Maupertuis), parameter coordinate index into q (−1 in the variational "
             "phase), then q at its end (3 per body)"}};
  }

 private:
  static Vec flat(const Eigen::Matrix3Xd& m) { return Eigen::Map<const Vec>(m.data(), m.size()); }

  void unflatten(const Vec& q, const Vec& p, double t, noether::State& s) const {
    s.t = t;
    s.x = Eigen::Map<const Eigen::Matrix3Xd>(q.data(), 3, q.size() / 3);
    s.p = Eigen::Map<const Eigen::Matrix3Xd>(p.data(), 3, p.size() / 3);
  }

  double kinetic(const Vec& p) const { return 0.5 * p.dot(minv_.cwiseProduct(p)); }

  // V(q) and ∇V(q): one potential evaluation.
  double evaluate(const Vec& q, Vec& grad) {
    state_.x = Eigen::Map<const Eigen::Matrix3Xd>(q.data(), 3, q.size() / 3);
    state_.t = t_;
    evaluate_(state_, forces_);
    ++work_.potential_evaluations;
    grad = -Eigen::Map<const Vec>(forces_.f.data(), forces_.f.size());
    return forces_.U;
  }

  // Störmer–Verlet (trapezoidal discrete Lagrangian, Nair, Ober-Blöbaum & Marsden 2009 eq. (8)) with step h.
  void vi_step(double h) {
    const Vec p_half = p_ - 0.5 * h * grad_;
    q_ += h * minv_.cwiseProduct(p_half);
    V_prev_ = V_;
    V_ = evaluate(q_, grad_);
    p_ = p_half - 0.5 * h * grad_;
    t_ += h;
    ++work_.steps;
  }

  void choose(const Vec& D, int& c, double& sign) const {
    Eigen::Index j;
    D.cwiseAbs().maxCoeff(&j);
    c = static_cast<int>(j);
    sign = D[j] >= 0 ? 1.0 : -1.0;
  }

  // W(q̄) = √(2(E − V(q̄))) and ∇W = −∇V/W at the midpoint of a and b.
  double midpoint_W(const Vec& a, const Vec& b, double E, Vec& gradW) {
    Vec grad;
    const Vec mid = 0.5 * (a + b);
    const double V = evaluate(mid, grad);
    const double twoK = 2.0 * (E - V);
    if (!(twoK > 0)) {
      std::ostringstream msg;
      msg << "jm-hybrid: E − V ≤ 0 inside a Jacobi–Maupertuis step at t ≈ " << t_ << " (E = " << E
          << ", V = " << V << "): the step left the region the energy allows. Raise Kc (so the "
          << "JM phase ends earlier) or lower theta";
      throw IntegrationError(msg.str(), t_);
    }
    const double W = std::sqrt(twoK);
    gradW = -grad / W;
    return W;
  }

  // D1 A_d(a, b) (sign = −1) or D2 A_d(a, b) (sign = +1).
  Vec action_gradient(const Vec& a, const Vec& b, double E, double side) {
    Vec gradW;
    const double W = midpoint_W(a, b, E, gradW);
    const Vec D = b - a;
    const Vec MD = mass_.cwiseProduct(D);
    const double L = std::sqrt(D.dot(MD));
    return 0.5 * L * gradW + side * (W / L) * MD;
  }

  // One JM step from (q_{k−1}, q_k) = (qm1, q_): q_{k+1}^c = q_k^c ± θ; the other coordinates
  // from D2 A_d(q_{k−1}, q_k) + D1 A_d(q_k, q_{k+1}) = 0 (Nair, Ober-Blöbaum & Marsden 2009 eq. (10)).
  // On a Newton failure, tries once more with the next-largest coordinate of the last step as
  // the parameter (a documented fallback); the parameter actually used is returned in c, sign.
  void jm_step(const Vec& qm1, double E, int& c, double& sign, Vec& q_next) {
    if (jm_try(qm1, E, c, sign, q_next)) return;
    const Vec D = (q_ - qm1).cwiseAbs();
    Eigen::Index j = -1;
    for (Eigen::Index i = 0; i < D.size(); ++i)
      if (i != c && (j < 0 || D[i] > D[j])) j = i;
    if (j >= 0 && D[j] > 0) {
      const int c2 = static_cast<int>(j);
      const double sign2 = (q_ - qm1)[j] >= 0 ? 1.0 : -1.0;
      if (jm_try(qm1, E, c2, sign2, q_next)) {
        c = c2;
        sign = sign2;
        return;
      }
    }
    std::ostringstream msg;
    msg << "jm-hybrid: the Jacobi–Maupertuis step did not converge at t ≈ " << t_
        << " (parameter coordinate " << c << ", and " << j << " as fallback; θ = " << theta_
        << "). The curve may have stopped being a graph over these coordinates; lower theta";
    throw IntegrationError(msg.str(), t_);
  }

  bool jm_try(const Vec& qm1, double E, int c, double sign, Vec& q_next) {
    const Vec left = action_gradient(qm1, q_, E, +1.0);  // D2 A_d(q_{k−1}, q_k)
    // Guess: the previous step, scaled so that q^c advances by θ.
    const Vec Dprev = q_ - qm1;
    const double scale = std::abs(Dprev[c]) > 0 ? theta_ / std::abs(Dprev[c]) : 1.0;
    q_next = q_ + scale * Dprev;
    q_next[c] = q_[c] + sign * theta_;
    const auto free = free_indices(c);
    const auto m = static_cast<Eigen::Index>(free.size());
    auto residual = [&](const Vec& y) {
      const Vec r = left + action_gradient(q_, y, E, -1.0);
      Vec out(m);
      for (Eigen::Index i = 0; i < m; ++i) out[i] = r[free[static_cast<std::size_t>(i)]];
      return out;
    };
    Vec r = residual(q_next);
    const double step_scale = (q_next - q_).norm();
    double previous = std::numeric_limits<double>::infinity();
    for (int it = 1; it <= max_iter_; ++it) {
      Eigen::MatrixXd Jac(m, m);  // forward differences, step √ε × the coordinate's size
      for (Eigen::Index j = 0; j < m; ++j) {
        const auto col = free[static_cast<std::size_t>(j)];
        const double e = 1.5e-8 * std::max({std::abs(q_next[col]), step_scale, 1e-300});
        Vec y = q_next;
        y[col] += e;
        Jac.col(j) = (residual(y) - r) / e;
      }
      const Vec delta = Jac.partialPivLu().solve(r);
      if (!delta.allFinite()) return false;
      for (Eigen::Index j = 0; j < m; ++j) q_next[free[static_cast<std::size_t>(j)]] -= delta[j];
      ++work_.newton_iterations;
      const double d = delta.norm();
      // Converged, or stalled at the round-off floor of the residual after converging.
      if (d <= tol_ * step_scale || (d <= 1e-9 * step_scale && d >= 0.5 * previous)) {
        finish_jm_step(q_next, E);
        return true;
      }
      previous = d;
      r = residual(q_next);
    }
    return false;
  }

  // Time (Nair, Ober-Blöbaum & Marsden 2009 eq. (11)) and momentum D2 A_d(q_k, q_{k+1}) of a converged JM step.
  void finish_jm_step(const Vec& q_next, double E) {
    Vec gradW;
    const double W = midpoint_W(q_, q_next, E, gradW);
    const Vec D = q_next - q_;
    const Vec MD = mass_.cwiseProduct(D);
    const double L = std::sqrt(D.dot(MD));
    last_dt_ = L / W;
    p_ = 0.5 * L * gradW + (W / L) * MD;
    t_ += last_dt_;
    V_prev_ = V_;
    V_ = evaluate(q_next, grad_);
    ++work_.steps;
  }

  // Leaving JM: q0 = qm1, q1 = q_; h0 = Δt of the last JM step. Returns the new VI step h and
  // sets (q_, p_, t_) to the first VI point q2.
  double leave_jm(const Vec& q0, double E) {
    const double h0 = last_dt_;
    const Vec P = mass_.cwiseProduct(q_ - q0) / h0 - 0.5 * h0 * grad_;  // D2 L_d(q0, q1; h0)
    const Vec q1 = q_, grad1 = grad_;
    const double V1 = V_;
    Vec q2, g2;
    double V2 = 0;
    auto energy_gap = [&](double h) {  // E_d(q1, q2(h); h) − E
      const Vec v = minv_.cwiseProduct(P - 0.5 * h * grad1);
      q2 = q1 + h * v;
      V2 = evaluate(q2, g2);
      return 0.5 * v.dot(mass_.cwiseProduct(v)) + 0.5 * (V1 + V2) - E;
    };
    double a = h_, b = h0;
    if (a == b) b = 0.5 * a;
    double fa = energy_gap(a), fb = energy_gap(b);
    for (int it = 0; it < 50 && std::abs(fb) > 1e-15 * std::max(1.0, std::abs(E)); ++it) {
      if (fb == fa) break;
      const double c = b - fb * (b - a) / (fb - fa);  // secant
      a = b;
      fa = fb;
      b = c > 0 ? c : 0.5 * a;
      fb = energy_gap(b);
    }
    if (!(std::abs(fb) <= 1e-10 * std::max(1.0, std::abs(E))) || !(b > 0)) {
      std::ostringstream msg;
      msg << "jm-hybrid: no variational step matches the JM energy when leaving the JM phase at "
          << "t ≈ " << t_ << " (|E_d − E| = " << std::abs(fb) << ")";
      throw IntegrationError(msg.str(), t_);
    }
    energy_gap(b);  // q2, V2, g2 at the root
    const double h = b;
    q_ = q2;
    V_prev_ = V1;
    V_ = V2;
    grad_ = g2;
    p_ = mass_.cwiseProduct(q2 - q1) / h - 0.5 * h * g2;  // D2 L_d(q1, q2; h)
    t_ += h;
    ++work_.steps;
    record(kVI, -1, h);
    return h;
  }

  std::vector<Eigen::Index> free_indices(int c) const {
    std::vector<Eigen::Index> out;
    for (std::size_t i = 0; i < n_; ++i)
      if (static_cast<int>(i) != c) out.push_back(static_cast<Eigen::Index>(i));
    return out;
  }

  void hermite(double t0, const Vec& q0, const Vec& p0, double t1, const Vec& q1, const Vec& p1,
               double tau, Vec& q, Vec& p) const {
    const double dt = t1 - t0, s = (tau - t0) / dt;
    const Vec v0 = minv_.cwiseProduct(p0), v1 = minv_.cwiseProduct(p1);
    const double h00 = 2 * s * s * s - 3 * s * s + 1, h10 = s * s * s - 2 * s * s + s,
                 h01 = -2 * s * s * s + 3 * s * s, h11 = s * s * s - s * s;
    q = h00 * q0 + h10 * dt * v0 + h01 * q1 + h11 * dt * v1;
    const double d00 = 6 * s * s - 6 * s, d10 = 3 * s * s - 4 * s + 1, d01 = -6 * s * s + 6 * s,
                 d11 = 3 * s * s - 2 * s;
    const Vec v = (d00 * q0 + d01 * q1) / dt + d10 * v0 + d11 * v1;
    p = mass_.cwiseProduct(v);
  }

  void record(Phase phase, int c, double dt) {
    if (!record_) return;
    steps_.push_back(t_);
    steps_.push_back(dt);
    steps_.push_back(phase);
    steps_.push_back(c);
    steps_.insert(steps_.end(), q_.data(), q_.data() + q_.size());
  }

  const noether::System system_;
  noether::PotentialEvaluator evaluate_;
  double h_ = 0, theta_ = 0, Kc_ = 0, tol_ = 0, ratio_ = 1.2;
  int max_iter_ = 25;
  bool record_ = false;
  std::size_t n_ = 0;
  Vec mass_, minv_;
  noether::State state_;
  noether::Forces forces_;
  double t_ = 0, V_ = 0, V_prev_ = 0, last_dt_ = 0;
  Vec q_, p_, grad_;
  // The state machine between steps: phase, the VI step, the JM energy and parameter
  // coordinate, the point before the current one (the JM map is two-step), and the start of
  // the last step (for interpolation).
  Phase phase_ = kVI;
  double h_now_ = 0, E_ = 0, sign_ = 1, t_prev_ = 0;
  int c_ = 0;
  Vec qm1_, q_prev_, p_prev_;
  std::vector<double> steps_;
};

const noether::ParamDoc params[] = {
    {"step", "number", nullptr, "h, the step of the variational (Störmer–Verlet) phase"},
    {"Kc", "number", nullptr, "critical kinetic energy: Jacobi–Maupertuis above, variational below"},
    {"theta", "number", "(step)", "θ, the increment of the parameter coordinate per JM step"},
    {"newton_tolerance", "number", "1e-12", "JM Newton: stop when ‖Δq‖ ≤ tolerance × step length"},
    {"newton_max_iterations", "integer", "25", "JM Newton iterations before giving up"},
    {"rechoose_ratio", "number", "1.2",
     "re-choose the parameter coordinate when another |Δq_j| exceeds this × |Δq_c|"},
    {"record_steps", "bool", "false",
     "write every step's t, Δt, phase, parameter coordinate and q to /integrator/steps"},
};

std::unique_ptr<noether::Integrator> make(const noether::System& system,
                                          std::shared_ptr<const noether::Potential> potential,
                                          const Params& p) {
  return std::make_unique<JmHybrid>(system, std::move(potential), p);
}

}  // namespace

NOETHER_PLUGIN_DESCRIPTOR = {
    NOETHER_PLUGIN_API_VERSION,
    noether::PluginKind::Integrator,
    "jm-hybrid",
    "hybrid variational / Jacobi–Maupertuis integrator for point masses (switches at Kc)",
    params,
    std::size(params),
    nullptr,
    &make};
