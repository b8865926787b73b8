// Sensitivities to keys of the bodies' initial states (run.sensitivities, docs/derivatives.md):
// each column against central differences of whole runs moved with the same key, for the LGVI
// and rk4; the columns are the STM times their start; keys the run cannot take are refused.
#include "test_support.hpp"

#include <noether/error.hpp>
#include <noether/simulation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <functional>
#include <map>

using namespace noether;
using test::registry;

namespace {

// Under the sanitizers the forced LGVI's order 4 is left out: the same kicks, composed.
#ifdef NOETHER_TEST_SANITIZED
constexpr bool kEveryMethod = false;
#else
constexpr bool kEveryMethod = true;
#endif

// A planet given by its osculating elements about a star, the scene moved onto its barycentre.
const char* kElements = R"(G: 1
barycentric: true
bodies:
  - {name: star, mass: 1, position: [0, 0, 0], velocity: [0, 0, 0]}
  - name: planet
    mass: 1.0e-3
    orbit: {around: star, a: 1, e: 0.3, i: 20, Omega: 40, omega: 60, M: 30}
potential: {plugin: point-mass}
integrator: {plugin: lgvi, step: 0.001}
run: {t_end: 3, output_every: 1}
)";

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

// The state at t_end of the scene `text` with `overrides`, or of its initial state changed by `edit`.
State final_state(const std::string& text, const std::vector<std::string>& overrides,
                  const std::function<void(State&)>& edit = {}, const std::string& file = "test") {
  Scene scene = parse_scene(text, file, overrides);
  if (edit) edit(scene.initial);
  Simulation sim(scene, registry());
  sim.integrate(scene.run.t_end);
  return sim.state();
}

// A column by central differences of whole runs, the key moved by ±h for h = fraction × scale,
// fraction 1e-3 … 1e-6, taking the larger h of the two successive ones whose differences agree
// best (as test_tangent_map.cpp's compare_with_differences: chosen by the differences alone).
Eigen::VectorXd differenced(const std::function<State(double)>& moved, double scale,
                            const std::vector<double>& fractions = {1e-3, 1e-4, 1e-5, 1e-6}) {
  std::vector<Eigen::VectorXd> columns;
  for (const double fraction : fractions) {
    const double h = fraction * scale;
    columns.push_back(State::difference(moved(-h), moved(h)) / (2.0 * h));
  }
  std::size_t best = 0;
  for (std::size_t k = 1; k + 1 < columns.size(); ++k)
    if ((columns[k] - columns[k + 1]).norm() < (columns[best] - columns[best + 1]).norm()) best = k;
  return columns[best];
}

double relative(const Eigen::VectorXd& a, const Eigen::VectorXd& b) { return (a - b).norm() / b.norm(); }

// Every column of the run's sensitivities against differences of runs with the key (a scalar
// key, or a component: "bodies.star.velocity.1") moved from `values` (its value in the scene),
// by fractions of max(1, |value|), or of |value| itself with `own_scale` (a mass of 1e11 kg);
// `fractions` as differenced's; `file`: where the text was read from (its relative paths).
double worst_column(const std::string& text, const std::vector<std::string>& overrides,
                    const std::map<std::string, double>& values, bool own_scale = false,
                    const std::vector<double>& fractions = {1e-3, 1e-4, 1e-5, 1e-6},
                    const std::string& file = "test") {
  Scene scene = parse_scene(text, file, overrides);
  Simulation sim(scene, registry());
  sim.integrate(scene.run.t_end);
  const Eigen::MatrixXd S = sim.state().tangent;
  const auto& names = sim.sensitivity_names();
  EXPECT_EQ(static_cast<std::size_t>(S.cols()), names.size());
  double worst = 0.0;
  for (std::size_t c = 0; c < names.size(); ++c) {
    const auto found = values.find(names[c]);
    if (found == values.end()) {
      ADD_FAILURE() << "no value given for " << names[c];
      continue;
    }
    const double v = found->second;
    const Eigen::VectorXd fd = differenced(
        [&](double h) {
          std::vector<std::string> moved = overrides;  // the same integrator; the key moved
          moved.push_back("run.sensitivities=~");
          moved.push_back(names[c] + "=" + number(v + h));
          return final_state(text, moved, {}, file);
        },
        own_scale ? std::abs(v) : std::max(1.0, std::abs(v)), fractions);
    const double d = relative(S.col(static_cast<Eigen::Index>(c)), fd);
    if (std::getenv("NOETHER_TEST_VERBOSE")) std::printf("%s: relative difference %.2e\n", names[c].c_str(), d);
    worst = std::max(worst, d);
  }
  return worst;
}

const std::map<std::string, double> kElementValues = {
    {"bodies.planet.orbit.a", 1},          {"bodies.planet.orbit.e", 0.3},        {"bodies.planet.orbit.i", 20},
    {"bodies.planet.orbit.Omega", 40},     {"bodies.planet.orbit.omega", 60},     {"bodies.planet.orbit.M", 30}};

const std::vector<std::string> kElementKeys = {
    "run.sensitivities=[bodies.planet.orbit.a, bodies.planet.orbit.e, bodies.planet.orbit.i, "
    "bodies.planet.orbit.Omega, bodies.planet.orbit.omega, bodies.planet.orbit.M]"};

}  // namespace

// The elements' map to z(t0) (Kepler's equation, the rotation by i, Ω, ω, the barycentric
// shift) differenced when the run starts, carried by the LGVI's tangent map: a orbit of e = 0.3
// over half its period.
TEST(Sensitivity, OrbitalElementsAgreeWithDifferencesOfWholeRunsLgvi) {
  EXPECT_LT(worst_column(kElements, kElementKeys, kElementValues), 1e-7);
}

TEST(Sensitivity, OrbitalElementsAgreeWithDifferencesOfWholeRunsRk4) {
  std::vector<std::string> overrides = kElementKeys;
  overrides.push_back("integrator={plugin: rk, method: rk4, step: 0.001}");
  EXPECT_LT(worst_column(kElements, overrides, kElementValues), 1e-7);
}

// With the STM carried too, the sensitivities are the STM times their start, ∂z(t)/∂p =
// M(t) ∂z(t0)/∂p (the tangent's columns split as the output writes them).
TEST(Sensitivity, AreTheStmTimesTheirStart) {
  std::vector<std::string> overrides = kElementKeys;
  overrides.push_back("run.stm=true");
  Scene scene = parse_scene(kElements, "test", overrides);
  Simulation sim(scene, registry());
  const Eigen::Index N = State::tangent_rows(scene.system);
  const Eigen::MatrixXd start = sim.state().tangent;
  ASSERT_EQ(start.cols(), N + 6);
  EXPECT_TRUE(start.leftCols(N).isIdentity(0.0));
  sim.integrate(scene.run.t_end);
  const Eigen::MatrixXd& V = sim.state().tangent;
  const Eigen::MatrixXd expected = V.leftCols(N) * start.rightCols(6);
  EXPECT_LT((V.rightCols(6) - expected).norm(), 1e-12 * V.leftCols(N).norm() * start.rightCols(6).norm());
}

// At a bound of its key (e = 0: a circular orbit) the start is differenced one-sided; against
// one-sided differences of whole runs (second order: (−3 z(0) + 4 z(h) − z(2h)) / 2h).
TEST(Sensitivity, CircularOrbitTakesTheOneSidedDerivative) {
  const std::vector<std::string> circular = {"bodies.planet.orbit.e=0", "run.sensitivities=[bodies.planet.orbit.e]"};
  Scene scene = parse_scene(kElements, "test", circular);
  Simulation sim(scene, registry());
  sim.integrate(scene.run.t_end);
  const Eigen::VectorXd column = sim.state().tangent.col(0);
  const State z0 = final_state(kElements, {"bodies.planet.orbit.e=0"});
  const double h = 1e-5;
  const Eigen::VectorXd fd = (4.0 * State::difference(z0, final_state(kElements, {"bodies.planet.orbit.e=" + number(h)})) -
                              State::difference(z0, final_state(kElements, {"bodies.planet.orbit.e=" + number(2 * h)}))) /
                             (2.0 * h);
  EXPECT_LT(relative(column, fd), 1e-6);
}

// Parameters of the dynamics (docs/equations.md §22): the masses and G move the orbit's start
// (its velocity from the elements, the momenta γ = m v) and every step (the forces, 1/m); against
// whole runs with the key moved, for the LGVI's tangent map, rk4's and cvode's variational
// equations. Keys of the initial state ride along, and the parameters' columns come last.
const std::map<std::string, double> kParameterValues = {
    {"bodies.planet.mass", 1e-3}, {"bodies.star.mass", 1}, {"G", 1}, {"bodies.planet.orbit.e", 0.3}};
const char* kParameterKeys = "run.sensitivities=[bodies.planet.mass, G, bodies.planet.orbit.e, bodies.star.mass]";

TEST(Sensitivity, MassesAndGAgreeWithDifferencesOfWholeRunsLgvi) {
  Scene scene = parse_scene(kElements, "test", {kParameterKeys});
  Simulation sim(scene, registry());
  const std::vector<std::string> order = {"bodies.planet.orbit.e", "bodies.planet.mass", "G", "bodies.star.mass"};
  EXPECT_EQ(sim.sensitivity_names(), order);
  EXPECT_LT(worst_column(kElements, {kParameterKeys}, kParameterValues, true), 1e-7);
}

TEST(Sensitivity, MassesAndGAgreeWithDifferencesOfWholeRunsRk4AndCvode) {
  for (const char* integrator : {"integrator={plugin: rk, method: rk4, step: 0.001}",
                                 "integrator={plugin: cvode, method: adams, rtol: 1e-13, atol: 1e-15}"}) {
    const double worst = worst_column(kElements, {kParameterKeys, integrator}, kParameterValues, true);
    EXPECT_LT(worst, integrator[20] == 'r' ? 1e-7 : 1e-6) << integrator;
  }
}

// Forces beyond the potential (docs/equations.md eq. 33.9): the tide's Love number and time lag
// move the forces alone, the moon's mass and the planet's moment both the potential's forces and
// the tide's; the tidal spin-down example over about one orbit. The forced LGVI's map (orders 2
// and 4: the kicks (33.6)–(33.7) with G^F) and rk4's variational equations (G + G^F) against
// whole runs with the key moved; cvode's sensitivities (CVODES) against rk4's at a 4× finer step
// (whole cvode runs would difference its step selection too). Without G^F the Love number's
// column would be zero.
TEST(Sensitivity, TidesAndMassesOfAForcedRunAgreeWithDifferencesOfWholeRuns) {
  const std::string file = test::source_path("examples/tidal-spin-down.yaml");
  std::ifstream in(file);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::map<std::string, double> values = {{"forces.0.k2", 0.5},
                                                {"forces.0.time_lag", 0.1},
                                                {"bodies.moon.mass", 0.1},
                                                {"bodies.planet.inertia.2", 0.0396}};
  const std::vector<std::string> keys = {
      "run.t_end=8", "run.output_every=8",
      "run.sensitivities=[forces.0.k2, forces.0.time_lag, bodies.moon.mass, bodies.planet.inertia.2]"};
  for (const char* integrator :
       {"integrator.order=2", "integrator.order=4", "integrator={plugin: rk, method: rk4, step: 0.01}"}) {
    if (!kEveryMethod && std::string(integrator) == "integrator.order=4") continue;  // the same kicks, composed
    std::vector<std::string> overrides = keys;
    overrides.push_back(integrator);
    const double worst = worst_column(text, overrides, values, true, {1e-3, 1e-4, 1e-5, 1e-6}, file);
    std::printf("%s: worst column %.3e\n", integrator, worst);
    EXPECT_LT(worst, 1e-6) << integrator;
  }
  auto sensitivities = [&](const std::string& integrator) {
    std::vector<std::string> overrides = keys;
    overrides.push_back(integrator);
    Scene scene = parse_scene(text, file, overrides);
    Simulation sim(scene, registry());
    sim.integrate(scene.run.t_end);
    return Eigen::MatrixXd(sim.state().tangent);
  };
  const Eigen::MatrixXd cvode = sensitivities("integrator={plugin: cvode, method: adams, rtol: 1e-12, atol: 1e-12}");
  const Eigen::MatrixXd rk4 = sensitivities("integrator={plugin: rk, method: rk4, step: 0.0025}");
  ASSERT_EQ(cvode.cols(), 4);
  for (Eigen::Index c = 0; c < cvode.cols(); ++c) {
    const double d = relative(cvode.col(c), rk4.col(c));
    std::printf("cvode against rk4 at h = 0.0025, column %ld: %.2e\n", static_cast<long>(c), d);
    EXPECT_LT(d, 1e-8) << c;
  }
}

// Rigid bodies: KW4's ellipsoids at order 4 (the series' inertia integrals move with the
// semi-axes and the density, the inertias with both), 120 LGVI steps, and rk4's variational
// equations with the same step.
TEST(Sensitivity, ShapesAndMassesOfKw4AgreeWithDifferencesOfWholeRuns) {
  const std::string text = [] {
    std::ifstream in(test::source_path("examples/kw4-ellipsoids.yaml"));
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();
  const std::vector<std::string> overrides = {
      "run.t_end=7200", "run.output_every=3600",
      "run.sensitivities=[bodies.beta.shape.ellipsoid.semi_axes, bodies.beta.mass, bodies.alpha.mass]"};
  const std::map<std::string, double> values = {{"bodies.beta.shape.ellipsoid.semi_axes.0", 285},
                                                {"bodies.beta.shape.ellipsoid.semi_axes.1", 231.5},
                                                {"bodies.beta.shape.ellipsoid.semi_axes.2", 174.5},
                                                {"bodies.beta.mass", 1.35e11},
                                                {"bodies.alpha.mass", 2.353e12}};
  EXPECT_LT(worst_column(text, overrides, values, true), 1e-6);
  std::vector<std::string> rk4 = overrides;
  rk4.push_back("integrator={plugin: rk, method: rk4, step: 60}");
  EXPECT_LT(worst_column(text, rk4, values, true), 1e-6);
}

// A polyhedron's shape: Hou et al.'s octahedra (SI units, order 6), B stretched along its body
// axes by scale: [1.1, 0.95, 1] (at fixed density: mass, inertia and the series' inertia
// integrals move together), 120 LGVI steps of 300 s; each scale factor of B, one of A, and B's
// density, against differences of whole runs with the factor moved. The stretched shape itself:
// its volume is the product of the factors times the mesh's, its inertia the stretched moments.
TEST(Sensitivity, APolyhedronsScaleAgreesWithDifferencesOfWholeRuns) {
  const std::string text = [] {
    std::ifstream in(test::source_path("examples/octahedra-hou.yaml"));
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();
  // The scene's shape paths are relative to its folder: the text is parsed as that file.
  const std::vector<std::string> overrides = {
      "run.t_end=36000", "run.output_every=18000", "bodies.B.shape.polyhedron.scale=[1.1, 0.95, 1]",
      "bodies.A.shape.polyhedron.scale=[1, 1, 1]",
      "run.sensitivities=[bodies.B.shape.polyhedron.scale, bodies.A.shape.polyhedron.scale.2, bodies.B.density]"};
  const std::map<std::string, double> values = {{"bodies.B.shape.polyhedron.scale.0", 1.1},
                                                {"bodies.B.shape.polyhedron.scale.1", 0.95},
                                                {"bodies.B.shape.polyhedron.scale.2", 1.0},
                                                {"bodies.A.shape.polyhedron.scale.2", 1.0},
                                                {"bodies.B.density", 2000}};
  const double worst = worst_column(text, overrides, values, true, {1e-3, 1e-4, 1e-5, 1e-6}, test::source_path("examples/octahedra-hou.yaml"));
  std::printf("octahedra, polyhedron scale and density: worst column %.2e\n", worst);
  EXPECT_LT(worst, 1e-6);
  const Scene plain = load_scene(test::source_path("examples/octahedra-hou.yaml"));
  const Scene stretched = load_scene(test::source_path("examples/octahedra-hou.yaml"),
                                     {"bodies.B.shape.polyhedron.scale=[1.1, 0.95, 1]"});
  const Solid& b0 = *plain.system.body(1).solid;
  const Solid& b1 = *stretched.system.body(1).solid;
  EXPECT_NEAR(b1.volume, 1.1 * 0.95 * b0.volume, 1e-12 * b0.volume);
  // Second moments ∫x_i x_j dm scale by s_i s_j (and the mass by s_x s_y s_z): J = tr(S) I − S.
  const Vec3 f(1.1, 0.95, 1.0);
  const Mat3 S0 = 0.5 * b0.inertia.trace() * Mat3::Identity() - b0.inertia;
  const Mat3 S1 = (f.prod() * f.asDiagonal() * S0 * f.asDiagonal()).eval();
  const Mat3 J1 = S1.trace() * Mat3::Identity() - S1;
  EXPECT_LT((b1.inertia - J1).cwiseAbs().maxCoeff(), 1e-12 * J1.cwiseAbs().maxCoeff());
  EXPECT_EQ(b1.stretch, f);
}

// The LGVI paper's dumbbells (sphere clusters) before their close approach, 5000 steps: alpha's
// transverse principal moments (the kinetic part alone: the clusters do not depend on them),
// beta's mass (clusters and kinetic part) and G; with the LGVI's tangent map and rk4's
// variational equations. The run depends on the small moments (0.0238, spun at 9 rad/s) so
// nonlinearly that whole-run differences agree to 1e-6 only for steps ≤ 1e-7 of the moment:
// the fractions go down to 1e-8. (The moment about the dumbbell's own axis is left out: no
// torque acts about that axis, so the state does not depend on it and its column is round-off.)
TEST(Sensitivity, InertiasMassesAndGOfTheDumbbellsAgreeWithDifferencesOfWholeRuns) {
  const std::string text = [] {
    std::ifstream in(test::source_path("examples/dumbbells.yaml"));
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();
  const std::vector<std::string> overrides = {"run.t_end=1", "run.output_every=0.5",
                                              "run.sensitivities=[bodies.alpha.inertia.1, bodies.alpha.inertia.2, "
                                              "bodies.beta.mass, G]"};
  const std::map<std::string, double> values = {{"bodies.alpha.inertia.1", 0.0238},
                                                {"bodies.alpha.inertia.2", 0.0238},
                                                {"bodies.beta.mass", 3},
                                                {"G", 0.2222222222222222}};
  const std::vector<double> fractions = {1e-5, 1e-6, 1e-7, 1e-8};
  EXPECT_LT(worst_column(text, overrides, values, true, fractions), 1e-6);
  std::vector<std::string> rk4 = overrides;
  rk4.push_back("integrator={plugin: rk, method: rk4, step: 0.0002}");
  EXPECT_LT(worst_column(text, rk4, values, true, fractions), 1e-6);
}

// A rigid body's spin, attitude and another body's position (the dumbbells, LGVI, 5000 steps):
// the attitude's columns are the right rotations R exp(S(θ)) of the state itself.
TEST(Sensitivity, RigidBodyKeysAgreeWithDifferencesOfWholeRuns) {
  const std::string text = [] {
    std::ifstream in(test::source_path("examples/dumbbells.yaml"));
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();
  const std::vector<std::string> base = {"run.t_end=1", "run.output_every=0.5"};
  std::vector<std::string> overrides = base;
  overrides.push_back("run.sensitivities=[bodies.alpha.angular_velocity.2, bodies.beta.position.0, bodies.alpha.attitude]");
  Scene scene = parse_scene(text, "test", overrides);
  Simulation sim(scene, registry());
  sim.integrate(scene.run.t_end);
  const Eigen::MatrixXd S = sim.state().tangent;
  const std::vector<std::string> expected = {"bodies.alpha.angular_velocity.2", "bodies.beta.position.0",
                                             "bodies.alpha.attitude.x", "bodies.alpha.attitude.y",
                                             "bodies.alpha.attitude.z"};
  ASSERT_EQ(sim.sensitivity_names(), expected);
  auto moved_key = [&](const std::string& key, double v) {
    return [&, key, v](double h) {
      std::vector<std::string> o = base;
      o.push_back(key + "=" + number(v + h));
      return final_state(text, o);
    };
  };
  double worst = relative(S.col(0), differenced(moved_key("bodies.alpha.angular_velocity.2", 9.0), 9.0));
  worst = std::max(worst, relative(S.col(1), differenced(moved_key("bodies.beta.position.0", -0.33), 1.0)));
  for (int a = 0; a < 3; ++a) {
    const Eigen::VectorXd fd = differenced(
        [&](double h) {
          return final_state(text, base, [&](State& z) { z.R[0] = z.R[0] * exp_so3(h * Vec3::Unit(a)); });
        },
        1.0);
    worst = std::max(worst, relative(S.col(2 + a), fd));
  }
  EXPECT_LT(worst, 1e-7);
}

// Keys that are not of an initial state, or that the scene cannot take, are refused by name
// before anything runs; so are a method without a tangent map and set_state.
TEST(Sensitivity, RefusesWhatItCannotDerive) {
  auto refusal = [](const std::string& keys, const std::vector<std::string>& more = {}) -> std::string {
    std::vector<std::string> overrides = {"run.sensitivities=" + keys};
    overrides.insert(overrides.end(), more.begin(), more.end());
    try {
      Scene scene = parse_scene(kElements, "test", overrides);
      Simulation sim(scene, registry());
    } catch (const SceneError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(refusal("[bodies.planet.density]").find("gives its mass, not a density"), std::string::npos);
  EXPECT_NE(refusal("[bodies.planet.shape.ellipsoid.semi_axes]").find("has no ellipsoid shape"), std::string::npos);
  EXPECT_NE(refusal("[bodies.planet.shape.polyhedron.scale]").find("has no polyhedron shape"), std::string::npos);
  EXPECT_NE(refusal("[bodies.planet.inertia]").find("is a point mass: it has no inertia"), std::string::npos);
  EXPECT_NE(refusal("[integrator.step]").find("not a key sensitivities are available to"), std::string::npos);
  try {
    Scene kw4 = load_scene(test::source_path("examples/kw4-ellipsoids.yaml"), {"run.sensitivities=[G]"});
    Simulation sim(kw4, registry());
    ADD_FAILURE() << "G was accepted in a scene with units";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("G follows from the scene's declared units"), std::string::npos) << e.what();
  }
  EXPECT_NE(refusal("[bodies.comet.velocity]").find("names no body of the scene (star, planet)"), std::string::npos);
  EXPECT_NE(refusal("[bodies.planet.position]").find("given by orbit"), std::string::npos);
  EXPECT_NE(refusal("[bodies.star.orbit.e]").find("given by position and velocity"), std::string::npos);
  EXPECT_NE(refusal("[bodies.planet.orbit.nu]").find("gives its anomaly as M"), std::string::npos);
  EXPECT_NE(refusal("[bodies.star.angular_velocity]").find("is a point mass"), std::string::npos);
  EXPECT_NE(refusal("[bodies.star.velocity, bodies.star.velocity.1]").find("asked for twice"), std::string::npos);
  const std::string hybrid = refusal("[bodies.star.velocity]", {"integrator={plugin: jm-hybrid, step: 0.01, Kc: 1}"});
  EXPECT_NE(hybrid.find("integrator 'jm-hybrid' cannot carry sensitivities"), std::string::npos) << hybrid;
  try {  // a model given in code cannot be made again at p ± δ
    Scene scene = parse_scene(kElements, "test", {"run.sensitivities=[bodies.planet.mass]"});
    Simulation sim(scene, registry(), RunOptions{}, make_scene_potential(scene, registry()));
    ADD_FAILURE() << "a mass was accepted with a model given in code";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("the model is given in code"), std::string::npos) << e.what();
  }

  Scene scene = parse_scene(kElements, "test", {"run.sensitivities=[bodies.star.velocity]"});
  Simulation sim(scene, registry());
  State z = sim.state();
  z.tangent.resize(0, 0);
  try {
    sim.set_state(z);
    ADD_FAILURE() << "set_state was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("carries sensitivities"), std::string::npos) << e.what();
  }
}

// A parameter whose stencil (p ± δ, p ± 2δ) changes what a tolerance chooses is refused, naming
// the choice: the models at the stencil would not be the run's model. The KW4 ellipsoids with the
// tolerance set to the estimated error of the order it chose at 1e-6 — a choice on its edge,
// which Beta's semi-axes moved by 1e-4 of themselves tip over; at 1e-6 itself they do not.
TEST(Sensitivity, RefusesAParameterThatChangesWhatAToleranceChose) {
  const auto kw4 = test::source_path("examples/kw4-ellipsoids.yaml");
  const Scene chosen = load_scene(kw4, {"potential={plugin: mutual-series, tolerance: 1e-6}"});
  const std::vector<PairModel> models = Simulation(chosen, registry()).summary().pair_models;
  ASSERT_EQ(models.size(), 1u);
  char edge[64];
  std::snprintf(edge, sizeof edge, "%.17g", models[0].estimated_error);
  const std::string keys = "run.sensitivities=[bodies.beta.shape.ellipsoid.semi_axes]";
  EXPECT_NO_THROW(Simulation(load_scene(kw4, {"potential={plugin: mutual-series, tolerance: 1e-6}", keys}), registry()));
  try {
    Simulation sim(load_scene(kw4, {std::string("potential={plugin: mutual-series, tolerance: ") + edge + "}", keys}),
                   registry());
    ADD_FAILURE() << "a stencil that changes the chosen order was accepted";
  } catch (const SceneError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("the model's choices (alpha–beta: series order " + std::to_string(models[0].order) + ") change"),
              std::string::npos) << what;
    EXPECT_NE(what.find("fix the model's order instead of a tolerance"), std::string::npos) << what;
  }
}
