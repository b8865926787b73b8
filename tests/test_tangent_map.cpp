// The tangent map of the LGVI (docs/equations.md §21): the state-transition matrix a run carries
// (run.stm) against central differences of whole runs, its symplecticity (21.9) and det = 1.
#include "test_support.hpp"

#include <noether/lie.hpp>
#include <noether/simulation.hpp>

#include <gtest/gtest.h>

#include <cmath>

using namespace noether;
using test::registry;

namespace {

// A Kepler orbit, e = 0.6, of a light body about a heavy one (point masses).
// The scene run to its t_end from its initial state moved by `dz` (coordinates 21.1).
State run_from(const Scene& scene, const Eigen::VectorXd& dz) {
  Scene s = scene;
  s.run.stm = false;
  const auto n = static_cast<Eigen::Index>(s.system.size()), m = static_cast<Eigen::Index>(s.system.rigid_count());
  State& z = s.initial;
  for (Eigen::Index i = 0; i < n; ++i) {
    z.x.col(i) += dz.segment(3 * i, 3);
    z.p.col(i) += dz.segment(3 * n + 3 * m + 3 * i, 3);
  }
  for (Eigen::Index r = 0; r < m; ++r) {
    z.R[static_cast<std::size_t>(r)] = z.R[static_cast<std::size_t>(r)] * exp_so3(dz.segment(3 * n + 3 * r, 3));
    z.Pi.col(r) += dz.segment(6 * n + 3 * m + 3 * r, 3);
  }
  Simulation sim(s, registry());
  sim.integrate(s.run.t_end);
  return sim.state();
}

// The step of each coordinate for central differences: a small fraction of the scene's scale of
// that kind (the largest separation L, each body's momentum at the largest speed V, and |Π| at
// the largest spin), and of a radian for attitudes.
Eigen::VectorXd steps(const Scene& scene, double fraction) {
  const State& z = scene.initial;
  const auto n = z.x.cols(), m = z.Pi.cols();
  double L = 0.0, V = 0.0, S = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < i; ++j) L = std::max(L, (z.x.col(i) - z.x.col(j)).norm());
    V = std::max(V, z.p.col(i).norm() / scene.system.body(static_cast<std::size_t>(i)).mass);
  }
  for (Eigen::Index r = 0; r < m; ++r) S = std::max(S, z.Pi.col(r).norm());
  Eigen::VectorXd h(6 * n + 6 * m);
  h.segment(0, 3 * n).setConstant(fraction * L);
  h.segment(3 * n, 3 * m).setConstant(fraction);
  for (Eigen::Index i = 0; i < n; ++i)
    h.segment(3 * n + 3 * m + 3 * i, 3).setConstant(fraction * scene.system.body(static_cast<std::size_t>(i)).mass * V);
  h.segment(6 * n + 3 * m, 3 * m).setConstant(fraction * S);
  return h;
}

// The STM the run carried, and the largest relative difference of a column from central
// differences of whole runs.
struct Comparison {
  Eigen::MatrixXd stm;
  double worst = 0.0;
};

// Each column by central differences of whole runs at steps 1e-4 … 1e-7 of the scales
// (steps()), taking the larger step of the two successive ones whose differences agree best: the
// error of central differences falls as h² until the runs' round-off (~ε/h, amplified by the
// run) takes over, and where that turns depends on the column (a fast spin's Π needs small
// steps, KW4's positions large ones). The choice uses the differences alone, never the STM they
// are compared with.
Comparison compare_with_differences(const Scene& scene) {
  Scene with = scene;
  with.run.stm = true;
  Simulation sim(with, registry());
  sim.integrate(with.run.t_end);
  Comparison c{sim.state().tangent, 0.0};
  const Eigen::Index N = c.stm.rows();
  EXPECT_EQ(N, State::tangent_rows(scene.system));
  EXPECT_EQ(c.stm.cols(), N);
  const double fractions[] = {1e-4, 1e-5, 1e-6, 1e-7};
  for (Eigen::Index j = 0; j < N; ++j) {
    std::vector<Eigen::VectorXd> columns;
    for (const double fraction : fractions) {
      const double h = steps(scene, fraction)(j);
      const Eigen::VectorXd e = h * Eigen::VectorXd::Unit(N, j);
      columns.push_back(State::difference(run_from(scene, -e), run_from(scene, e)) / (2.0 * h));
    }
    std::size_t best = 0;
    for (std::size_t k = 1; k + 1 < columns.size(); ++k)
      if ((columns[k] - columns[k + 1]).norm() < (columns[best] - columns[best + 1]).norm()) best = k;
    const double difference = (columns[best] - c.stm.col(j)).norm() / c.stm.col(j).norm();
    c.worst = std::max(c.worst, difference);
    if (std::getenv("NOETHER_TEST_VERBOSE"))
      std::printf("column %ld: |stm| %.3e, differences at %.0e: relative difference %.3e\n", static_cast<long>(j),
                  c.stm.col(j).norm(), fractions[best], difference);
  }
  return c;
}

// The symplectic form of z = (x, θ, γ, Π) at a state (21.9): canonical for (x, γ); for a rigid
// body's left-trivialised (θ, Π) the block S(Π) in θθ.
Eigen::MatrixXd symplectic_form(const State& z) {
  const auto n = z.x.cols(), m = z.Pi.cols(), q = 3 * n + 3 * m;
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(2 * q, 2 * q);
  W.topRightCorner(q, q) = -Eigen::MatrixXd::Identity(q, q);
  W.bottomLeftCorner(q, q) = Eigen::MatrixXd::Identity(q, q);
  for (Eigen::Index r = 0; r < m; ++r) W.block(3 * n + 3 * r, 3 * n + 3 * r, 3, 3) = hat(z.Pi.col(r));
  return W;
}

TEST(TangentMap, KeplerAgreesWithDifferencesOfWholeRuns) {
  const Comparison c = compare_with_differences(test::kepler_scene());
  EXPECT_LT(c.worst, 1e-6);
  EXPECT_NEAR(c.stm.determinant(), 1.0, 1e-10);
}

TEST(TangentMap, DumbbellsAgreeWithDifferencesBeforeTheCloseApproach) {
  const Comparison c = compare_with_differences(test::dumbbell_scene({"run.t_end=1", "run.output_every=0.5"}));
  EXPECT_LT(c.worst, 1e-6);
}

TEST(TangentMap, CompositionsAreProductsOfTheirStages) {
  const Comparison c = compare_with_differences(test::dumbbell_scene(
      {"run.t_end=1", "run.output_every=0.5", "integrator.order=4", "integrator.step=0.001"}));
  EXPECT_LT(c.worst, 1e-6);
}

// The Lagrangian form is the same map on (x, R, γ, Π) through the discrete Legendre transform
// (docs/equations.md §21): its STM and a mass's sensitivity agree with differences of its own
// whole runs, and with the Hamiltonian form's to round-off.
TEST(TangentMap, LagrangianFormCarriesTheSameMap) {
  const std::vector<std::string> set = {"run.t_end=1", "run.output_every=0.5", "integrator.form=lagrangian"};
  const Comparison c = compare_with_differences(test::dumbbell_scene(set));
  EXPECT_LT(c.worst, 1e-6);
  auto carried = [](const std::vector<std::string>& overrides) {
    Scene s = test::dumbbell_scene(overrides);
    s.run.stm = true;
    s.run.sensitivities = {"bodies.beta.mass"};
    Simulation sim(s, registry());
    sim.integrate(s.run.t_end);
    return Eigen::MatrixXd(sim.state().tangent);
  };
  const Eigen::MatrixXd lagrangian = carried(set);
  const Eigen::MatrixXd hamiltonian = carried({"run.t_end=1", "run.output_every=0.5"});
  const double apart = (lagrangian - hamiltonian).cwiseAbs().maxCoeff() / hamiltonian.cwiseAbs().maxCoeff();
  std::printf("Lagrangian against Hamiltonian form: STM and mass column %.1e apart (max |entry| %.1e)\n", apart,
              hamiltonian.cwiseAbs().maxCoeff());
  EXPECT_LT(apart, 1e-10);
}

// The relative-frame forms reduce the inertial map and reproduce it (docs/equations.md §5): they
// carry its tangent map (RelativeTangent). Both relative forms' STM and a mass's column against
// the inertial Hamiltonian form's, whose STM is checked against differences of whole runs above:
// after one step to round-off (measured 6e-17), after 5000 steps (t = 1) as far as round-off
// grows in an STM that reaches 2.5e3 (measured 8.5e-9; positions 3e-14 apart). (The relative
// Hamiltonian form's STM also agreed with differences of its own whole runs to < 1e-6, a check
// left out for its minute under the sanitizers.)
TEST(TangentMap, RelativeFormsCarryTheInertialMap) {
  auto carried = [](const std::string& t_end, const std::string& frame, const std::string& form) {
    Scene s = test::dumbbell_scene({"run.t_end=" + t_end, "run.output_every=" + t_end, "integrator.frame=" + frame,
                                    "integrator.form=" + form});
    s.run.stm = true;
    s.run.sensitivities = {"bodies.beta.mass"};
    Simulation sim(s, registry());
    sim.integrate(s.run.t_end);
    return Eigen::MatrixXd(sim.state().tangent);
  };
  for (const auto& [t_end, tolerance] : {std::pair<std::string, double>{"0.0002", 1e-14}, {"1", 1e-7}}) {
    const Eigen::MatrixXd inertial = carried(t_end, "inertial", "hamiltonian");
    for (const char* form : {"hamiltonian", "lagrangian"}) {
      const Eigen::MatrixXd relative = carried(t_end, "relative", form);
      const double apart = (relative - inertial).cwiseAbs().maxCoeff() / inertial.cwiseAbs().maxCoeff();
      std::printf("t = %s: relative %s form against the inertial Hamiltonian form, STM and mass column %.1e apart\n",
                  t_end.c_str(), form, apart);
      EXPECT_LT(apart, tolerance) << form << " at t = " << t_end;
    }
  }
}

TEST(TangentMap, Kw4EllipsoidsAtOrderFourAgreeWithDifferences) {
  const Comparison c = compare_with_differences(load_scene(test::source_path("examples/kw4-ellipsoids.yaml"),
                                                           {"run.t_end=7200", "run.output_every=3600"}));
  EXPECT_LT(c.worst, 1e-6);
}

// 10^4 steps: M^T W(z_N) M = W(z_0) to round-off, and det M = 1. Round-off in M's entries is
// ~ε‖M‖, so the defect is measured against ‖M‖² (the Kepler orbit's shear makes ‖M‖ ~ 3e4 by
// t = 10); the dumbbells' is also below 1e-10 as it stands.
TEST(TangentMap, IsSymplecticAfterTenThousandSteps) {
  for (const Scene& scene : {test::kepler_scene({"run.t_end=10", "run.output_every=10"}),
                             test::dumbbell_scene({"run.t_end=2", "run.output_every=2"})}) {
    Scene with = scene;
    with.run.stm = true;
    Simulation sim(with, registry());
    sim.integrate(with.run.t_end);
    const State& end = sim.state();
    const Eigen::MatrixXd& M = end.tangent;
    const double defect = (M.transpose() * symplectic_form(end) * M - symplectic_form(scene.initial)).cwiseAbs().maxCoeff();
    const double size = M.cwiseAbs().maxCoeff();
    EXPECT_LT(defect / std::max(1.0, size * size), 1e-16) << scene.file << ": defect " << defect << ", max |M| " << size;
    EXPECT_NEAR(M.determinant(), 1.0, 1e-11) << scene.file;
    EXPECT_EQ(sim.summary().work.steps, 10000);
    if (scene.file != "kepler") EXPECT_LT(defect, 1e-10);
  }
}

// rk: the variational equations (21.10) integrated beside the state by the same method. With a
// fixed step (rk4) that is the derivative of the method's map in its own variables; adaptive
// methods choose their steps on both, so whole runs differ from it at the tolerance.
const char* kRk4Kepler = "integrator={plugin: rk, method: rk4, step: 0.001}";
const char* kRk4Dumbbells = "integrator={plugin: rk, method: rk4, step: 0.0002}";
const char* kDopri5 = "integrator={plugin: rk, method: dopri5, rtol: 1e-13, atol: 1e-15}";
const char* kRkf78 = "integrator={plugin: rk, method: rkf78, rtol: 1e-13, atol: 1e-15}";
// cvode: CVODES forward sensitivities of the same variational equations, error-controlled.
const char* kAdams = "integrator={plugin: cvode, method: adams, rtol: 1e-13, atol: 1e-15}";
const char* kBdf = "integrator={plugin: cvode, method: bdf, rtol: 1e-12, atol: 1e-14}";

// Under the sanitizers (130 s there) one method of each kind on Kepler and the dumbbells: the
// same code (rk's stages, CVODES' sensitivities) that the other methods and KW4 run again.
#ifdef NOETHER_TEST_SANITIZED
constexpr bool kEveryMethod = false;
#else
constexpr bool kEveryMethod = true;
#endif

TEST(TangentMap, ContinuousStmsAgreeWithDifferencesOfWholeRuns) {
  for (const char* integrator : {kRk4Kepler, kDopri5, kRkf78, kAdams, kBdf}) {
    if (!kEveryMethod && integrator != kRk4Kepler && integrator != kAdams) continue;
    const Comparison c = compare_with_differences(test::kepler_scene({integrator}));
    EXPECT_LT(c.worst, 1e-6) << integrator;
    std::printf("kepler, %s: worst column %.3e\n", integrator, c.worst);
  }
  if (!kEveryMethod) return;
  for (const char* integrator : {kRk4Dumbbells, kDopri5, kAdams}) {
    const Comparison c =
        compare_with_differences(test::dumbbell_scene({"run.t_end=1", "run.output_every=0.5", integrator}));
    EXPECT_LT(c.worst, 1e-6) << integrator;
    std::printf("dumbbells, %s: worst column %.3e\n", integrator, c.worst);
  }
  // KW4 in SI units: an atol in metres and kg m/s. (dopri5 agrees to 2e-7 here with g++ and
  // 2e-6 with clang: differences of whole adaptive runs carry the step choices' noise, ~rtol/h,
  // so rk is checked here with its fixed-step method.)
  for (const char* integrator : {"integrator={plugin: rk, method: rk4, step: 60}",
                                 "integrator={plugin: cvode, method: adams, rtol: 1e-13, atol: 1e-6}"}) {
    const Comparison c = compare_with_differences(load_scene(test::source_path("examples/kw4-ellipsoids.yaml"),
                                                             {"run.t_end=3600", "run.output_every=3600", integrator}));
    EXPECT_LT(c.worst, 1e-6) << integrator;
    std::printf("kw4 ellipsoids, %s: worst column %.3e\n", integrator, c.worst);
  }
}

// rk in the relative frame and in the Lagrangian form carries the flow's STM in the inertial
// coordinates (21.1) too: the variational equations (21.10) at each stage's state made inertial.
// Against the inertial form's STM, itself checked against differences of whole runs above (rkf78
// at rtol 1e-12: the same flow, so to the tolerance; measured 8.7e-14 relative frame, 8.1e-15
// Lagrangian form; dopri5's relative-frame STM agreed with differences of its own whole runs to
// 2.2e-8, a check left out for its 3.5 minutes under the sanitizers). With a fixed step (rk4) it
// is the flow's STM to the method's order, not the exact derivative of that map.
TEST(TangentMap, RkInTheRelativeFrameCarriesTheFlowsStm) {
  auto carried = [](const std::string& variables) {
    std::vector<std::string> set = {"run.t_end=1", "run.output_every=1", "run.stm=true",
                                    "integrator={plugin: rk, method: rkf78, rtol: 1e-12, atol: 1e-14}"};
    if (!variables.empty()) set.push_back(variables);
    Simulation sim(test::dumbbell_scene(set), registry());
    sim.integrate(1.0);
    return Eigen::MatrixXd(sim.state().tangent);
  };
  const Eigen::MatrixXd inertial = carried("");
  for (const char* variables : {"integrator.frame=relative", "integrator.form=lagrangian"}) {
    const double apart = (carried(variables) - inertial).cwiseAbs().maxCoeff() / inertial.cwiseAbs().maxCoeff();
    std::printf("rkf78 at rtol 1e-12, %s against the inertial Hamiltonian form: STM %.1e apart\n", variables, apart);
    EXPECT_LT(apart, 1e-8) << variables;
  }
}

// The flow's STM is symplectic; an rk or cvode run's is so to its tolerance.
TEST(TangentMap, ContinuousStmIsSymplecticToTheTolerance) {
  for (const std::string rtol : {"1e-8", "1e-11"})
    for (const std::string method : {"{plugin: rk, method: dopri5", "{plugin: cvode, method: adams"}) {
    Scene scene = test::dumbbell_scene({"run.t_end=2", "run.output_every=2", "run.stm=true",
                                        "integrator=" + method + ", atol: 1e-14, rtol: " + rtol + "}"});
    Simulation sim(scene, registry());
    sim.integrate(scene.run.t_end);
    const Eigen::MatrixXd& M = sim.state().tangent;
    const double defect =
        (M.transpose() * symplectic_form(sim.state()) * M - symplectic_form(scene.initial)).cwiseAbs().maxCoeff();
    const double size = M.cwiseAbs().maxCoeff();
    std::printf("%s rtol %s: max |M^T W M - W| / |M|^2 = %.3e, det - 1 = %.3e\n", method.c_str(), rtol.c_str(),
                defect / (size * size), M.determinant() - 1);
    EXPECT_LT(defect / (size * size), 100 * std::stod(rtol)) << method;
    EXPECT_LT(std::abs(M.determinant() - 1), 100 * std::stod(rtol)) << method;
  }
}

// stm_error_control: the tangent's error controlled too — more steps, the same derivative.
TEST(TangentMap, ErrorControlOnTheStmTakesMoreStepsAndAgrees) {
  for (const char* plugin : {"rk", "cvode"}) {
    std::int64_t steps[2];
    for (const bool control : {false, true}) {
      Scene scene = test::kepler_scene(
                                {std::string("integrator={plugin: ") + plugin + ", rtol: 1e-12, atol: 1e-14, stm_error_control: " +
                                 (control ? "true" : "false") + "}"});
      const Comparison c = compare_with_differences(scene);
      EXPECT_LT(c.worst, 1e-6) << plugin << control;
      Scene with = scene;
      with.run.stm = true;
      Simulation sim(with, registry());
      sim.integrate(with.run.t_end);
      steps[control] = sim.summary().work.steps;
    }
    std::printf("%s: steps %ld without, %ld with error control on the STM\n", plugin, static_cast<long>(steps[0]),
                static_cast<long>(steps[1]));
    EXPECT_GT(steps[1], steps[0]) << plugin;
  }
}

TEST(TangentMap, RefusedByAnIntegratorWithoutOne) {
  for (const char* integrator : {"integrator={plugin: rk, atol: 0}", "integrator={plugin: cvode, atol: 0}",
                                 "integrator={plugin: cvode, frame: relative}", "integrator={plugin: jm-hybrid}"}) {
    Scene s = test::dumbbell_scene({"run.stm=true", integrator});
    EXPECT_THROW(Simulation(s, registry()), SceneError) << integrator;
  }
  // Started directly (not through the host, which asks first), each bundled method refuses a
  // tangent it cannot carry rather than handing it back unchanged.
  for (const char* integrator : {"integrator={plugin: cvode, frame: relative}", "integrator={plugin: cvode, atol: 0}"}) {
    Scene s = test::dumbbell_scene({integrator});
    auto potential = make_scene_potential(s, registry());
    auto method = registry().make_integrator(s.integrator.plugin, s.system, potential, s.integrator.params);
    State z = s.initial;
    z.tangent = Eigen::MatrixXd::Identity(24, 24);
    EXPECT_THROW(method->start(z), Error) << integrator;
  }
  try {
    Scene s = test::dumbbell_scene({"run.stm=true", "integrator={plugin: cvode, frame: relative}"});
    Simulation sim(s, registry());
    FAIL() << "cvode in the relative frame accepted run.stm";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot carry the state-transition matrix"), std::string::npos) << e.what();
  }
}

}  // namespace

// With forces beyond the potential (docs/equations.md §33): the kicks' derivatives (33.6)–(33.7)
// join the conservative map's — a tide that depends on the velocities and the spin (the closing
// kick implicit), at order 2 and in the order-4 composition, against differences of whole runs.
TEST(TangentMap, ForcedLgviAgreesWithDifferencesOfWholeRuns) {
  for (const char* order : {"integrator.order=2", "integrator.order=4"}) {
    if (!kEveryMethod && std::string(order) == "integrator.order=4") continue;  // the same kicks, composed
    const Scene scene = load_scene(test::source_path("examples/tidal-spin-down.yaml"),
                                   {"run.t_end=8", "run.output_every=8", order});
    const Comparison c = compare_with_differences(scene);
    std::printf("%s: worst column %.3e\n", order, c.worst);
    EXPECT_LT(c.worst, 1e-6) << order;
    // The forces matter: without them the map differs by far more than that.
    Scene unforced = scene;
    unforced.forces.clear();
    unforced.initial.force_balance.resize(0, 0);
    unforced.run.stm = true;
    Simulation sim(unforced, registry());
    sim.integrate(unforced.run.t_end);
    EXPECT_GT((sim.state().tangent - c.stm).norm() / c.stm.norm(), 1e-3) << order;
  }
}

// rk and cvode add B K^F V to the variational equations (33.8): rk4 at a fixed step (its own
// map's derivative to the method's order), and cvode's Adams at a tight tolerance.
TEST(TangentMap, ForcedContinuousStmsAgreeWithDifferencesOfWholeRuns) {
  for (const char* integrator : {"integrator={plugin: rk, method: rk4, step: 0.01}",
                                 "integrator={plugin: cvode, method: adams, rtol: 1e-12, atol: 1e-12}"}) {
    const Comparison c = compare_with_differences(
        load_scene(test::source_path("examples/tidal-spin-down.yaml"), {"run.t_end=8", "run.output_every=8", integrator}));
    std::printf("%s: worst column %.3e\n", integrator, c.worst);
    EXPECT_LT(c.worst, 1e-6) << integrator;
  }
}

// Carrying the tangent does not move the run: the same bits with and without it.
TEST(TangentMap, ForcedRunIsTheSameWithItsTangent) {
  Scene scene = load_scene(test::source_path("examples/tidal-spin-down.yaml"), {"run.t_end=2", "run.output_every=2"});
  Simulation without(scene, registry());
  without.integrate(scene.run.t_end);
  scene.run.stm = true;
  Simulation with(scene, registry());
  with.integrate(scene.run.t_end);
  EXPECT_EQ(with.state().x, without.state().x);
  EXPECT_EQ(with.state().p, without.state().p);
  EXPECT_EQ(with.state().Pi, without.state().Pi);
  EXPECT_EQ(with.state().force_balance, without.state().force_balance);
}

// Every form of the forced LGVI carries one tangent: the kicks' maps (33.6)–(33.7) around the
// inertial Lagrangian form's map and around the relative forms' (whose kicks are in the reduced
// momenta, (33.11)) are the inertial Hamiltonian form's, whose map the test above checks against
// whole runs — the STM and the sensitivities to the tide's Love number (G^F, 33.9) and the moon's
// mass, to round-off; and the relative Lagrangian form's STM against differences of whole runs.
// The moon made rigid (a small sphere's inertia) so that the relative frame takes the pair.
TEST(TangentMap, EveryForcedLgviFormCarriesTheSameTangent) {
  const std::vector<std::string> base = {"run.t_end=8", "run.output_every=8", "bodies.moon.inertia=[1e-3, 1e-3, 1e-3]"};
  auto scene = [&](const std::string& integrator, bool parameters) {
    std::vector<std::string> o = base;
    o.push_back("integrator={plugin: lgvi, step: 0.01" + integrator + "}");
    if (parameters) o.push_back("run.sensitivities=[forces.0.k2, bodies.moon.mass]");
    return load_scene(test::source_path("examples/tidal-spin-down.yaml"), o);
  };
  auto tangent = [&](const std::string& integrator) {
    Scene s = scene(integrator, true);
    s.run.stm = true;
    Simulation sim(s, registry());
    sim.integrate(s.run.t_end);
    return Eigen::MatrixXd(sim.state().tangent);
  };
  const std::pair<const char*, const char*> pairs[] = {{"", ", form: lagrangian"},
                                                       {"", ", frame: relative"},
                                                       {"", ", frame: relative, form: lagrangian"},
                                                       {", order: 4", ", order: 4, frame: relative"}};
  for (const auto& [reference, form] : pairs) {
    if (!kEveryMethod && std::string(form).find("order: 4") != std::string::npos) continue;  // the same kicks, composed
    const Eigen::MatrixXd a = tangent(reference), b = tangent(form);
    ASSERT_EQ(a.cols(), 26);  // 24 of the STM, then k2 and the moon's mass
    double worst = 0.0;
    for (Eigen::Index c = 0; c < a.cols(); ++c) worst = std::max(worst, (a.col(c) - b.col(c)).norm() / a.col(c).norm());
    std::printf("lgvi {step: 0.01%s} against {step: 0.01%s}: worst column %.2e\n", form, reference, worst);
    EXPECT_LT(worst, 1e-10) << form;
  }
  if (!kEveryMethod) return;
  const Comparison c = compare_with_differences(scene(", frame: relative, form: lagrangian", false));
  std::printf("relative lagrangian against whole runs: worst column %.3e\n", c.worst);
  EXPECT_LT(c.worst, 1e-6);
}
