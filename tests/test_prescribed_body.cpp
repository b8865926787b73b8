// A body on a prescribed conic (docs/forces.md, "Prescribed bodies"; docs/equations.md §35): the
// universal-anomaly conic against an integrated two-body orbit, the prescribed body's force and
// torque against mutual-series with the same body integrated, and a flyby of a binary — the
// prescribed planet against the integrated one, E − W conserved while the flyby does work.
#include "broken_run.hpp"
#include "test_support.hpp"

#include <noether/diagnostics.hpp>
#include <noether/kepler_orbit.hpp>
#include <noether/particles.hpp>
#include <noether/simulation.hpp>

#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <optional>
#include <sstream>

using namespace noether;
using test::registry;

// The conic by Lagrange's f and g in the universal anomaly (35.1)–(35.3) against the same two
// bodies integrated by rkf78 at rtol 1e-13: an ellipse (e ≈ 0.6) over 3 periods and a hyperbola
// (e ≈ 2) through its pericentre, forwards and backwards.
TEST(KeplerOrbit, IsTheIntegratedTwoBodyOrbit) {
  for (const double speed : {1.2, 2.0}) {  // at r = 1 about μ = 1.001: bound, then hyperbolic
    SCOPED_TRACE(speed);
    std::ostringstream yaml;
    yaml.precision(17);
    yaml << "G: 1\nbodies:\n  - {name: sun, mass: 1, position: [0, 0, 0], velocity: [0, 0, 0]}\n"
         << "  - {name: comet, mass: 1.0e-3, position: [1, 0.2, -0.1], velocity: [0.1, " << speed << ", 0.3]}\n"
         << "potential: {plugin: point-mass}\nintegrator: {plugin: rk, method: rkf78, rtol: 1.0e-13, atol: 1.0e-15}\n"
         << "run: {t_end: 15, output_every: 15}\n";
    const Scene scene = parse_scene(yaml.str(), "two-body");
    const Vec3 r0 = scene.initial.x.col(1) - scene.initial.x.col(0);
    const Vec3 v0 = scene.initial.p.col(1) / 1e-3 - scene.initial.p.col(0);
    const KeplerOrbit orbit(r0, v0, 1.001, 0.0);
    Simulation sim(scene, registry());
    double worst = 0.0;
    for (const double t : {0.5, 3.0, 7.5, 15.0}) {
      sim.integrate(t);
      const State& s = sim.state();
      Vec3 r, v;
      orbit.state(t, r, v);
      const Vec3 r_int = s.x.col(1) - s.x.col(0);
      worst = std::max(worst, (r - r_int).norm() / r_int.norm());
      // Backwards from t to 0 returns the start.
      const KeplerOrbit back(r, v, 1.001, t);
      Vec3 r_back, v_back;
      back.state(0.0, r_back, v_back);
      EXPECT_LT((r_back - r0).norm(), 1e-12 * (1 + r.norm()));
      EXPECT_LT((v_back - v0).norm(), 1e-12 * (1 + v.norm()));
    }
    std::printf("1/a = %.4f: conic against the integrated orbit %.2e\n", orbit.inverse_semi_major_axis(), worst);
    EXPECT_LT(worst, 1e-10);
  }
}

namespace {

const char* kRock = "  - {name: rock, mass: 2, shape: {ellipsoid: {semi_axes: [0.3, 0.2, 0.1]}}, position: [0, 0, 0], "
                    "velocity: [0, 0, 0], attitude: {euler_angles: [30, 20, 10]}}\n";

// The rock (above) and a planet of mass 5 prescribed on a conic about it: `model` is the force's
// order or tolerance, e.g. "order: 4".
Scene rock_and_prescribed_planet(const std::string& model, const Vec3& x = Vec3(1.5, -1, 0.7),
                                 const Vec3& v = Vec3(0, 1, 0)) {
  std::ostringstream yaml;
  yaml.precision(17);
  yaml << "G: 1\nbodies:\n" << kRock << "potential: {plugin: point-mass}\n"
       << "forces: [{plugin: prescribed-body, name: planet, mass: 5, center: origin, mu: 7, position: [" << x.x() << ", "
       << x.y() << ", " << x.z() << "], velocity: [" << v.x() << ", " << v.y() << ", " << v.z() << "], " << model << "}]\n"
       << "integrator: {plugin: lgvi, step: 0.01}\nrun: {t_end: 1, output_every: 1}\n";
  return parse_scene(yaml.str(), "prescribed");
}

// The force and torque on the rock where the scene starts.
std::pair<Vec3, Vec3> rock_forces(const Scene& scene) {
  const auto force = registry().make_force("prescribed-body", scene.system, scene.forces[0].params);
  Forces f;
  f.resize(scene.system);
  auto ws = force->make_workspace();
  force->evaluate(scene.initial, f, *ws);
  return {f.f.col(0), f.M.col(0)};
}

}  // namespace

// A prescribed body against two independent formulations: at order 2, MacCullagh's quadrupole
// written out (35.5) — U2 = −(G M / 2)(tr J / d³ − 3 dᵀ J_in d / d⁵), its gradient and the
// gravity-gradient torque 3 G M (d_b × J d_b) / d⁵; at order 4, the same planet integrated in
// mutual-series of order 4.
TEST(PrescribedBody, ForceAndTorqueAreMacCullaghsAndTheIntegratedSeries) {
  const Scene prescribed = rock_and_prescribed_planet("order: 2");
  const auto [F, M] = rock_forces(prescribed);
  const double GM = 5.0;
  const Mat3& R = prescribed.initial.R[0];
  const Mat3& J = prescribed.system.body(0).inertia;
  const Vec3 d(1.5, -1, 0.7), db = R.transpose() * d, Jd = R * J * db;
  const double dn = d.norm(), d5 = std::pow(dn, 5), dJd = db.dot(J * db);
  const Vec3 F0 = GM * 2.0 * d / (dn * dn * dn) - 0.5 * GM * (-3.0 * J.trace() * d / d5 - 6.0 * Jd / d5 + 15.0 * dJd * d / (d5 * dn * dn));
  const Vec3 M0 = (3.0 * GM / d5) * db.cross(J * db);
  std::printf("order 2 against MacCullagh's: force %.2e, torque %.2e\n", (F - F0).norm() / F0.norm(),
              (M - M0).norm() / M0.norm());
  EXPECT_LT((F - F0).norm(), 1e-13 * F0.norm());
  EXPECT_LT((M - M0).norm(), 1e-13 * M0.norm());

  const Scene integrated = parse_scene(std::string("G: 1\nbodies:\n") + kRock +
                                           "  - {name: planet, mass: 5, position: [1.5, -1, 0.7], velocity: [0, 1, 0]}\n"
                                           "potential: {plugin: mutual-series, order: 4}\nintegrator: {plugin: lgvi, step: 0.01}\n"
                                           "run: {t_end: 1, output_every: 1}\n",
                                       "integrated");
  Forces series;
  series.resize(integrated.system);
  make_scene_potential(integrated, registry())->evaluate(integrated.initial, series);
  const auto [F4, M4] = rock_forces(rock_and_prescribed_planet("order: 4"));
  const double df = (F4 - Vec3(series.f.col(0))).norm() / series.f.col(0).norm();
  const double dM = (M4 - Vec3(series.M.col(0))).norm() / series.M.col(0).norm();
  std::printf("order 4 against mutual-series order 4 with the planet integrated: force %.2e, torque %.2e\n", df, dM);
  EXPECT_LT(df, 1e-13);
  EXPECT_LT(dM, 1e-13);
  EXPECT_GT((F4 - F).norm(), 1e-6 * F.norm());  // order 4 is not order 2 here
}

// With a tolerance, each rigid body's order is the lowest that meets it at the closest the conic
// comes (35.6): a hyperbola whose periapsis 1.5 (5 rock radii) is at the epoch, so the first evaluation is the
// closest; the chosen order's error against order 12 there (force relative to |F|, torque to d |F|)
// stays within each tolerance and grows as the tolerance loosens. A min_separation that the conic
// breaks stops the run, naming the remedy.
TEST(PrescribedBody, ToleranceChoosesTheOrderAtTheClosestApproach) {
  const Vec3 x(1.5, 0, 0), v(0, 5, 0.5);  // v² > 2 μ / r: a hyperbola, at periapsis
  const auto [F12, M12] = rock_forces(rock_and_prescribed_planet("order: 12", x, v));
  double previous = 0.0;
  for (const double tolerance : {1e-7, 1e-5, 1e-3}) {
    std::ostringstream model;
    model << "tolerance: " << tolerance;
    const auto [F, M] = rock_forces(rock_and_prescribed_planet(model.str(), x, v));
    const double error = std::max((F - F12).norm() / F12.norm(), (M - M12).norm() / (x.norm() * F12.norm()));
    std::printf("tolerance %.0e: error against order 12 at the periapsis %.2e\n", tolerance, error);
    EXPECT_LE(error, tolerance);
    EXPECT_GT(error, previous);
    previous = error;
  }
  try {
    const Scene scene = rock_and_prescribed_planet("tolerance: 1.0e-9, min_separation: 5", x, v);
    rock_forces(scene);
    FAIL() << "a min_separation the conic breaks was not caught";
  } catch (const IntegrationError& e) {
    EXPECT_NE(std::string(e.what()).find("give a smaller min_separation"), std::string::npos) << e.what();
  }
  try {
    rock_forces(rock_and_prescribed_planet("tolerance: 1.0e-9", Vec3(0.25, 0, 0), Vec3(0, 12, 0)));
    FAIL() << "a conic through the body's sphere was not refused";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("where the series need not converge"), std::string::npos) << e.what();
  }
  try {
    rock_forces(rock_and_prescribed_planet("tolerance: 1.0e-9, order: 4"));
    FAIL() << "order and tolerance together were accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("not both"), std::string::npos) << e.what();
  }
}

namespace {

// The rock moving at 1 along x from the origin, and the planet on a hyperbola about the origin at
// its periapsis 3 at t = 0: the closest the planet is expected to come to the rock (35.6) is
// 0.9 (3 − 0) from the start and about 0.9 (3 − 1) from t = 1, so the two may choose different
// orders (the planet itself stays more than 2.7 from the rock until t = 2).
Scene moving_rock_and_planet(double tolerance, const std::string& integrator = "{plugin: lgvi, step: 0.01}") {
  std::ostringstream yaml;
  yaml.precision(17);
  yaml << "G: 1\nbodies:\n  - {name: rock, mass: 2, shape: {ellipsoid: {semi_axes: [0.3, 0.2, 0.1]}}, "
       << "position: [0, 0, 0], velocity: [1, 0, 0], attitude: {euler_angles: [30, 20, 10]}, angular_velocity: [0, 0, 2]}\n"
       << "potential: {plugin: point-mass}\n"
       << "forces: [{plugin: prescribed-body, name: planet, mass: 5, center: origin, mu: 7, position: [0, 3, 0], "
       << "velocity: [2.5, 0, 0], tolerance: " << tolerance << "}]\n"
       << "integrator: " << integrator << "\nrun: {t_end: 2, output_every: 0.5}\n";
  return parse_scene(yaml.str(), "moving-rock");
}

int chosen_order(const Scene& scene, const State& at) {
  const auto force = registry().make_force("prescribed-body", scene.system, scene.forces[0].params, &at);
  const std::vector<PairModel> models = force->pair_models();
  EXPECT_EQ(models.size(), 1u);
  return models.empty() ? -1 : models[0].order;
}

}  // namespace

// A tolerance chooses each body's order once, at the scene's initial state, and the summary and
// the output report it: a run continued from t = 1 (saved and loaded, or resumed from its output)
// keeps the order chosen at t = 0 and ends bit for bit where the run from t = 0 ends — for a
// tolerance where a choice made at t = 1 would take another order (without it the continued run
// would differ by ~1e-5). Bit for bit also needs the fixed-step clock t0 + k h kept across the
// break (step_clock.hpp): the planet's conic depends on the time, and a clock restarted at t = 1
// differs from the uninterrupted one in the last bits (by ~1e-19 in the state at t = 2 without it),
// for the LGVI and for rk4.
TEST(PrescribedBody, ToleranceChoosesOnceAtTheStartAndReportsIt) {
  double tolerance = 0.0;
  int at_start = -1, at_break = -1;
  for (double t = 1e-3; t > 1e-12 && tolerance == 0.0; t /= 1.5) {
    const Scene scene = moving_rock_and_planet(t);
    State later = scene.initial;
    later.x(0, 0) = 1.0;  // about where the rock is at t = 1
    at_start = chosen_order(scene, scene.initial), at_break = chosen_order(scene, later);
    if (at_start != at_break) tolerance = t;
  }
  ASSERT_GT(tolerance, 0.0) << "no tolerance in 1e-3 … 1e-12 chooses differently at t = 0 and t = 1";
  std::printf("tolerance %.3g: order %d chosen at t = 0, %d at t = 1\n", tolerance, at_start, at_break);
  for (const std::string integrator : {"{plugin: lgvi, step: 0.01}", "{plugin: rk, method: rk4, step: 0.01}"}) {
    SCOPED_TRACE(integrator);
    const Scene scene = moving_rock_and_planet(tolerance, integrator);
    PluginRegistry& r = registry();
    Simulation whole(scene, r);
    whole.integrate(2.0);
    const RunSummary summary = whole.finish();
    ASSERT_EQ(summary.pair_models.size(), 1u);
    const PairModel& m = summary.pair_models[0];
    EXPECT_EQ(m.body_a, "rock");
    EXPECT_EQ(m.body_b, "prescribed-body planet");
    EXPECT_EQ(m.order, at_start);
    EXPECT_EQ(m.model, "series order " + std::to_string(at_start));
    EXPECT_DOUBLE_EQ(m.separation, 0.9 * 3.0);
    EXPECT_LE(m.estimated_error, tolerance);
    EXPECT_NE(format_summary(summary).find("pair rock–prescribed-body planet"), std::string::npos) << format_summary(summary);

    const test::BrokenRun broken(scene, r, 1.0, "prescribed");
    {  // the output's record of the choice
      const hid_t f = H5Fopen(broken.output.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
      const hid_t g = H5Gopen2(f, "/parameters/pair_models/rock–prescribed-body planet", H5P_DEFAULT);
      ASSERT_GE(g, 0);
      int order = -1;
      const hid_t a = H5Aopen(g, "order", H5P_DEFAULT);
      H5Aread(a, H5T_NATIVE_INT, &order);
      H5Aclose(a), H5Gclose(g), H5Fclose(f);
      EXPECT_EQ(order, at_start);
    }
    auto expect_same_end = [&](Simulation& continued, const char* how) {
      continued.integrate(2.0);
      EXPECT_EQ((continued.state().x - whole.state().x).cwiseAbs().maxCoeff(), 0.0) << how;
      EXPECT_EQ((continued.state().R[0] - whole.state().R[0]).cwiseAbs().maxCoeff(), 0.0) << how;
      EXPECT_EQ((continued.state().Pi - whole.state().Pi).cwiseAbs().maxCoeff(), 0.0) << how;
      const RunSummary s = continued.finish();
      ASSERT_EQ(s.pair_models.size(), 1u) << how;
      EXPECT_EQ(s.pair_models[0].order, at_start) << how;
    };
    expect_same_end(*Simulation::load(broken.saved, r), "saved and loaded");
    expect_same_end(*Simulation::resume(broken.output, r, RunOptions{}, 2.0), "resumed");
  }
}

namespace {

// A binary of two ellipsoids (1 and 0.1, 1 apart, circular) and a planet 1000 times heavier on a
// hyperbola about the binary's barycentre (v∞ ≈ 10, closest approach ≈ 30: its tide is 7 % of the
// binary's own pull there), integrated (`prescribed` false: a third body, mutual-series of order 2)
// or prescribed; from 200 before closest approach to about as far after.
const double kPlanet = 1000, kAlpha = 1, kBeta = 0.1;
const Vec3 kPlanetFromBarycentre(-200, 38.7, 3), kPlanetVelocity(10.5, 0, 0.5);

Scene flyby(bool planet, bool prescribed, const std::string& integrator = "{plugin: lgvi, step: 0.01}",
            const std::string& particles = "") {
  const double vb = std::sqrt((kAlpha + kBeta) / 1.0);
  const Vec3 barycentre(kBeta / (kAlpha + kBeta), 0, 0), barycentre_velocity(0, kBeta * vb / (kAlpha + kBeta), 0);
  std::ostringstream yaml;
  yaml.precision(17);
  yaml << "G: 1\nbodies:\n"
       << "  - {name: alpha, mass: " << kAlpha << ", shape: {ellipsoid: {semi_axes: [0.3, 0.25, 0.2]}}, "
       << "position: [0, 0, 0], velocity: [0, 0, 0], angular_velocity: [0, 0, 3]}\n"
       << "  - {name: beta, mass: " << kBeta << ", shape: {ellipsoid: {semi_axes: [0.12, 0.1, 0.08]}}, "
       << "position: [1, 0, 0], velocity: [0, " << vb << ", 0], angular_velocity: [0, 0, " << vb << "]}\n";
  const Vec3 x = barycentre + kPlanetFromBarycentre, v = barycentre_velocity + kPlanetVelocity;
  if (planet && !prescribed)
    yaml << "  - {name: planet, mass: " << kPlanet << ", position: [" << x.x() << ", " << x.y() << ", " << x.z()
         << "], velocity: [" << v.x() << ", " << v.y() << ", " << v.z() << "]}\n";
  yaml << "potential: {plugin: mutual-series, order: 2}\n";
  if (planet && prescribed)
    yaml << "forces: [{plugin: prescribed-body, name: planet, mass: " << kPlanet << ", position: ["
         << kPlanetFromBarycentre.x() << ", " << kPlanetFromBarycentre.y() << ", " << kPlanetFromBarycentre.z()
         << "], velocity: [" << kPlanetVelocity.x() << ", " << kPlanetVelocity.y() << ", " << kPlanetVelocity.z()
         << "]}]\n";
  yaml << "integrator: " << integrator << "\nrun: {t_end: 40, output_every: 1}\n";
  if (!particles.empty()) yaml << "particles: " << particles << "\n";
  return parse_scene(yaml.str(), "flyby");
}

struct Outcome {
  Vec3 separation, velocity, spin_alpha, spin_beta;
  RunSummary summary;
  Eigen::Matrix3Xd particles;  // the particles' positions relative to alpha at the end
  std::vector<std::string> particle_fields;
};

Outcome run(const Scene& scene) {
  Simulation sim(scene, registry());
  sim.integrate(scene.run.t_end);
  const State s = sim.state();
  Outcome o{s.x.col(1) - s.x.col(0), s.p.col(1) / kBeta - s.p.col(0) / kAlpha,
            s.R[0] * scene.system.body(0).inertia_inverse * Vec3(s.Pi.col(0)),
            s.R[1] * scene.system.body(1).inertia_inverse * Vec3(s.Pi.col(1)), sim.finish()};
  if (const ParticleSwarm* swarm = sim.particles()) {
    o.particles = swarm->positions().colwise() - Vec3(s.x.col(0));
    o.particle_fields = swarm->fields();
  }
  return o;
}

}  // namespace

// The flyby changes the binary's relative state by 0.24 and beta's spin by 0.07; the prescribed
// planet gives the integrated planet's changes to the planet's own back-reaction (the binary's
// pull on the planet beyond its barycentre's, which bends the integrated planet's path off the
// conic): 1.2e-5 and 9e-6 of them. E − W stays at E0 to 2.6e-7 while the flyby does work
// W = 12.5 (mostly on the binary's motion as a whole).
TEST(PrescribedBody, FlybyIsTheIntegratedPlanetsToItsBackReaction) {
  const Outcome alone = run(flyby(false, false));
  const Outcome integrated = run(flyby(true, false));
  const Outcome prescribed = run(flyby(true, true));
  const double change = (integrated.separation - alone.separation).norm() + (integrated.velocity - alone.velocity).norm();
  const double difference =
      (prescribed.separation - integrated.separation).norm() + (prescribed.velocity - integrated.velocity).norm();
  const double spin_change = (integrated.spin_beta - alone.spin_beta).norm();
  const double spin_difference = (prescribed.spin_beta - integrated.spin_beta).norm();
  ASSERT_EQ(prescribed.summary.forces.size(), 1u);
  const double W = prescribed.summary.forces[0].work;
  std::printf("flyby: the binary's relative state changes by %.3e, prescribed − integrated %.3e (%.2e of it); beta's "
              "spin changes by %.3e, difference %.3e (%.2e); W %.4e, max |E - W - E0| %.3e\n",
              change, difference, difference / change, spin_change, spin_difference, spin_difference / spin_change, W,
              prescribed.summary.max_abs_energy_error);
  EXPECT_GT(change, 1e-2);
  EXPECT_LT(difference, 1e-3 * change);
  EXPECT_LT(spin_difference, 1e-3 * spin_change);
  EXPECT_GT(std::abs(W), 1e-3 * std::abs(prescribed.summary.initial.energy));
  EXPECT_LT(prescribed.summary.max_abs_energy_error, 1e-6 * std::abs(W));
}

// The LGVI's relative frame takes the prescribed planet as the inertial frame does: its kicks in the
// reduced momenta (docs/equations.md (33.11)) are the inertial kicks in other variables — an
// external force, which moves the binary as a whole (body 2's x2, γ2) as well as its relative
// motion. The flyby above in both frames, each form: the same run to round-off (measured: 7e-12 of
// the separation and velocity, 4e-13 of beta's spin, 4e-15 of the planet's work).
TEST(PrescribedBody, FlybyInTheRelativeFrameIsTheInertialFramesMap) {
  for (const std::string form : {"hamiltonian", "lagrangian"}) {
    const Outcome inertial = run(flyby(true, true, "{plugin: lgvi, step: 0.01, form: " + form + "}"));
    const Outcome relative = run(flyby(true, true, "{plugin: lgvi, step: 0.01, frame: relative, form: " + form + "}"));
    const double dx = (relative.separation - inertial.separation).norm() / inertial.separation.norm();
    const double dv = (relative.velocity - inertial.velocity).norm() / inertial.velocity.norm();
    const double dw = (relative.spin_beta - inertial.spin_beta).norm() / inertial.spin_beta.norm();
    const double dW = std::abs(relative.summary.forces[0].work - inertial.summary.forces[0].work) /
                      std::abs(inertial.summary.forces[0].work);
    std::printf("%s form, relative vs inertial frame through the flyby: separation %.2e, velocity %.2e, beta's spin "
                "%.2e, the planet's work %.2e\n",
                form.c_str(), dx, dv, dw, dW);
    EXPECT_LT(std::max({dx, dv, dw}), 1e-10) << form;  // measured ≤ 7.2e-12 over the 4000 steps
    EXPECT_LT(dW, 1e-11) << form;
  }
}

// Why the relative frame is there: a binary far from the origin keeps its mutual orbit to its own
// size's precision. KW4's ellipsoids about the Sun (prescribed, 1 au; a day of 60 s steps), run
// where they are and moved by 2^37 m ≈ 0.92 au along x (positions on a 2^-15 m grid, so that the
// move is exact and both start from the same mutual state). In the inertial frame every step of
// the moved run rounds its positions to ulp(2^37 m) = 2^-15 m, and the separation accumulates
// those roundings; in the relative frame, whose X is the separation itself, the moved run's
// separation is the unmoved one's to the rounding of its output alone (x1 = x2 + R2 X, one ulp).
TEST(PrescribedBody, RelativeFrameKeepsAFarBinarysMutualOrbit) {
  const double grid = std::ldexp(1.0, -15), shift = std::ldexp(1.0, 37);
  auto on_grid = [&](double v) { return std::round(v / grid) * grid; };
  auto scene = [&](double dx, const std::string& frame) {
    std::ostringstream yaml;
    yaml.precision(17);
    yaml << "units: SI\nG: 6.674e-11\nbodies:\n"
         << "  - {name: alpha, mass: 2.353e12, shape: {ellipsoid: {semi_axes: [766, 747.5, 673.5]}}, position: ["
         << on_grid(106.7776748392283) + dx << ", " << on_grid(-79.91484525723472) << ", " << on_grid(36.21423834405145)
         << "], velocity: [-0.006935245176848875, -0.01120679059485531, -0.004281746382636655], "
         << "angular_velocity: [0, 0, 6.313333333333333e-4]}\n"
         << "  - {name: beta, mass: 1.35e11, shape: {ellipsoid: {semi_axes: [285, 231.5, 174.5]}}, position: ["
         << on_grid(-1861.095325160772) + dx << ", " << on_grid(1392.886154742765) << ", " << on_grid(-631.2007616559484)
         << "], velocity: [0.1208787548231511, 0.1953302094051447, 0.07462925361736333], "
         << "angular_velocity: [0, 0, 1.003055555555556e-4]}\n"
         << "potential: {plugin: mutual-series, order: 4}\n"
         << "forces: [{plugin: prescribed-body, name: sun, mass: 1.989e30, position: [-1.495978707e11, 0, 0], "
         << "velocity: [0, -29784.69, 0]}]\n"
         << "integrator: {plugin: lgvi, step: 60, frame: " << frame << "}\nrun: {t_end: 86400, output_every: 86400}\n";
    return parse_scene(yaml.str(), "far-binary");
  };
  auto separation = [&](double dx, const std::string& frame) {
    Simulation sim(scene(dx, frame), registry());
    sim.integrate(86400);
    return Vec3(sim.state().x.col(1) - sim.state().x.col(0));
  };
  const Vec3 inertial_here = separation(0, "inertial"), relative_here = separation(0, "relative");
  const double ulps = 1.0 / (grid * 1.0);  // a separation difference in ulps of the moved positions
  const double relative_far = (separation(shift, "relative") - relative_here).norm() * ulps;
  const double inertial_far = (separation(shift, "inertial") - inertial_here).norm() * ulps;
  std::printf("a day at 0.92 au from the origin: the separation off the unmoved run's by %.2f ulps of the positions "
              "(relative frame), %.1f ulps (inertial frame), ulp = %.2e m of %.0f m; the two frames unmoved: %.2e\n",
              relative_far, inertial_far, grid, inertial_here.norm(),
              (relative_here - inertial_here).norm() / inertial_here.norm());
  EXPECT_LE(relative_far, 1.0);
  EXPECT_GT(inertial_far, 20.0);
  EXPECT_LT((relative_here - inertial_here).norm() / inertial_here.norm(), 1e-9);  // the same map, and the
  // unmoved inertial run's own roundings: the Sun moves the binary 2e7 m in the day
}

// Massless particles feel the prescribed planet as the bodies do (ForceModel::pull_particles):
// four particles on orbits about the binary (a = 5 and 6, well beyond beta) through the flyby
// above. The planet moves them relative to alpha by up to 22 (its tide strips the binary of them;
// particles that did not feel it at all would be left ~100 behind, as far as the planet moves the
// binary); prescribed against integrated (where the particles feel the planet as a body), they
// agree to the planet's back-reaction, 1e-5 of that, as the binary does.
TEST(PrescribedBody, ParticlesFeelItAsTheyFeelTheIntegratedPlanet) {
  const std::string particles =
      "{around: alpha, orbits: [{a: 5}, {a: 5, M: 180}, {a: 6, e: 0.1, i: 20, M: 90}, {a: 6, e: 0.1, i: 160}]}";
  const std::string lgvi = "{plugin: lgvi, step: 0.01}";
  const Outcome alone = run(flyby(false, false, lgvi, particles));
  const Outcome integrated = run(flyby(true, false, lgvi, particles));
  const Outcome prescribed = run(flyby(true, true, lgvi, particles));
  ASSERT_EQ(prescribed.particles.cols(), 4);
  const double change = (integrated.particles - alone.particles).colwise().norm().maxCoeff();
  const double difference = (prescribed.particles - integrated.particles).colwise().norm().maxCoeff();
  std::printf("particles through the flyby: moved by up to %.3e relative to alpha; prescribed − integrated %.3e "
              "(%.2e of it)\n", change, difference, difference / change);
  EXPECT_GT(change, 0.1);
  EXPECT_LT(difference, 1e-3 * change);
  for (const Outcome* o : {&alone, &integrated, &prescribed}) EXPECT_EQ(o->summary.particles.in_flight, 4u);
  ASSERT_EQ(prescribed.particle_fields.size(), 3u);  // alpha, beta, then the force
  EXPECT_EQ(prescribed.particle_fields[2], "prescribed-body planet: point masses (its bodies' gravity)");
}

namespace {

// A planet of mass 1 and radius 1 (G = 1) moving at 0.5 across the scene, 1e5 from its one body
// (a grain of mass 1e-15, which it hardly moves); particles in `states`, relative to the planet
// (x, y, z, vx, vy, vz), at the particles' Verlet `step`.
Scene planet_and_particles(const std::string& states, double step, const std::string& extra = "") {
  std::ostringstream yaml;
  yaml.precision(17);
  const Vec3 X(1e5, 0, 0), V(0, 0.5, 0);
  yaml << "G: 1\nbodies:\n  - {name: grain, mass: 1.0e-15, position: [0, 0, 0], velocity: [0, 0, 0]" << extra
       << "}\npotential: {plugin: point-mass}\n"
       << "forces: [{plugin: prescribed-body, name: planet, mass: 1, radius: 1, position: [" << X.x() << ", 0, 0], "
       << "velocity: [0, " << V.y() << ", 0]}]\n"
       << "integrator: {plugin: lgvi, step: 0.01}\nrun: {t_end: 3, output_every: 1}\n"
       << "particles: {escape: 0, check: 0, step: " << step << ", states: [" << states << "]}\n";
  Scene scene = parse_scene(yaml.str(), "planet");
  // The states were given relative to the planet: make them inertial.
  for (std::size_t i = 0; i < scene.particles.position.size(); ++i) {
    scene.particles.position[i] += X;
    scene.particles.velocity[i] += V;
  }
  return scene;
}

// The error a run of `scene` to its end stops with (none: it ran to the end).
std::optional<IntegrationError> integration_error(const Scene& scene) {
  Simulation sim(scene, registry());
  try {
    sim.integrate(scene.run.t_end);
  } catch (const IntegrationError& e) {
    return e;
  }
  return std::nullopt;
}

}  // namespace

// A prescribed body with a radius is a sphere the particles land on: a particle let go at rest
// 2 radii from the planet's centre falls radially, and lands when the radial Kepler fall says,
// t* = √(r0³/2μ) (√(u(1−u)) + arccos √u), u = R/r0 (= 1 + π/2 here), at speed √(2μ(1/R − 1/r0))
// = 1 relative to the planet, at the point of its sphere on its line — by the Verlet steps'
// order 2: the landing time's error falls by 4 when the step halves. (The planet's own
// acceleration about the scene's barycentre, 1e-10, moves t* by ~1e-10.)
TEST(PrescribedBody, ParticlesLandOnItsSphereWhenTheRadialFallSays) {
  const double t_star = 1 + M_PI / 2;
  double error[2];
  for (int k = 0; k < 2; ++k) {
    const Scene scene = planet_and_particles("[2, 0, 0, 0, 0, 0]", 0.01 / (2 << k));
    Simulation sim(scene, registry());
    sim.integrate(scene.run.t_end);
    const ParticleSwarm& swarm = *sim.particles();
    ASSERT_EQ(swarm.surfaces(), (std::vector<std::string>{"grain", "prescribed-body planet"}));
    const ParticleOutcome& o = swarm.outcomes()[0];
    ASSERT_EQ(o.fate, ParticleFate::impact);
    ASSERT_EQ(o.body, 1);
    error[k] = o.t - t_star;
    std::printf("step %.4f: landed at t = %.10f (radial fall %.10f, error %.3e), point (%.3e, %.3e, %.3e), relative "
                "velocity (%.6f, %.3e, %.3e)\n",
                0.01 / (2 << k), o.t, t_star, error[k], o.point.x(), o.point.y(), o.point.z(), o.velocity.x(),
                o.velocity.y(), o.velocity.z());
    EXPECT_NEAR(o.point.norm(), 1.0, 1e-12);  // on the sphere (the root's precision)
    EXPECT_LT((o.point - Vec3::UnitX()).norm(), 1e-6);
    EXPECT_LT((o.velocity + Vec3::UnitX()).norm(), 1e-4);
    const RunSummary summary = sim.finish();
    EXPECT_EQ(summary.particles.impacts, (std::vector<std::size_t>{0, 1}));
    // It rides on the planet after: recorded where the planet is, plus the landing point.
    Eigen::Matrix3Xd recorded;
    swarm.recorded_positions(sim.state(), recorded);
    const Vec3 planet = Vec3(1e5, 0.5 * sim.state().t, 0);
    EXPECT_LT((Vec3(recorded.col(0)) - planet - o.point).norm(), 1e-6);
  }
  EXPECT_LT(std::abs(error[0]), 1e-5);
  EXPECT_GT(std::abs(error[0] / error[1]), 3.5);
  EXPECT_LT(std::abs(error[0] / error[1]), 4.5);
}

// What cannot be: a particle that starts inside the prescribed body's sphere; a body whose
// bounding sphere meets it (the run stops with an error at that time); a particle that meets a
// radius-less point mass's centre exactly (its state is no longer finite: the run says so
// instead of carrying NaN).
TEST(PrescribedBody, ImpossibleContactsAreErrorsNamingWhatMet) {
  try {
    Simulation sim(planet_and_particles("[0.5, 0.5, 0, 0, 0, 0]", 0.01), registry());
    FAIL() << "a particle inside the planet was accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("starts inside 'prescribed-body planet' (within its radius 1"), std::string::npos)
        << e.what();
  }
  {
    std::ostringstream yaml;
    yaml << "G: 1\nbodies:\n  - {name: rock, mass: 1, radius: 2, position: [0, 0, 0], velocity: [0, 0, 0]}\n"
         << "potential: {plugin: point-mass}\nforces: [{plugin: prescribed-body, name: planet, mass: 1.0e-6, radius: 1, "
         << "position: [10, 0, 0], velocity: [-1, 0, 0]}]\nintegrator: {plugin: lgvi, step: 0.01}\n"
         << "run: {t_end: 20, output_every: 1}\n";
    const auto e = integration_error(parse_scene(yaml.str(), "collision"));
    ASSERT_TRUE(e) << "the planet passed through the rock";
    EXPECT_NE(std::string(e->what()).find("body 'rock' came within"), std::string::npos) << e->what();
    EXPECT_NE(std::string(e->what()).find("less than its radius 1 and the body's 2"), std::string::npos) << e->what();
    EXPECT_GT(e->t_reached(), 5.0);  // it falls in from 10 at 1 and more: meets r = 3 before t = 7
    EXPECT_LT(e->t_reached(), 7.0);
  }
  {
    // One Verlet step of 0.5 from x = 1, v = −1.75 in −1/r² lands on x = 1 + 0.5 (−1.75 − 0.25) = 0 exactly.
    const std::string yaml =
        "G: 1\nbodies:\n  - {name: sun, mass: 1, position: [0, 0, 0], velocity: [0, 0, 0]}\n"
        "potential: {plugin: point-mass}\nintegrator: {plugin: lgvi, step: 0.5}\nrun: {t_end: 2, output_every: 1}\n"
        "particles: {escape: 0, check: 0, states: [[1, 0, 0, -1.75, 0, 0]]}\n";
    const auto e = integration_error(parse_scene(yaml, "centre"));
    ASSERT_TRUE(e) << "a particle through a point mass's centre went on";
    EXPECT_NE(std::string(e->what()).find("particle 0 (from 0) is no longer finite"), std::string::npos) << e->what();
  }
}

// jm-hybrid refuses forces by design (its Jacobi–Maupertuis phase is at a fixed energy, which a
// time-dependent pull changes), saying so and what to use instead.
TEST(PrescribedBody, JmHybridRefusesItAndSaysWhy) {
  const Scene scene = parse_scene(R"(G: 1
bodies:
  - {name: star, mass: 1, position: [0, 0, 0], velocity: [0, 0, 0]}
  - {name: planet, mass: 1.0e-3, position: [1, 0, 0], velocity: [0, 1, 0]}
potential: {plugin: point-mass}
forces: [{plugin: prescribed-body, name: passer, mass: 0.1, position: [-50, 5, 0], velocity: [1, 0, 0]}]
integrator: {plugin: jm-hybrid, step: 0.01, Kc: 0.5}
run: {t_end: 1, output_every: 1}
)",
                                  "jm");
  try {
    Simulation sim(scene, registry());
    ADD_FAILURE() << "jm-hybrid took a force";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("integrates at a fixed energy"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("with lgvi or rk"), std::string::npos) << e.what();
  }
}

// A conic that starts at its own center is no conic: the scene's key is named, with where it is
// (it was KeplerOrbit's bare "r0 ≠ 0", with no file, line or key); so is one beyond 1e150,
// where distances overflow.
TEST(PrescribedBody, APositionAtItsCenterIsAnErrorAtItsKey) {
  for (const char* position : {"[0, 0, 0]", "[1.0e300, 0, 0]"}) {
    SCOPED_TRACE(position);
    try {
      const Scene scene = load_scene(test::source_path("examples/kw4-earth-flyby.yaml"),
                                     {std::string("forces.0.position=") + position});
      Simulation sim(scene, registry());
      ADD_FAILURE() << "accepted";
    } catch (const SceneError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("forces.0.position"), std::string::npos) << what;
      EXPECT_NE(what.find("prescribed-body: 'position'"), std::string::npos) << what;
      EXPECT_EQ(what.find("KeplerOrbit"), std::string::npos) << what;
    }
  }
}
