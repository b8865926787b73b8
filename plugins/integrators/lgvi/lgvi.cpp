// lgvi: the Lie group variational integrator of the full body problem (Lee, Leok & McClamroch 2007; docs/equations.md §4–5).
// Four discrete forms — inertial or relative frame, Hamiltonian or Lagrangian — chosen by the
// scene (`frame`, `form`); orders 4 and 6 by symmetric compositions (compositions.hpp) of the one-step
// (Hamiltonian) forms. Every form is symmetric and symplectic, conserves total linear and
// angular momentum to round-off and keeps every R on SO(3) to round-off.
#include "compositions.hpp"
#include "discrete_flow.hpp"

#include <noether/error.hpp>
#include <noether/plugin.hpp>
#include <noether/step_clock.hpp>

#include <cmath>
#include <limits>

namespace {

using noether::Params;
using noether::SceneError;

class Lgvi final : public noether::Integrator {
 public:
  Lgvi(const noether::System& system, std::shared_ptr<const noether::Potential> potential,
       const Params& params)
      : evaluator_(std::move(potential)) {
    h_ = params.at("step").as_double();
    if (!(h_ > 0.0)) throw SceneError(params.at("step").here() + "lgvi: 'step' must be positive");
    lgvi::Settings settings;
    settings.newton.tolerance = params.at("newton_tolerance").as_double();
    settings.newton.max_iterations = static_cast<int>(params.at("newton_max_iterations").as_int());
    if (settings.newton.tolerance <= 0.0 || settings.newton.max_iterations < 1)
      throw SceneError(params.here() + "lgvi: newton_tolerance and newton_max_iterations must be positive");
    const std::string frame = params.at("frame").as_string();
    const std::string form = params.at("form").as_string();
    order_ = static_cast<int>(params.at("order").as_int());
    const std::string composition = params.get("composition", std::string(order_ == 6 ? "kahan-li" : "yoshida"));
    if (frame != "inertial" && frame != "relative")
      throw SceneError(params.at("frame").here() + "lgvi: frame must be inertial or relative, not '" + frame + "'");
    if (form != "hamiltonian" && form != "lagrangian")
      throw SceneError(params.at("form").here() + "lgvi: form must be hamiltonian or lagrangian, not '" + form + "'");
    if (order_ != 2 && order_ != 4 && order_ != 6)
      throw SceneError(params.at("order").here() + "lgvi: order must be 2, 4 or 6");
    if (order_ > 2 && form == "lagrangian")
      throw SceneError(params.at("order").here() +
                       "lgvi: orders 4 and 6 (compositions) need a one-step map: use form: hamiltonian");
    if (order_ > 2) {
      gamma_ = lgvi::composition_coefficients(order_, composition);
      if (gamma_.empty())
        throw SceneError(params.at("composition").here() + "lgvi: no composition '" + composition + "' of order " +
                         std::to_string(order_) + "; " + lgvi::compositions_of_order(order_));
    } else if (params.has("composition")) {
      throw SceneError(params.at("composition").here() + "lgvi: 'composition' needs order 4 or 6");
    }
    if (frame == "inertial")
      flow_ = form == "hamiltonian" ? lgvi::make_inertial_hamiltonian(system, evaluator_, settings)
                                    : lgvi::make_inertial_lagrangian(system, evaluator_, settings);
    else
      flow_ = form == "hamiltonian" ? lgvi::make_relative_hamiltonian(system, evaluator_, settings)
                                    : lgvi::make_relative_lagrangian(system, evaluator_, settings);
    form_ = frame + " " + form;
  }

  // Forces beyond the potential (docs/equations.md §33): every form takes them — the inertial
  // forms' kicks (33.1)–(33.2), (33.10), the relative forms' in the reduced momenta (33.11) — and
  // so do the Hamiltonian form's compositions (the forced map is symmetric: they keep their order).
  std::string add_forcing(std::shared_ptr<const noether::Forcing> forcing) override {
    if (!flow_->add_forcing(std::move(forcing))) return "the " + form_ + " form of the lgvi takes no forces beyond the potential";
    return "";
  }

  noether::PotentialEvaluator* potential_evaluator() override { return &evaluator_; }

  void start(const noether::State& state) override {
    flow_->start(state);
    clock_.start(state.t, h_);
  }

  // One step of size h, or a shorter one that ends at t_max (the loop's landing on an event).
  void step(double t_max) override {
    const noether::ClockStep next = clock_.next(t_max);
    advance(next.dt, next.t_next);
    clock_.advance(next);
  }

  double time() const override { return clock_.time(); }
  // The flow's variables, then the clock (step_clock.hpp): a run continued from a step's end steps
  // through the uninterrupted run's times to the bit.
  std::vector<double> checkpoint() const override {
    std::vector<double> out = flow_->checkpoint();
    clock_.checkpoint(out);
    return out;
  }
  void restore(const noether::State& state, const std::vector<double>& data) override {
    if (data.empty()) return start(state);
    const std::size_t flow = flow_->checkpoint_size(), clock = noether::StepClock::kCheckpointSize;
    if (data.size() != flow && data.size() != flow + clock)
      throw noether::Error("lgvi: a checkpoint of " + std::to_string(data.size()) + " numbers, not the " +
                           std::to_string(flow + clock) + " of the " + form_ + " form");
    if (flow == 0)
      flow_->start(state);
    else
      flow_->restore(state, std::vector<double>(data.begin(), data.begin() + static_cast<std::ptrdiff_t>(flow)));
    clock_.start(state.t, h_);  // a file written before the clock was kept: it restarts here
    if (data.size() == flow + clock) clock_.restore(state.t, h_, data.data() + flow, "lgvi");
  }
  double fixed_step() const override { return h_; }
  int order() const override { return order_; }
  // Every form carries the tangent map of its steps (the relative forms: the inertial map's, §21);
  // with forces, the kicks' derivatives (33.6)–(33.7) join it, and for parameters the forces' own
  // dependence on them (33.9).
  std::string tangent_map_unavailable() const override { return ""; }
  std::string carry_parameters(std::shared_ptr<const noether::ParameterDerivatives> parameters) override {
    if (!flow_->carry_parameters(std::move(parameters))) return "this form of the lgvi has no tangent map";
    return "";
  }

  void current(noether::State& state, noether::Forces& forces) override {
    flow_->current(state, forces);
    state.t = clock_.time();
  }
  // The state alone, at every step where events are watched (a kept Forces for a flow that
  // computes them anyway, so that the step loop allocates nothing).
  void current_state(noether::State& state) override {
    flow_->current_state(state, scratch_forces_);
    state.t = clock_.time();
  }

 private:
  // One step of size dt to t_next: the base map, or its symmetric composition γ_1 dt, …, γ_s dt
  // (docs/equations.md §4, compositions.hpp), of order 4 or 6, its stages ending at t + (γ_1 + …
  // + γ_i) dt and the last at t_next. A failure inside the composition restarts from the step's
  // start, so the integrator stays at the last valid state.
  void advance(double dt, double t_next) {
    if (gamma_.empty()) {
      flow_->advance(dt, t_next);
    } else {
      flow_->current(before_, scratch_forces_);
      try {
        double sum = 0.0;
        for (std::size_t i = 0; i < gamma_.size(); ++i) {
          sum += gamma_[i];
          flow_->advance(gamma_[i] * dt, i + 1 == gamma_.size() ? t_next : clock_.time() + sum * dt);
        }
      } catch (const noether::Error&) {
        flow_->start(before_);
        collect();
        throw;
      }
    }
    collect();
  }
  void collect() {
    work_ = flow_->work;
    if (!gamma_.empty()) work_.steps /= static_cast<std::int64_t>(gamma_.size());  // steps of size h
  }

  noether::PotentialEvaluator evaluator_;  // declared before flow_, which keeps a reference
  std::unique_ptr<lgvi::DiscreteFlow> flow_;
  double h_ = 0.0;
  int order_ = 2;
  std::vector<double> gamma_;  // composition coefficients (empty: the base map, order 2)
  std::string form_;           // "inertial hamiltonian", …
  noether::StepClock clock_;  // t = t0 + k h between restarts
  noether::State before_;
  noether::Forces scratch_forces_;  // what current_state() and a composition's start drop
};

const noether::ParamDoc params[] = {
    {"step", "number", nullptr,
     "time step h (fixed); run.t_end and run.output_every must be whole multiples of it"},
    {"frame", "string", "inertial",
     "inertial (93)–(97) / (78)–(80), or relative (118)–(127) / (112)–(117): two rigid bodies only"},
    {"form", "string", "hamiltonian", "hamiltonian (one-step) or lagrangian (two-step)"},
    {"order", "integer", "2", "2, or 4 or 6 by a symmetric composition of the order-2 map (hamiltonian form)"},
    {"composition", "string", "(yoshida at order 4, kahan-li at order 6)",
     "order 4: yoshida (3 stages), suzuki or mclachlan (5 stages); order 6: yoshida (7), kahan-li (9)"},
    {"newton_tolerance", "number", "1e-15",
     "relative tolerance ‖Δf‖/‖f‖ of the Newton solve for F_k (128)"},
    {"newton_max_iterations", "integer", "30",
     "Newton iterations before the step is declared too large for the spin"},
};

std::unique_ptr<noether::Integrator> make(const noether::System& system,
                                          std::shared_ptr<const noether::Potential> potential,
                                          const Params& p) {
  return std::make_unique<Lgvi>(system, std::move(potential), p);
}

}  // namespace

NOETHER_PLUGIN_DESCRIPTOR = {
    NOETHER_PLUGIN_API_VERSION,
    noether::PluginKind::Integrator,
    "lgvi",
    "Lie group variational integrator: inertial or relative frame, Hamiltonian or Lagrangian "
    "form, order 2, 4 or 6",
    params,
    std::size(params),
    nullptr,
    &make};
