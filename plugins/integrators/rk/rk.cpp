// rk: classical explicit Runge–Kutta baselines on the continuous equations (docs/equations.md §3), from
// Boost.Odeint: RK4 with a fixed step, Dormand–Prince 5(4) and Fehlberg 7(8) with error
// control. Like Lee et al.'s Runge–Kutta they integrate R as nine numbers and drift off SO(3);
// `renormalize: true` projects every R back onto SO(3) after each accepted step (opt-in,
// never silent: the output records it in /parameters). With a tangent (run.stm), the
// variational equations (docs/equations.md eq. 21.10) are integrated beside the state by the
// same method; the adaptive methods control the error of the state only, unless
// stm_error_control asks for both (a differenced force Jacobian's noise, ~1e-10, then caps
// what rtol can be met: steps collapse below it). Forces beyond the potential (docs/equations.md
// §33) join the inertial Hamiltonian equations, their balance (33.3) integrated beside the state
// by the same method, outside the error control.
#include <noether/continuous_equations.hpp>
#include <noether/error.hpp>
#include <noether/plugin.hpp>
#include <noether/step_clock.hpp>
#include <noether/variational_equations.hpp>

#include <boost/numeric/odeint/stepper/controlled_runge_kutta.hpp>
#include <boost/numeric/odeint/stepper/dense_output_runge_kutta.hpp>
#include <boost/numeric/odeint/stepper/generation.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta4.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_dopri5.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_fehlberg78.hpp>

#include <cmath>
#include <limits>
#include <functional>
#include <optional>
#include <sstream>

namespace {

namespace odeint = boost::numeric::odeint;
using Vector = std::vector<double>;

// Odeint's default error checker (max over components of |err| / (atol + rtol (|x| + |dt| |ẋ|)))
// restricted to the first *controlled components: the state's, not the tangent's carried after
// it (all of them when no tangent is carried, or with stm_error_control). The same arithmetic
// as odeint's, so that runs without a tangent take the same steps as before.
struct StateErrorChecker {
  using value_type = double;
  using algebra_type = odeint::range_algebra;
  using operations_type = odeint::default_operations;
  double eps_abs = 1e-6, eps_rel = 1e-6;
  const std::size_t* controlled = nullptr;
  template <class State, class Deriv, class Err, class Time>
  double error(algebra_type&, const State& x_old, const Deriv& dxdt_old, Err& x_err, Time dt) const {
    double e = 0.0;
    for (std::size_t i = 0; i < *controlled; ++i)
      e = std::max(e, std::abs(x_err[i]) /
                          (eps_abs + eps_rel * (1.0 * std::abs(x_old[i]) + (1.0 * std::abs(dt)) * std::abs(dxdt_old[i]))));
    return e;
  }
};
using Dopri5 = odeint::controlled_runge_kutta<odeint::runge_kutta_dopri5<Vector>, StateErrorChecker>;
using Rkf78 = odeint::controlled_runge_kutta<odeint::runge_kutta_fehlberg78<Vector>, StateErrorChecker>;
using Dense = odeint::dense_output_runge_kutta<Dopri5>;
using noether::IntegrationError;
using noether::Params;
using noether::SceneError;

class Rk final : public noether::Integrator {
 public:
  Rk(const noether::System& system, std::shared_ptr<const noether::Potential> potential,
     const Params& p)
      : equations_(noether::make_continuous_equations(
            system, std::move(potential), p.at("frame").as_string(),
            p.at("form").as_string())) {
    form_ = p.at("frame").as_string() + " " + p.at("form").as_string();
    method_ = p.at("method").as_string();
    if (method_ != "rk4" && method_ != "dopri5" && method_ != "rkf78")
      throw SceneError(p.at("method").here() + "rk: method must be rk4, dopri5 or rkf78, not '" +
                       method_ + "'");
    if (method_ == "rk4" && !p.has("step"))
      throw SceneError(p.here() + "rk: method rk4 needs a fixed 'step'");
    step_ = p.get("step", 0.0);
    rtol_ = p.at("rtol").as_double();
    atol_ = p.at("atol").as_double();
    renormalize_ = p.at("renormalize").as_bool();
    max_steps_ = p.at("max_steps").as_int();  // 0: no cap (a run is bounded by t_end, events, signals, run budgets)
    stm_error_control_ = p.at("stm_error_control").as_bool();
    dopri5_ = Dopri5(checker());
    rkf78_ = Rkf78(checker());
    if (step_ < 0 || rtol_ <= 0 || atol_ < 0 || max_steps_ < 0)
      throw SceneError(p.here() + "rk: step and rtol must be positive, atol and max_steps non-negative");
    // The tangent is the flow's, in the inertial coordinates (21.1), whatever variables carry the
    // state (the relative frame, the Lagrangian form): V' = A(z) V with z the stage's state made
    // inertial (ContinuousEquations::unpack).
    if (method_ != "rk4" && atol_ == 0.0)
      tangent_unavailable_ = "with atol: 0 the error of the state-transition matrix, whose entries start at 0, cannot be "
                             "controlled; give rk a positive atol";
  }

  std::string tangent_map_unavailable() const override { return tangent_unavailable_; }
  std::string add_forcing(std::shared_ptr<const noether::Forcing> forcing) override {
    if (form_ != "inertial hamiltonian")
      return "rk takes forces beyond the potential in its inertial Hamiltonian equations only: use frame: inertial, "
             "form: hamiltonian";
    forcing_.emplace(equations_->system(), std::move(forcing));
    return "";
  }
  // The parameters' terms (22.2) join the variational equations of the last columns, with the
  // forces' own derivative G^F when there are forces beyond the potential (33.9).
  std::string carry_parameters(std::shared_ptr<const noether::ParameterDerivatives> parameters) override {
    if (!tangent_map_unavailable().empty()) return tangent_map_unavailable();
    parameter_forces_.emplace(std::move(parameters));
    return "";
  }

  void start(const noether::State& state) override {
    if (state.tangent.size() > 0 && !tangent_map_unavailable().empty()) throw noether::Error(tangent_map_unavailable());
    if (forcing_) forcing_->check_balance(state, "rk");
    if (parameter_forces_ && !parameter_forces_->fits(state.tangent))
      throw noether::Error("rk: the tangent has fewer columns than the parameters it carries");
    tangent_rows_ = state.tangent.rows();
    tangent_columns_ = state.tangent.cols();
    balance_offset_ = equations_->size() + static_cast<std::size_t>(state.tangent.size());
    y_.resize(balance_offset_ + static_cast<std::size_t>(forcing_ ? state.force_balance.size() : 0));
    controlled_ = stm_error_control_ ? balance_offset_ : equations_->size();
    equations_->pack(state, y_.data());
    // y = (the equations' variables, then V column by column, then the forces' balance)
    std::copy(state.tangent.data(), state.tangent.data() + state.tangent.size(), y_.data() + equations_->size());
    if (forcing_) std::copy(state.force_balance.data(), state.force_balance.data() + state.force_balance.size(),
                            y_.data() + balance_offset_);
    y_prev_ = y_;
    t_ = t_prev_ = state.t;
    clock_.start(state.t, step_);
    dt_ = step_ > 0 ? step_ : 0.0;  // 0: first_trial() at the first step
    dense_.reset();
    dopri5_.reset();  // no derivative cached from another state
  }

  void step(double t_max) override {
    y_prev_ = y_;
    t_prev_ = t_;
    try {
      if (method_ == "rk4")
        fixed_step_to(t_max);
      else if (method_ == "dopri5" && !renormalize_)
        dense_step(t_max);
      else if (method_ == "dopri5")
        controlled_step(dopri5_, t_max);
      else
        controlled_step(rkf78_, t_max);
    } catch (const IntegrationError&) {
      y_ = y_prev_;  // stay at the last valid state
      t_ = t_prev_;
      dense_.reset();  // restart the steppers from y_ at the next step
      dopri5_.reset();
      work_.potential_evaluations = equations_->evaluations() + differenced_evaluations_;
      throw;
    }
    work_.potential_evaluations = equations_->evaluations() + differenced_evaluations_;
  }

  double time() const override { return t_; }
  double fixed_step() const override { return method_ == "rk4" ? step_ : 0.0; }
  int order() const override { return method_ == "rk4" ? 4 : method_ == "dopri5" ? 5 : 8; }
  // rk4's clock (step_clock.hpp): a run continued from a step's end steps through the
  // uninterrupted run's times to the bit. The adaptive methods keep nothing beyond the State.
  std::vector<double> checkpoint() const override {
    std::vector<double> out;
    if (method_ == "rk4") clock_.checkpoint(out);
    return out;
  }
  void restore(const noether::State& state, const std::vector<double>& data) override {
    start(state);
    if (data.empty()) return;  // a file written before the clock was kept: it restarts here
    if (method_ != "rk4" || data.size() != noether::StepClock::kCheckpointSize)
      throw noether::Error("rk: a checkpoint of " + std::to_string(data.size()) + " numbers, not " +
                           (method_ == "rk4" ? "rk4's clock (2)" : "none (" + method_ + " keeps none)"));
    clock_.restore(state.t, step_, data.data(), "rk");
  }

  void current(noether::State& state, noether::Forces& forces) override {
    unpack(y_, t_, state);
    equations_->forces(state, forces);  // for output; not counted as work
  }

  noether::PotentialEvaluator* potential_evaluator() override { return &equations_->evaluator(); }

  void current_state(noether::State& state) override { unpack(y_, t_, state); }

  // Dopri5: its own (4th-order) dense output. Rkf78 and dopri5 with renormalize: one step of
  // the same method from the step's start, on a copy, so outputs carry the method's own
  // accuracy (those evaluations count as work). rk4: none (the loop lands by a short step).
  bool interpolate(double t, noether::State& state) override {
    if (method_ == "rk4") return false;
    if (t == t_prev_) {
      unpack(y_prev_, t, state);
      return true;
    }
    y_out_ = y_prev_;
    if (method_ == "dopri5" && !renormalize_) {
      dense_->calc_state(t, y_out_);
    } else if (method_ == "dopri5") {
      odeint::runge_kutta_dopri5<Vector> fresh;  // no derivative cached from another state
      fresh.do_step(rhs_, y_out_, t_prev_, t - t_prev_);
    } else {
      odeint::runge_kutta_fehlberg78<Vector> fresh;
      fresh.do_step(rhs_, y_out_, t_prev_, t - t_prev_);
    }
    work_.potential_evaluations = equations_->evaluations() + differenced_evaluations_;
    unpack(y_out_, t, state);
    return true;
  }

 private:
  // rk4: a step of h, or a shorter one that ends at t_max.
  void fixed_step_to(double t_max) {
    const noether::ClockStep next = clock_.next(t_max);
    rk4_.do_step(rhs_, y_, t_, next.dt);
    ++work_.steps;
    accepted(y_, next.t_next);  // before the clock moves: a failure leaves it at the last valid state
    clock_.advance(next);
    t_ = clock_.time();
  }

  // Dormand–Prince with dense output: steps chosen by the error control alone, possibly past
  // t_max (outputs are interpolated). Odeint retries rejected steps internally, so they are
  // not counted here (reported as −1, unknown).
  void dense_step(double t_max) {
    if (!dense_) {
      dense_.emplace(Dopri5(checker()));
      dense_->initialize(y_, t_, dt_ > 0 ? dt_ : first_trial(t_max));
    }
    work_.rejected_steps = -1;
    dense_->do_step(rhs_);
    ++work_.steps;
    t_ = dense_->current_time();
    y_ = dense_->current_state();
    for (double v : y_)
      if (!std::isfinite(v)) fail("the solution became non-finite", t_);
    if (dense_->current_time_step() < 1e-14 * std::max(1.0, std::abs(t_)))
      fail("the step size fell below 1e-14 |t| (the error control cannot be met)", t_);
    if (max_steps_ > 0 && work_.steps > max_steps_) fail("more than max_steps = " + std::to_string(max_steps_) + " steps", t_);
  }

  // Controlled steps chosen by the error control, never past t_max.
  template <class Controlled>
  void controlled_step(Controlled& stepper, double t_max) {
    if (!(dt_ > 0)) dt_ = first_trial(t_max);
    for (;;) {
      double h = std::min(dt_, t_max - t_);
      const double h_tried = h;
      if (stepper.try_step(rhs_, y_, t_, h) == odeint::success) {
        ++work_.steps;
        dt_ = h;  // the controller's proposal for the next step
        if (t_max - t_ < 1e-12 * std::max(1.0, std::abs(t_))) t_ = t_max;
        if (accepted(y_, t_)) {
          // The state was projected: a first-same-as-last stepper must not reuse its cached
          // derivative of the unprojected state (one more evaluation per step).
          if constexpr (requires { stepper.reset(); }) stepper.reset();
        }
        break;
      }
      ++work_.rejected_steps;
      dt_ = h;
      if (h < 1e-14 * std::max(1.0, std::abs(t_)) || h >= h_tried)
        fail("the step size fell below 1e-14 |t| (the error control cannot be met)", t_);
      if (max_steps_ > 0 && work_.steps + work_.rejected_steps > max_steps_)
        fail("more than max_steps = " + std::to_string(max_steps_) + " steps", t_);
    }
    if (max_steps_ > 0 && work_.steps + work_.rejected_steps > max_steps_)
      fail("more than max_steps = " + std::to_string(max_steps_) + " steps", t_);
  }

  // Without a given `step`: the starting step of Hairer, Nørsett & Wanner (1993, §II.4),
  // h0 = 0.01 ‖y‖/‖y'‖ in the norm weighted by atol + rtol |y| (one evaluation), at most the
  // time to t_max.
  double first_trial(double t_max) {
    Vector f(y_.size());
    rhs_(y_, f, t_);
    double d0 = 0, d1 = 0;
    for (std::size_t i = 0; i < y_.size(); ++i) {
      const double sc = atol_ + rtol_ * std::abs(y_[i]);
      d0 += (y_[i] / sc) * (y_[i] / sc);
      d1 += (f[i] / sc) * (f[i] / sc);
    }
    const double h0 = (d0 < 1e-10 || d1 < 1e-10) ? 1e-6 * (t_max - t_) : 0.01 * std::sqrt(d0 / d1);
    return std::min(h0, t_max - t_);
  }

  // Checks an accepted state; projects R onto SO(3) when asked. Returns whether y changed.
  bool accepted(Vector& y, double t) {
    for (double v : y)
      if (!std::isfinite(v)) fail("the solution became non-finite", t);
    if (!renormalize_) return false;
    for (const std::size_t offset : equations_->rotation_offsets()) {
      Eigen::Map<noether::Mat3> R(y.data() + offset);
      R = noether::nearest_rotation(R);
    }
    return true;
  }

  StateErrorChecker checker() const { return StateErrorChecker{atol_, rtol_, &controlled_}; }

  // The state of y (and its tangent, when carried).
  void unpack(const Vector& y, double t, noether::State& state) const {
    equations_->unpack(y.data(), t, state);
    if (tangent_columns_ > 0)
      state.tangent = Eigen::Map<const Eigen::MatrixXd>(y.data() + equations_->size(), tangent_rows_, tangent_columns_);
    else
      state.tangent.resize(0, 0);
    if (forcing_)
      state.force_balance = Eigen::Map<const Eigen::MatrixXd>(y.data() + balance_offset_, noether::kBalanceRows,
                                                              static_cast<Eigen::Index>(forcing_->size()));
  }

  // The forces beyond the potential at the stage y: added to γ̇ and Π̇ of the inertial
  // Hamiltonian equations (29)–(32), each one's balance rate (33.3) into its components.
  void add_forces(const Vector& y, Vector& dydt, double t) {
    equations_->unpack(y.data(), t, stage_);
    forcing_->add_to_inertial_hamiltonian(stage_, dydt.data(), dydt.data() + balance_offset_);
  }

  // y' = F(t, y), and V' = A V beside it when a tangent is carried (21.10), with the force
  // Jacobian at the stage's state (differenced evaluations counted as work).
  void rhs(const Vector& y, Vector& dydt, double t) {
    equations_->rhs(t, y.data(), dydt.data());
    if (forcing_) add_forces(y, dydt, t);
    if (tangent_columns_ == 0) return;
    equations_->unpack(y.data(), t, stage_);
    bool analytic = true;
    const Eigen::MatrixXd K = equations_->evaluator().force_jacobian(stage_, &analytic);
    if (!analytic) differenced_evaluations_ += 2 * K.rows();
    const auto s = static_cast<std::ptrdiff_t>(equations_->size());
    Eigen::Map<Eigen::MatrixXd> dV(dydt.data() + s, tangent_rows_, tangent_columns_);
    const Eigen::Map<const Eigen::MatrixXd> V(y.data() + s, tangent_rows_, tangent_columns_);
    noether::variational_rhs(equations_->system(), stage_, K, V, dV);
    if (forcing_) {  // + B K^F V (33.8)
      forcing_->jacobian(stage_, forcing_jacobian_);
      noether::add_forcing_tangent(equations_->system(), forcing_jacobian_, 1.0, V, dV);
    }
    if (parameter_forces_) {  // ∂z/∂p columns: + the parameters' terms (22.2)
      const auto P = static_cast<Eigen::Index>(parameter_forces_->size());
      const Eigen::MatrixXd& G = parameter_forces_->with_forcing(stage_);  // G + G^F (33.9)
      differenced_evaluations_ += parameter_forces_->evaluations_per_call();
      noether::add_parameter_rhs(equations_->system(), stage_, parameter_forces_->derivatives(), G, dV.rightCols(P));
    }
  }

  [[noreturn]] void fail(const std::string& why, double t) const {
    std::ostringstream msg;
    msg << "rk (" << method_ << ", rtol " << rtol_ << ", atol " << atol_ << "): " << why
        << " at t = " << t << "; loosen the tolerances, raise max_steps, or check the scene";
    throw IntegrationError(msg.str(), t);
  }

  std::unique_ptr<noether::ContinuousEquations> equations_;
  std::function<void(const Vector&, Vector&, double)> rhs_ = [this](const Vector& x, Vector& dxdt,
                                                                       double t) { rhs(x, dxdt, t); };
  odeint::runge_kutta4<Vector> rk4_;
  Dopri5 dopri5_;
  Rkf78 rkf78_;
  std::optional<Dense> dense_;
  Vector y_, y_prev_, y_out_;
  double t_ = 0, t_prev_ = 0, dt_ = 0;
  noether::StepClock clock_;  // rk4: t = t0 + k h between restarts
  std::string method_;
  double step_ = 0, rtol_ = 0, atol_ = 0;
  bool renormalize_ = false;
  long max_steps_ = 0;
  // The tangent (run.stm): its shape (0 columns: none carried), the state at a stage, and the
  // evaluations made to difference a force Jacobian.
  Eigen::Index tangent_rows_ = 0, tangent_columns_ = 0;
  bool stm_error_control_ = false;
  std::size_t controlled_ = 0;  // the components of y under error control (StateErrorChecker)
  noether::State stage_;
  std::int64_t differenced_evaluations_ = 0;
  std::string tangent_unavailable_;
  std::optional<noether::ParameterForces> parameter_forces_;  // sensitivities to parameters of the dynamics
  std::string form_;  // "inertial hamiltonian", …
  // Forces beyond the potential (none: the potential alone) and where their balance starts in y.
  std::optional<noether::ForcingEvaluator> forcing_;
  Eigen::MatrixXd forcing_jacobian_;  // K^F at a stage, when a tangent is carried (33.8)
  std::size_t balance_offset_ = 0;
};

const noether::ParamDoc params[] = {
    {"method", "string", "dopri5",
     "rk4 (classic, fixed step), dopri5 (Dormand–Prince 5(4)), rkf78 (Fehlberg 7(8))"},
    {"step", "number", "(automatic)",
     "rk4: the fixed step (required); adaptive methods: the first trial step (default: "
     "Hairer–Nørsett–Wanner's starting step, 0.01 ‖y‖/‖y'‖)"},
    {"rtol", "number", "1e-8", "relative tolerance (adaptive methods)"},
    {"atol", "number", "1e-10", "absolute tolerance (adaptive methods)"},
    {"renormalize", "bool", "false",
     "project every R onto SO(3) after each step (opt-in; the drift is reported otherwise)"},
    {"max_steps", "integer", "0", "steps (accepted + rejected) before giving up; 0: no cap (bound long runs with --max-wall-time)"},
    {"stm_error_control", "bool", "false",
     "with run.stm: control the error of the state-transition matrix too, not only of the state (smaller steps; "
     "with a differenced force Jacobian, rtol below ~1e-10 then cannot be met)"},
    {"frame", "string", "inertial", "inertial (29)–(32), or relative: two rigid bodies only"},
    {"form", "string", "hamiltonian", "hamiltonian (momenta) or lagrangian (velocities, (25)–(28), (55)–(62))"},
};

std::unique_ptr<noether::Integrator> make(const noether::System& system,
                                          std::shared_ptr<const noether::Potential> potential,
                                          const Params& p) {
  return std::make_unique<Rk>(system, std::move(potential), p);
}

}  // namespace

NOETHER_PLUGIN_DESCRIPTOR = {
    NOETHER_PLUGIN_API_VERSION,
    noether::PluginKind::Integrator,
    "rk",
    "explicit Runge–Kutta baselines (Odeint): rk4, dopri5, rkf78; R drifts off SO(3)",
    params,
    std::size(params),
    nullptr,
    &make};
