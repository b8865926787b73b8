// cvode: SUNDIALS 6.4 CVODE on the continuous equations (docs/equations.md §3): variable-order,
// variable-step Adams–Moulton (with the fixed-point nonlinear solver) or BDF (Newton with a
// dense linear solver and a difference-quotient Jacobian). Output at the requested times by
// CVODE's own interpolation. Optional root finding stops the run when two body centres come
// closer than `close_approach`. Like every general-purpose solver here it integrates R as nine
// numbers, so R drifts off SO(3).
#include <noether/continuous_equations.hpp>
#include <noether/error.hpp>
#include <noether/plugin.hpp>

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <cmath>
#include <sstream>

namespace {

using noether::IntegrationError;
using noether::Params;
using noether::SceneError;

// Owns every SUNDIALS object of one integration; releases them in reverse order.
struct CvodeSession {
  SUNContext context = nullptr;
  N_Vector y = nullptr;
  void* memory = nullptr;
  SUNMatrix matrix = nullptr;
  SUNLinearSolver linear = nullptr;
  SUNNonlinearSolver nonlinear = nullptr;
  ~CvodeSession() {
    if (memory) CVodeFree(&memory);
    if (nonlinear) SUNNonlinSolFree(nonlinear);
    if (linear) SUNLinSolFree(linear);
    if (matrix) SUNMatDestroy(matrix);
    if (y) N_VDestroy(y);
    if (context) SUNContext_Free(&context);
  }
};

class Cvode final : public noether::Integrator {
 public:
  Cvode(const noether::System& system, std::shared_ptr<const noether::Potential> potential,
        const Params& p)
      : equations_(noether::make_continuous_equations(
            system, std::move(potential), p.get("frame", std::string("inertial")),
            p.get("form", std::string("hamiltonian")))) {
    method_ = p.get("method", std::string("adams"));
    if (method_ != "adams" && method_ != "bdf")
      throw SceneError(p.at("method").here() + "cvode: method must be adams or bdf, not '" +
                       method_ + "'");
    rtol_ = p.get("rtol", 1e-8);
    atol_ = p.get("atol", 1e-10);
    max_steps_ = p.get("max_steps", 500000L);
    close_approach_ = p.get("close_approach", 0.0);
    p_frame_ = p.get("frame", std::string("inertial"));
    if (rtol_ <= 0 || atol_ < 0 || max_steps_ < 1 || close_approach_ < 0)
      throw SceneError(p.here() + "cvode: rtol and max_steps must be positive, atol and "
                                  "close_approach non-negative");
    for (std::size_t i = 0; i < system.size(); ++i)
      for (std::size_t j = i + 1; j < system.size(); ++j) pairs_.emplace_back(i, j);
  }

  void integrate(noether::State& state, const noether::OutputSchedule& schedule,
                 noether::Observer& observer) override {
    CvodeSession s;
    check(SUNContext_Create(nullptr, &s.context), "SUNContext_Create", state.t);
    const auto n = static_cast<sunindextype>(equations_->size());
    s.y = N_VNew_Serial(n, s.context);
    equations_->pack(state, N_VGetArrayPointer(s.y));
    s.memory = CVodeCreate(method_ == "adams" ? CV_ADAMS : CV_BDF, s.context);
    if (!s.memory) throw IntegrationError("cvode: CVodeCreate failed", state.t);
    CVodeSetErrHandlerFn(s.memory, &Cvode::on_error, this);
    check(CVodeInit(s.memory, &Cvode::rhs, state.t, s.y), "CVodeInit", state.t);
    check(CVodeSetUserData(s.memory, this), "CVodeSetUserData", state.t);
    check(CVodeSStolerances(s.memory, rtol_, atol_), "CVodeSStolerances", state.t);
    check(CVodeSetMaxNumSteps(s.memory, max_steps_), "CVodeSetMaxNumSteps", state.t);
    if (method_ == "adams") {
      s.nonlinear = SUNNonlinSol_FixedPoint(s.y, 0, s.context);
      check(CVodeSetNonlinearSolver(s.memory, s.nonlinear), "CVodeSetNonlinearSolver", state.t);
    } else {
      s.matrix = SUNDenseMatrix(n, n, s.context);
      s.linear = SUNLinSol_Dense(s.y, s.matrix, s.context);
      check(CVodeSetLinearSolver(s.memory, s.linear, s.matrix), "CVodeSetLinearSolver", state.t);
    }
    if (close_approach_ > 0 && p_frame_ == "relative")
      throw noether::SceneError("cvode: close_approach needs frame: inertial");
    if (close_approach_ > 0 && !pairs_.empty())
      check(CVodeRootInit(s.memory, static_cast<int>(pairs_.size()), &Cvode::roots),
            "CVodeRootInit", state.t);

    noether::Forces forces;
    forces.resize(equations_->system());
    auto emit = [&](double t) {  // forces at the output state for diagnostics (not counted)
      equations_->unpack(N_VGetArrayPointer(s.y), t, state);
      equations_->potential().evaluate(state, forces);
      observer.observe(state, forces);
    };
    emit(state.t);
    const auto times = noether::output_times(state.t, schedule.t_end, schedule.output_every);
    for (std::size_t k = 1; k < times.size(); ++k) {
      double t_reached = state.t;
      const int flag = CVode(s.memory, times[k], s.y, &t_reached, CV_NORMAL);
      collect_work(s.memory);
      if (flag == CV_ROOT_RETURN) {
        record_close_approach(s, t_reached);
        emit(t_reached);
        return;
      }
      if (flag < 0) {
        equations_->unpack(N_VGetArrayPointer(s.y), t_reached, state);
        std::ostringstream msg;
        msg << "cvode (" << method_ << ", rtol " << rtol_ << ", atol " << atol_ << ") stopped at t = "
            << t_reached << ": " << CVodeGetReturnFlagName(flag) << ": " << last_error_ << hint(flag);
        throw IntegrationError(msg.str(), t_reached);
      }
      emit(times[k]);
    }
  }

 private:
  static int rhs(sunrealtype t, N_Vector y, N_Vector ydot, void* self) {
    auto* me = static_cast<Cvode*>(self);
    try {
      me->equations_->rhs(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot));
      return 0;
    } catch (const std::exception& e) {
      me->last_error_ = e.what();
      return -1;  // unrecoverable: CVODE stops with CV_RHSFUNC_FAIL
    }
  }

  // g_ij = ‖x_i − x_j‖ − close_approach for every pair: a root is a close approach.
  static int roots(sunrealtype, N_Vector y, sunrealtype* g, void* self) {
    auto* me = static_cast<Cvode*>(self);
    const double* x = N_VGetArrayPointer(y);
    for (std::size_t k = 0; k < me->pairs_.size(); ++k) {
      const auto [i, j] = me->pairs_[k];
      const Eigen::Map<const noether::Vec3> xi(x + 3 * i), xj(x + 3 * j);
      g[k] = (xi - xj).norm() - me->close_approach_;
    }
    return 0;
  }

  static void on_error(int, const char* module, const char* function, char* msg, void* self) {
    static_cast<Cvode*>(self)->last_error_ =
        std::string(module) + "/" + function + ": " + msg;
  }

  static std::string hint(int flag) {
    switch (flag) {
      case CV_TOO_MUCH_WORK: return " (raise integrator.max_steps, or loosen rtol/atol)";
      case CV_TOO_MUCH_ACC: return " (the tolerances are below what double precision allows)";
      case CV_ERR_FAILURE:
      case CV_CONV_FAILURE:
        return " (a singularity or collision is likely near this time; check the scene, or try "
               "method bdf)";
      default: return "";
    }
  }

  void record_close_approach(CvodeSession& s, double t) {
    std::vector<int> found(pairs_.size());
    CVodeGetRootInfo(s.memory, found.data());
    std::ostringstream msg;
    for (std::size_t k = 0; k < pairs_.size(); ++k)
      if (found[k] < 0) {  // distance decreasing through the threshold
        msg << "close approach: bodies '" << equations_->system().body(pairs_[k].first).name
            << "' and '" << equations_->system().body(pairs_[k].second).name
            << "' came within " << close_approach_ << " at t = " << t;
        break;
      }
    stop_reason_ = msg.str().empty()
                       ? "close approach threshold " + std::to_string(close_approach_) +
                             " crossed at t = " + std::to_string(t)
                       : msg.str();
  }

  void collect_work(void* memory) {
    long steps = 0, fevals = 0, lin_fevals = 0, nonlin = 0, fails = 0;
    CVodeGetNumSteps(memory, &steps);
    CVodeGetNumRhsEvals(memory, &fevals);
    if (method_ == "bdf") CVodeGetNumLinRhsEvals(memory, &lin_fevals);
    CVodeGetNumNonlinSolvIters(memory, &nonlin);
    CVodeGetNumErrTestFails(memory, &fails);
    work_.steps = steps;
    work_.potential_evaluations = fevals + lin_fevals;  // every rhs call evaluates U once
    work_.newton_iterations = nonlin;
    work_.rejected_steps = fails;
  }

  void check(int flag, const char* what, double t) const {
    if (flag < 0)
      throw IntegrationError(std::string("cvode: ") + what + " failed (" +
                                 CVodeGetReturnFlagName(flag) + ") " + last_error_,
                             t);
  }

  std::unique_ptr<noether::ContinuousEquations> equations_;
  std::string method_;
  double rtol_ = 0, atol_ = 0, close_approach_ = 0;
  long max_steps_ = 0;
  std::vector<std::pair<std::size_t, std::size_t>> pairs_;
  std::string last_error_;
  std::string p_frame_;
};

const noether::ParamDoc params[] = {
    {"method", "string", "adams",
     "adams (Adams–Moulton, fixed-point iteration; non-stiff) or bdf (BDF, Newton + dense LU)"},
    {"rtol", "number", "1e-8", "relative tolerance"},
    {"atol", "number", "1e-10", "absolute tolerance"},
    {"max_steps", "integer", "500000", "internal steps allowed between two output times"},
    {"close_approach", "number", "0 (off)",
     "stop the run (an event, not an error) when two body centres come closer than this"},
    {"frame", "string", "inertial", "inertial (29)–(32), or relative: two rigid bodies only"},
    {"form", "string", "hamiltonian", "hamiltonian (momenta) or lagrangian (velocities, (25)–(28), (55)–(62))"},
};

std::unique_ptr<noether::Integrator> make(const noether::System& system,
                                          std::shared_ptr<const noether::Potential> potential,
                                          const Params& p) {
  return std::make_unique<Cvode>(system, std::move(potential), p);
}

}  // namespace

NOETHER_PLUGIN_DESCRIPTOR = {
    NOETHER_PLUGIN_API_VERSION,
    noether::PluginKind::Integrator,
    "cvode",
    "SUNDIALS CVODE (Adams or BDF) on the continuous equations, with close-approach events",
    params,
    std::size(params),
    nullptr,
    &make};
