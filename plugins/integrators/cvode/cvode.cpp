// cvode: SUNDIALS 6.4 CVODE on the continuous equations (docs/equations.md §3): variable-order,
// variable-step Adams–Moulton (with the fixed-point nonlinear solver) or BDF (Newton with a
// dense linear solver and a difference-quotient Jacobian). Output at the requested times by
// CVODE's own interpolation (dense output for the host's output times and events). Like every general-purpose solver here it integrates R as nine
// numbers, so R drifts off SO(3). With a tangent (run.stm), CVODES integrates it as forward
// sensitivities with error control: one sensitivity vector per column of the tangent, whose
// right-hand side is the variational equations (docs/equations.md eq. 21.10) laid out in y's
// slots (θ in the first three of each attitude's nine, the other six zero). The error control
// is on the state only unless stm_error_control asks for the sensitivities too. Forces beyond
// the potential (docs/equations.md §33) join the inertial Hamiltonian equations, their balance
// (33.3) integrated after the state in y, outside the error control (an atol of 1e300 there).
#include <noether/continuous_equations.hpp>
#include <noether/error.hpp>
#include <noether/plugin.hpp>
#include <noether/variational_equations.hpp>

#include <cvodes/cvodes.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <cmath>
#include <cstdlib>
#include <optional>
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
  N_Vector y = nullptr, dky = nullptr, tolerances = nullptr;
  void* memory = nullptr;
  SUNMatrix matrix = nullptr;
  SUNLinearSolver linear = nullptr;
  SUNNonlinearSolver nonlinear = nullptr, nonlinear_sensitivities = nullptr;
  N_Vector* yS = nullptr;  // the sensitivities (the tangent's columns), when carried
  int Ns = 0;
  ~CvodeSession() {
    if (memory) CVodeFree(&memory);
    if (yS) N_VDestroyVectorArray(yS, Ns);
    if (nonlinear_sensitivities) SUNNonlinSolFree(nonlinear_sensitivities);
    if (nonlinear) SUNNonlinSolFree(nonlinear);
    if (linear) SUNLinSolFree(linear);
    if (matrix) SUNMatDestroy(matrix);
    if (dky) N_VDestroy(dky);
    if (tolerances) N_VDestroy(tolerances);
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
    stm_error_control_ = p.at("stm_error_control").as_bool();
    if (rtol_ <= 0 || atol_ < 0 || max_steps_ < 0)
      throw SceneError(p.here() + "cvode: rtol must be positive, atol and max_steps non-negative");
    if (p.at("frame").as_string() != "inertial" || p.at("form").as_string() != "hamiltonian")
      tangent_unavailable_ = "cvode carries the state-transition matrix in its inertial Hamiltonian form only, not "
                             "frame: " + p.at("frame").as_string() + ", form: " + p.at("form").as_string();
    else if (atol_ == 0.0)
      tangent_unavailable_ = "with atol: 0 the error of the state-transition matrix, whose entries start at 0, cannot be "
                             "controlled; give cvode a positive atol";
    form_ = p.at("frame").as_string() + " " + p.at("form").as_string();
  }

  std::string tangent_map_unavailable() const override { return tangent_unavailable_; }
  std::string add_forcing(std::shared_ptr<const noether::Forcing> forcing) override {
    if (form_ != "inertial hamiltonian")
      return "cvode takes forces beyond the potential in its inertial Hamiltonian equations only: use frame: "
             "inertial, form: hamiltonian";
    forcing_.emplace(equations_->system(), std::move(forcing));
    return "";
  }
  // The parameters' terms (22.2) join the sensitivity right-hand side of the last columns, with
  // the forces' own derivative G^F when there are forces beyond the potential (33.9).
  std::string carry_parameters(std::shared_ptr<const noether::ParameterDerivatives> parameters) override {
    if (!tangent_map_unavailable().empty()) return tangent_map_unavailable();
    parameter_forces_.emplace(std::move(parameters));
    return "";
  }

  void start(const noether::State& state) override {
    if (state.tangent.size() > 0 && !tangent_map_unavailable().empty()) throw noether::Error(tangent_map_unavailable());
    balance_size_ = forcing_ ? static_cast<std::size_t>(noether::kBalanceRows) * forcing_->size() : 0;
    if (forcing_) forcing_->check_balance(state, "cvode");
    if (parameter_forces_ && !parameter_forces_->fits(state.tangent))
      throw noether::Error("cvode: the tangent has fewer columns than the parameters it carries");
    session_ = std::make_unique<CvodeSession>();
    CvodeSession& s = *session_;
    check(SUNContext_Create(nullptr, &s.context), "SUNContext_Create", state.t);
    const auto n = static_cast<sunindextype>(equations_->size() + balance_size_);
    s.y = N_VNew_Serial(n, s.context);
    // Fused vector operations (one pass, one call, for CVODE's linear combinations of the
    // Nordsieck history); CVODE's internal vectors are cloned from y and inherit them.
    check(N_VEnableFusedOps_Serial(s.y, SUNTRUE), "N_VEnableFusedOps_Serial", state.t);
    s.dky = N_VNew_Serial(n, s.context);
    equations_->pack(state, N_VGetArrayPointer(s.y));
    if (forcing_)  // y = (the equations' variables, then the forces' balance)
      std::copy(state.force_balance.data(), state.force_balance.data() + balance_size_,
                N_VGetArrayPointer(s.y) + equations_->size());
    s.memory = CVodeCreate(method_ == "adams" ? CV_ADAMS : CV_BDF, s.context);
    if (!s.memory) throw IntegrationError("cvode: CVodeCreate failed", state.t);
    CVodeSetErrHandlerFn(s.memory, &Cvode::on_error, this);
    check(CVodeInit(s.memory, &Cvode::rhs, state.t, s.y), "CVodeInit", state.t);
    check(CVodeSetUserData(s.memory, this), "CVodeSetUserData", state.t);
    if (forcing_) {  // the balance rides along outside the error control
      s.tolerances = N_VNew_Serial(n, s.context);
      double* atol = N_VGetArrayPointer(s.tolerances);
      std::fill(atol, atol + equations_->size(), atol_);
      std::fill(atol + equations_->size(), atol + n, 1e300);
      check(CVodeSVtolerances(s.memory, rtol_, s.tolerances), "CVodeSVtolerances", state.t);
    } else {
      check(CVodeSStolerances(s.memory, rtol_, atol_), "CVodeSStolerances", state.t);
    }
    if (method_ == "adams") {
      s.nonlinear = SUNNonlinSol_FixedPoint(s.y, 0, s.context);
      check(CVodeSetNonlinearSolver(s.memory, s.nonlinear), "CVodeSetNonlinearSolver", state.t);
    } else {
      s.matrix = SUNDenseMatrix(n, n, s.context);
      s.linear = SUNLinSol_Dense(s.y, s.matrix, s.context);
      check(CVodeSetLinearSolver(s.memory, s.linear, s.matrix), "CVodeSetLinearSolver", state.t);
    }
    tangent_rows_ = state.tangent.rows();
    if (state.tangent.size() > 0) start_sensitivities(state);
    start_tangent_ = state.tangent;
    stepped_ = false;
    t_ = state.t;
    base_ = work_;  // counters of earlier sessions (restarts) carry on
    differenced_evaluations_ = 0;  // this session's
  }

  // One internal step of CVODE (CV_ONE_STEP), never past t_max (its stop time).
  void step(double t_max) override {
    CvodeSession& s = *session_;
    const double* y = N_VGetArrayPointer(s.y);
    y_prev_.assign(y, y + equations_->size() + balance_size_);
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
    stepped_ = true;
    if (max_steps_ > 0 && work_.steps > max_steps_) {
      std::ostringstream msg;
      msg << "cvode (" << method_ << ", rtol " << rtol_ << ", atol " << atol_ << "): more than max_steps = "
          << max_steps_ << " steps (CV_TOO_MUCH_WORK) at t = " << t_ << hint(CV_TOO_MUCH_WORK);
      throw IntegrationError(msg.str(), t_);
    }
  }

  double time() const override { return t_; }

  void current(noether::State& state, noether::Forces& forces) override {
    current_state(state);
    equations_->forces(state, forces);  // for output; not counted as work
  }

  noether::PotentialEvaluator* potential_evaluator() override { return &equations_->evaluator(); }

  void current_state(noether::State& state) override {
    unpack(N_VGetArrayPointer(session_->y), t_, state);
    state.tangent.resize(0, 0);
    if (session_->Ns > 0 && !stepped_) {  // as started: CVODES has no step to read them from yet
      state.tangent = start_tangent_;
    } else if (session_->Ns > 0) {  // the sensitivities where the solver stands (its last step's end)
      double t_sensitivities = t_;
      check(CVodeGetSens(session_->memory, &t_sensitivities, session_->yS), "CVodeGetSens", t_);
      tangent_from(session_->yS, state);
    }
  }

  // CVODE's own interpolating polynomial over the last step (CVodeGetDky, k = 0), and CVODES's
  // for the sensitivities (CVodeGetSensDky).
  bool interpolate(double t, noether::State& state) override {
    check(CVodeGetDky(session_->memory, t, 0, session_->dky), "CVodeGetDky", t);
    unpack(N_VGetArrayPointer(session_->dky), t, state);
    state.tangent.resize(0, 0);
    if (session_->Ns > 0) {
      check(CVodeGetSensDky(session_->memory, t, 0, session_->yS), "CVodeGetSensDky", t);
      tangent_from(session_->yS, state);
    }
    return true;
  }

 private:
  // The state of y, with the forces' balance when there are forces.
  void unpack(const double* y, double t, noether::State& state) const {
    equations_->unpack(y, t, state);
    if (forcing_)
      state.force_balance = Eigen::Map<const Eigen::MatrixXd>(y + equations_->size(), noether::kBalanceRows,
                                                              static_cast<Eigen::Index>(forcing_->size()));
  }

  // The slot in y of each row of the tangent (21.1): x, θ (the first three of the attitude's
  // nine numbers), γ, Π; y's layout is [x | γ | R (9 each) | Π] (continuous_equations.hpp).
  std::vector<std::size_t> tangent_slots() const {
    const noether::System& sys = equations_->system();
    const std::size_t n = sys.size(), m = sys.rigid_count();
    std::vector<std::size_t> slot;
    for (std::size_t i = 0; i < 3 * n; ++i) slot.push_back(i);
    for (std::size_t r = 0; r < m; ++r)
      for (std::size_t a = 0; a < 3; ++a) slot.push_back(6 * n + 9 * r + a);
    for (std::size_t i = 0; i < 3 * n; ++i) slot.push_back(3 * n + i);
    for (std::size_t i = 0; i < 3 * m; ++i) slot.push_back(6 * n + 9 * m + i);
    return slot;
  }

  // CVODES forward sensitivities, one per column of the tangent, with tolerances estimated from
  // the state's (CVodeSensEEtolerances), under error control only with stm_error_control.
  // Simultaneous corrector: the fixed-point iteration for adams, Newton on the same dense
  // linear solver for bdf.
  void start_sensitivities(const noether::State& state) {
    CvodeSession& s = *session_;
    s.Ns = static_cast<int>(state.tangent.cols());
    s.yS = N_VCloneVectorArray(s.Ns, s.y);
    if (!s.yS) throw IntegrationError("cvode: could not allocate the sensitivities", state.t);
    slots_ = tangent_slots();
    for (int c = 0; c < s.Ns; ++c) {
      N_VConst(0.0, s.yS[c]);
      double* v = N_VGetArrayPointer(s.yS[c]);
      for (Eigen::Index r = 0; r < tangent_rows_; ++r) v[slots_[static_cast<std::size_t>(r)]] = state.tangent(r, c);
    }
    check(CVodeSensInit(s.memory, s.Ns, CV_SIMULTANEOUS, &Cvode::sensitivity_rhs, s.yS), "CVodeSensInit", state.t);
    check(CVodeSensEEtolerances(s.memory), "CVodeSensEEtolerances", state.t);
    check(CVodeSetSensErrCon(s.memory, stm_error_control_ ? SUNTRUE : SUNFALSE), "CVodeSetSensErrCon", state.t);
    if (method_ == "adams") {
      s.nonlinear_sensitivities = SUNNonlinSol_FixedPointSens(s.Ns + 1, s.y, 0, s.context);
      check(CVodeSetNonlinearSolverSensSim(s.memory, s.nonlinear_sensitivities), "CVodeSetNonlinearSolverSensSim",
            state.t);
    }
    V_.resize(tangent_rows_, s.Ns);
    dV_.resize(tangent_rows_, s.Ns);
  }

  // The tangent's rows from the sensitivity vectors' slots.
  void tangent_from(N_Vector* yS, noether::State& state) const {
    state.tangent.resize(tangent_rows_, session_->Ns);
    for (int c = 0; c < session_->Ns; ++c) {
      const double* v = N_VGetArrayPointer(yS[c]);
      for (Eigen::Index r = 0; r < tangent_rows_; ++r) state.tangent(r, c) = v[slots_[static_cast<std::size_t>(r)]];
    }
  }

  // ẏS = A(y) yS: the variational equations (21.10) in y's slots, K at the state y (a
  // differenced K's evaluations counted as work).
  static int sensitivity_rhs(int Ns, sunrealtype t, N_Vector y, N_Vector, N_Vector* yS, N_Vector* ySdot,
                             void* self, N_Vector, N_Vector) {
    auto* me = static_cast<Cvode*>(self);
    try {
      me->equations_->unpack(N_VGetArrayPointer(y), t, me->stage_);
      bool analytic = true;
      const Eigen::MatrixXd K = me->equations_->evaluator().force_jacobian(me->stage_, &analytic);
      if (!analytic) me->differenced_evaluations_ += 2 * K.rows();
      for (int c = 0; c < Ns; ++c) {
        const double* v = N_VGetArrayPointer(yS[c]);
        for (Eigen::Index r = 0; r < me->tangent_rows_; ++r) me->V_(r, c) = v[me->slots_[static_cast<std::size_t>(r)]];
      }
      noether::variational_rhs(me->equations_->system(), me->stage_, K, me->V_, me->dV_);
      if (me->forcing_) {  // + B K^F V (33.8)
        me->forcing_->jacobian(me->stage_, me->forcing_jacobian_);
        noether::add_forcing_tangent(me->equations_->system(), me->forcing_jacobian_, 1.0, me->V_, me->dV_);
      }
      if (me->parameter_forces_) {  // ∂z/∂p columns: + the parameters' terms (22.2)
        auto& forces = *me->parameter_forces_;
        const Eigen::MatrixXd& G = forces.with_forcing(me->stage_);  // G + G^F (33.9)
        me->differenced_evaluations_ += forces.evaluations_per_call();
        noether::add_parameter_rhs(me->equations_->system(), me->stage_, forces.derivatives(), G,
                                   me->dV_.rightCols(static_cast<Eigen::Index>(forces.size())));
      }
      for (int c = 0; c < Ns; ++c) {
        N_VConst(0.0, ySdot[c]);
        double* d = N_VGetArrayPointer(ySdot[c]);
        for (Eigen::Index r = 0; r < me->tangent_rows_; ++r) d[me->slots_[static_cast<std::size_t>(r)]] = me->dV_(r, c);
      }
      return 0;
    } catch (const std::exception& e) {
      me->last_error_ = e.what();
      return -1;  // unrecoverable: CVODES stops with CV_SRHSFUNC_FAIL
    }
  }

  static int rhs(sunrealtype t, N_Vector y, N_Vector ydot, void* self) {
    auto* me = static_cast<Cvode*>(self);
    try {
      me->equations_->rhs(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot));
      if (me->forcing_) {  // forces beyond the potential and their balance rates (33.3)
        me->equations_->unpack(N_VGetArrayPointer(y), t, me->stage_);
        me->forcing_->add_to_inertial_hamiltonian(me->stage_, N_VGetArrayPointer(ydot),
                                                  N_VGetArrayPointer(ydot) + me->equations_->size());
      }
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
    // (fS evaluates K, not U: a differenced K's evaluations are counted, an analytic one's not)
    work_.potential_evaluations =
        base_.potential_evaluations + fevals + lin_fevals + differenced_evaluations_;  // one U per rhs call
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
  bool stm_error_control_ = false;
  std::string last_error_;
  std::unique_ptr<CvodeSession> session_;
  std::vector<double> y_prev_;
  double t_ = 0;
  noether::WorkCounters base_;
  // The tangent (run.stm): its rows, their slots in y, scratch for the variational equations,
  // and the evaluations made to difference a force Jacobian.
  Eigen::Index tangent_rows_ = 0;
  Eigen::MatrixXd start_tangent_;  // the tangent given to start(), what current() returns before the first step
  bool stepped_ = false;           // a step was taken since start()
  std::vector<std::size_t> slots_;
  Eigen::MatrixXd V_, dV_;
  noether::State stage_;
  std::int64_t differenced_evaluations_ = 0;
  std::string tangent_unavailable_;
  std::optional<noether::ParameterForces> parameter_forces_;  // sensitivities to parameters of the dynamics
  std::string form_;  // "inertial hamiltonian", …
  // Forces beyond the potential (none: the potential alone) and their balance's numbers in y.
  std::optional<noether::ForcingEvaluator> forcing_;
  Eigen::MatrixXd forcing_jacobian_;  // K^F at the state of a sensitivity evaluation (33.8)
  std::size_t balance_size_ = 0;
};

const noether::ParamDoc params[] = {
    {"method", "string", "adams",
     "adams (Adams–Moulton, fixed-point iteration; non-stiff) or bdf (BDF, Newton + dense LU)"},
    {"rtol", "number", "1e-8", "relative tolerance"},
    {"atol", "number", "1e-10", "absolute tolerance"},
    {"max_steps", "integer", "0", "internal steps allowed in the whole run; 0: no cap (bound long runs with --max-wall-time)"},
    {"stm_error_control", "bool", "false",
     "with run.stm: control the error of the sensitivities too, not only of the state (smaller steps; with a "
     "differenced force Jacobian, rtol below ~1e-10 then cannot be met)"},
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
