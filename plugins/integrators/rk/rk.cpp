// rk: classical explicit Runge–Kutta baselines on the continuous equations (docs/equations.md §3), from
// Boost.Odeint: RK4 with a fixed step, Dormand–Prince 5(4) and Fehlberg 7(8) with error
// control. Like the seed's Runge–Kutta they integrate R as nine numbers and drift off SO(3);
// `renormalize: true` projects every R back onto SO(3) after each accepted step (opt-in,
// never silent: the output records it in /parameters).
#include <noether/continuous_equations.hpp>
#include <noether/error.hpp>
#include <noether/plugin.hpp>

#include <boost/numeric/odeint/stepper/controlled_runge_kutta.hpp>
#include <boost/numeric/odeint/stepper/dense_output_runge_kutta.hpp>
#include <boost/numeric/odeint/stepper/generation.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta4.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_dopri5.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_fehlberg78.hpp>

#include <cmath>
#include <sstream>

namespace {

namespace odeint = boost::numeric::odeint;
using Vector = std::vector<double>;
using noether::IntegrationError;
using noether::Params;
using noether::SceneError;

class Rk final : public noether::Integrator {
 public:
  Rk(const noether::System& system, std::shared_ptr<const noether::Potential> potential,
     const Params& p)
      : equations_(noether::make_continuous_equations(
            system, std::move(potential), p.get("frame", std::string("inertial")),
            p.get("form", std::string("hamiltonian")))) {
    method_ = p.get("method", std::string("dopri5"));
    if (method_ != "rk4" && method_ != "dopri5" && method_ != "rkf78")
      throw SceneError(p.at("method").here() + "rk: method must be rk4, dopri5 or rkf78, not '" +
                       method_ + "'");
    if (method_ == "rk4" && !p.has("step"))
      throw SceneError(p.here() + "rk: method rk4 needs a fixed 'step'");
    step_ = p.get("step", 0.0);
    rtol_ = p.get("rtol", 1e-8);
    atol_ = p.get("atol", 1e-10);
    renormalize_ = p.get("renormalize", false);
    max_steps_ = p.get("max_steps", 10000000L);
    if (step_ < 0 || rtol_ <= 0 || atol_ < 0 || max_steps_ < 1)
      throw SceneError(p.here() + "rk: step, rtol, max_steps must be positive, atol non-negative");
  }

  void integrate(noether::State& state, const noether::OutputSchedule& schedule,
                 noether::Observer& observer) override {
    Vector y(equations_->size());
    equations_->pack(state, y.data());
    auto rhs = [this](const Vector& x, Vector& dxdt, double t) {
      equations_->rhs(t, x.data(), dxdt.data());
    };
    noether::Forces forces;
    forces.resize(equations_->system());
    double t = state.t;
    auto emit = [&] {  // diagnostics need the forces at the output state (not counted as work)
      equations_->unpack(y.data(), t, state);
      equations_->potential().evaluate(state, forces);
      observer.observe(state, forces);
    };
    emit();
    try {
      if (method_ == "rk4")
        fixed(rhs, y, t, schedule, emit);
      else if (method_ == "dopri5" && !renormalize_)
        dense(odeint::make_dense_output(atol_, rtol_, odeint::runge_kutta_dopri5<Vector>()), rhs,
              y, t, schedule, emit);
      else if (method_ == "dopri5")
        adaptive(odeint::make_controlled(atol_, rtol_, odeint::runge_kutta_dopri5<Vector>()), rhs,
                 y, t, schedule, emit);
      else
        adaptive(odeint::make_controlled(atol_, rtol_, odeint::runge_kutta_fehlberg78<Vector>()),
                 rhs, y, t, schedule, emit);
    } catch (const IntegrationError&) {
      equations_->unpack(y.data(), t, state);
      work_.potential_evaluations = equations_->evaluations();
      throw;
    }
    work_.potential_evaluations = equations_->evaluations();
  }

 private:
  template <class Rhs, class Emit>
  void fixed(Rhs& rhs, Vector& y, double& t, const noether::OutputSchedule& s, Emit& emit) {
    const double t0 = t;
    const std::int64_t n = noether::whole_steps(s.t_end - t0, step_, "run.t_end − t0", "rk");
    const std::int64_t stride = noether::whole_steps(s.output_every, step_, "run.output_every", "rk");
    odeint::runge_kutta4<Vector> rk4;
    for (std::int64_t k = 0; k < n; ++k) {
      rk4.do_step(rhs, y, t, step_);
      t = t0 + static_cast<double>(k + 1) * step_;
      ++work_.steps;
      accepted(y, t);
      if ((k + 1) % stride == 0 || k + 1 == n) emit();
    }
  }

  // Dormand–Prince with its own (4th-order) dense output: steps are chosen by the error
  // control alone, output frames are interpolated. Odeint retries rejected steps internally,
  // so rejected steps are not counted here (reported as −1, unknown).
  template <class Dense, class Rhs, class Emit>
  void dense(Dense stepper, Rhs& rhs, Vector& y, double& t, const noether::OutputSchedule& s,
             Emit& emit) {
    const auto times = noether::output_times(t, s.t_end, s.output_every);
    stepper.initialize(y, t, step_ > 0 ? step_ : s.output_every / 100.0);
    work_.rejected_steps = -1;
    for (std::size_t k = 1; k < times.size(); ++k) {
      while (stepper.current_time() < times[k]) {
        stepper.do_step(rhs);
        ++work_.steps;
        const Vector& current = stepper.current_state();
        for (double v : current)
          if (!std::isfinite(v)) fail("the solution became non-finite", stepper.current_time());
        if (stepper.current_time_step() < 1e-14 * std::max(1.0, std::abs(stepper.current_time())))
          fail("the step size fell below 1e-14 |t| (the error control cannot be met)",
               stepper.current_time());
        if (work_.steps > max_steps_)
          fail("more than max_steps = " + std::to_string(max_steps_) + " steps",
               stepper.current_time());
      }
      t = times[k];
      stepper.calc_state(t, y);
      emit();
    }
  }

  // Controlled steps chosen by the error control alone (rkf78, and dopri5 with renormalize:
  // Odeint has no dense output for Fehlberg 7(8)). An output time inside an accepted step is
  // reached by one extra step of the same method from the step's start, on a copy, so outputs
  // carry the method's own accuracy; those evaluations count as work.
  template <class Controlled, class Rhs, class Emit>
  void adaptive(Controlled stepper, Rhs& rhs, Vector& y, double& t,
                const noether::OutputSchedule& s, Emit& emit) {
    const auto times = noether::output_times(t, s.t_end, s.output_every);
    double dt = step_ > 0 ? step_ : s.output_every / 100.0;
    using OutputStepper = typename Controlled::stepper_type;
    Vector y_prev = y, y_out = y;
    std::size_t next = 1;
    while (next < times.size()) {
      const double t_prev = t;
      y_prev = y;
      // Never step past t_end.
      double h = std::min(dt, times.back() - t);
      const double h_tried = h;
      if (stepper.try_step(rhs, y, t, h) != odeint::success) {
        ++work_.rejected_steps;
        dt = h;
        if (h < 1e-14 * std::max(1.0, std::abs(t)) || h >= h_tried)
          fail("the step size fell below 1e-14 |t| (the error control cannot be met)", t);
      } else {
        ++work_.steps;
        dt = h;  // the controller's proposal for the next step
        if (times.back() - t < 1e-12 * std::max(1.0, std::abs(t))) t = times.back();
        if (accepted(y, t)) {
          // The state was projected: a first-same-as-last stepper must not reuse its cached
          // derivative of the unprojected state (one more evaluation per step).
          if constexpr (requires { stepper.reset(); }) stepper.reset();
        }
        const double t_now = t;
        while (next < times.size() && times[next] <= t_now) {
          if (times[next] == t_now) {
            emit();
          } else {  // an output inside the step: one step of the method from its start
            y_out = y_prev;
            OutputStepper fresh;  // no derivative cached from another state
            fresh.do_step(rhs, y_out, t_prev, times[next] - t_prev);
            std::swap(y, y_out);
            t = times[next];
            emit();
            std::swap(y, y_out);
            t = t_now;
          }
          ++next;
        }
      }
      if (work_.steps + work_.rejected_steps > max_steps_)
        fail("more than max_steps = " + std::to_string(max_steps_) + " steps", t);
    }
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

  [[noreturn]] void fail(const std::string& why, double t) const {
    std::ostringstream msg;
    msg << "rk (" << method_ << ", rtol " << rtol_ << ", atol " << atol_ << "): " << why
        << " at t = " << t << "; loosen the tolerances, raise max_steps, or check the scene";
    throw IntegrationError(msg.str(), t);
  }

  std::unique_ptr<noether::ContinuousEquations> equations_;
  std::string method_;
  double step_ = 0, rtol_ = 0, atol_ = 0;
  bool renormalize_ = false;
  long max_steps_ = 0;
};

const noether::ParamDoc params[] = {
    {"method", "string", "dopri5",
     "rk4 (classic, fixed step), dopri5 (Dormand–Prince 5(4)), rkf78 (Fehlberg 7(8))"},
    {"step", "number", "output_every/100",
     "rk4: the fixed step (required); adaptive methods: the first trial step"},
    {"rtol", "number", "1e-8", "relative tolerance (adaptive methods)"},
    {"atol", "number", "1e-10", "absolute tolerance (adaptive methods)"},
    {"renormalize", "bool", "false",
     "project every R onto SO(3) after each step (opt-in; the drift is reported otherwise)"},
    {"max_steps", "integer", "10000000", "steps (accepted + rejected) before giving up"},
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
