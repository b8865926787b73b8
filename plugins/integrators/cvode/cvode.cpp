// cvode: SUNDIALS 6.4 CVODE on the continuous equations (docs/equations.md §3): variable-order,
// variable-step Adams–Moulton (with the fixed-point nonlinear solver) or BDF (Newton with a
// dense linear solver and a difference-quotient Jacobian). Output at the requested times by
// CVODE's own interpolation (dense output for the host's output times and events). Like every general-purpose solver here it integrates R as nine
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
#include <cstdlib>
#include <sstream>

namespace {

// CVodeGetReturnFlagName returns a string the caller must free (24 bytes leaked per failure
// otherwise).
std::string flag_name(int flag) {
  char* name = CVodeGetReturnFlagName(flag);
  std::string out = name ? name : "unknown flag";
  std::free(name);
  return out;
}

using noether::IntegrationError;
using noether::Params;
using noether::SceneError;

// Owns every SUNDIALS object of one integration; releases them in reverse order.
struct CvodeSession {
  SUNContext context = nullptr;
  N_Vector y = nullptr, dky = nullptr;
  void* memory = nullptr;
  SUNMatrix matrix = nullptr;
  SUNLinearSolver linear = nullptr;
  SUNNonlinearSolver nonlinear = nullptr;
  ~CvodeSession() {
    if (memory) CVodeFree(&memory);
    if (nonlinear) SUNNonlinSolFree(nonlinear);
    if (linear) SUNLinSolFree(linear);
    if (matrix) SUNMatDestroy(matrix);
    if (dky) N_VDestroy(dky);
    if (y) N_VDestroy(y);
    if (context) SUNContext_Free(&context);
  }
};

class Cvode final : public noether::Integrator {
 public:
  Cvode(const noether::System& system, std::shared_ptr<const noether::Potential> potential,
        const Params& p)
      : equations_(noether::make_continuous_equations(
            system, std::move(potential), p.at("frame").as_string(),
            p.at("form").as_string())) {
    method_ = p.at("method").as_string();
    if (method_ != "adams" && method_ != "bdf")
      throw SceneError(p.at("method").here() + "cvode: method must be adams or bdf, not '" +
                       method_ + "'");
    rtol_ = p.at("rtol").as_double();
    atol_ = p.at("atol").as_double();
    max_steps_ = p.at("max_steps").as_int();  // 0: no cap
    if (rtol_ <= 0 || atol_ < 0 || max_steps_ < 0)
      throw SceneError(p.here() + "cvode: rtol must be positive, atol and max_steps non-negative");
  }

  void start(const noether::State& state) override {
    session_ = std::make_unique<CvodeSession>();
    CvodeSession& s = *session_;
    check(SUNContext_Create(nullptr, &s.context), "SUNContext_Create", state.t);
    const auto n = static_cast<sunindextype>(equations_->size());
    s.y = N_VNew_Serial(n, s.context);
    // Fused vector operations (one pass, one call, for CVODE's linear combinations of the
    // Nordsieck history); CVODE's internal vectors are cloned from y and inherit them.
    check(N_VEnableFusedOps_Serial(s.y, SUNTRUE), "N_VEnableFusedOps_Serial", state.t);
    s.dky = N_VNew_Serial(n, s.context);
    equations_->pack(state, N_VGetArrayPointer(s.y));
    s.memory = CVodeCreate(method_ == "adams" ? CV_ADAMS : CV_BDF, s.context);
    if (!s.memory) throw IntegrationError("cvode: CVodeCreate failed", state.t);
    CVodeSetErrHandlerFn(s.memory, &Cvode::on_error, this);
    check(CVodeInit(s.memory, &Cvode::rhs, state.t, s.y), "CVodeInit", state.t);
    check(CVodeSetUserData(s.memory, this), "CVodeSetUserData", state.t);
    check(CVodeSStolerances(s.memory, rtol_, atol_), "CVodeSStolerances", state.t);
    if (method_ == "adams") {
      s.nonlinear = SUNNonlinSol_FixedPoint(s.y, 0, s.context);
      check(CVodeSetNonlinearSolver(s.memory, s.nonlinear), "CVodeSetNonlinearSolver", state.t);
    } else {
      s.matrix = SUNDenseMatrix(n, n, s.context);
      s.linear = SUNLinSol_Dense(s.y, s.matrix, s.context);
      check(CVodeSetLinearSolver(s.memory, s.linear, s.matrix), "CVodeSetLinearSolver", state.t);
    }
    t_ = state.t;
    base_ = work_;  // counters of earlier sessions (restarts) carry on
  }

  // One internal step of CVODE (CV_ONE_STEP), never past t_max (its stop time).
  void step(double t_max) override {
    CvodeSession& s = *session_;
    const double* y = N_VGetArrayPointer(s.y);
    y_prev_.assign(y, y + equations_->size());
    check(CVodeSetStopTime(s.memory, t_max), "CVodeSetStopTime", t_);
    double t_reached = t_;
    const int flag = CVode(s.memory, t_max, s.y, &t_reached, CV_ONE_STEP);
    collect_work(s.memory);
    if (flag < 0) {
      std::copy(y_prev_.begin(), y_prev_.end(), N_VGetArrayPointer(s.y));  // the last valid state
      std::ostringstream msg;
      msg << "cvode (" << method_ << ", rtol " << rtol_ << ", atol " << atol_ << ") stopped at t = "
          << t_reached << ": " << flag_name(flag) << ": " << last_error_ << hint(flag);
      throw IntegrationError(msg.str(), t_);
    }
    t_ = t_reached;
    if (max_steps_ > 0 && work_.steps > max_steps_) {
      std::ostringstream msg;
      msg << "cvode (" << method_ << ", rtol " << rtol_ << ", atol " << atol_ << "): more than max_steps = "
          << max_steps_ << " steps (CV_TOO_MUCH_WORK) at t = " << t_ << hint(CV_TOO_MUCH_WORK);
      throw IntegrationError(msg.str(), t_);
    }
  }

  double time() const override { return t_; }

  void current(noether::State& state, noether::Forces& forces) override {
    equations_->unpack(N_VGetArrayPointer(session_->y), t_, state);
    equations_->forces(state, forces);  // for output; not counted as work
  }

  noether::PotentialEvaluator* potential_evaluator() override { return &equations_->evaluator(); }

  void current_state(noether::State& state) override {
    equations_->unpack(N_VGetArrayPointer(session_->y), t_, state);
  }

  // CVODE's own interpolating polynomial over the last step (CVodeGetDky, k = 0).
  bool interpolate(double t, noether::State& state) override {
    check(CVodeGetDky(session_->memory, t, 0, session_->dky), "CVodeGetDky", t);
    equations_->unpack(N_VGetArrayPointer(session_->dky), t, state);
    return true;
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

  void collect_work(void* memory) {
    long steps = 0, fevals = 0, lin_fevals = 0, nonlin = 0, fails = 0;
    CVodeGetNumSteps(memory, &steps);
    CVodeGetNumRhsEvals(memory, &fevals);
    if (method_ == "bdf") CVodeGetNumLinRhsEvals(memory, &lin_fevals);
    CVodeGetNumNonlinSolvIters(memory, &nonlin);
    CVodeGetNumErrTestFails(memory, &fails);
    work_.steps = base_.steps + steps;
    work_.potential_evaluations = base_.potential_evaluations + fevals + lin_fevals;  // one U per rhs call
    work_.newton_iterations = base_.newton_iterations + nonlin;
    work_.rejected_steps = base_.rejected_steps + fails;
  }

  void check(int flag, const char* what, double t) const {
    if (flag < 0)
      throw IntegrationError(std::string("cvode: ") + what + " failed (" +
                                 flag_name(flag) + ") " + last_error_,
                             t);
  }

  std::unique_ptr<noether::ContinuousEquations> equations_;
  std::string method_;
  double rtol_ = 0, atol_ = 0;
  long max_steps_ = 0;
  std::string last_error_;
  std::unique_ptr<CvodeSession> session_;
  std::vector<double> y_prev_;
  double t_ = 0;
  noether::WorkCounters base_;
};

const noether::ParamDoc params[] = {
    {"method", "string", "adams",
     "adams (Adams–Moulton, fixed-point iteration; non-stiff) or bdf (BDF, Newton + dense LU)"},
    {"rtol", "number", "1e-8", "relative tolerance"},
    {"atol", "number", "1e-10", "absolute tolerance"},
    {"max_steps", "integer", "0", "internal steps allowed in the whole run; 0: no cap (bound long runs with --max-wall-time)"},
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
    "SUNDIALS CVODE (Adams or BDF) on the continuous equations",
    params,
    std::size(params),
    nullptr,
    &make};
