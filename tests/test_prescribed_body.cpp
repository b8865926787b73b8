// A body on a prescribed conic (docs/forces.md, "Prescribed bodies"; docs/equations.md §35): the
// universal-anomaly conic against an integrated two-body orbit, the prescribed body's force and
// torque against mutual-series with the same body integrated, and a flyby of a binary — the
// prescribed planet against the integrated one, E − W conserved while the flyby does work.
#include "test_support.hpp"

#include <noether/diagnostics.hpp>
#include <noether/kepler_orbit.hpp>
#include <noether/simulation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

using namespace noether;

namespace {

PluginRegistry& registry() {
  static PluginRegistry r = test::bundled_plugins();
  return r;
}

}  // namespace

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

// A prescribed body at order 2 against the same body integrated, as a point mass in
// mutual-series of order 2 (inertia integrals, Hou et al.): the force on and torque of an
// ellipsoid near it, two formulations of MacCullagh's quadrupole term.
TEST(PrescribedBody, ForceAndTorqueAreTheSeriesOfOrderTwo) {
  const char* body = "  - {name: rock, mass: 2, shape: {ellipsoid: {semi_axes: [0.3, 0.2, 0.1]}}, position: [0, 0, 0], "
                     "velocity: [0, 0, 0], attitude: {euler_angles: [30, 20, 10]}}\n";
  const Scene integrated = parse_scene(std::string("G: 1\nbodies:\n") + body +
                                           "  - {name: planet, mass: 5, position: [1.5, -1, 0.7], velocity: [0, 1, 0]}\n"
                                           "potential: {plugin: mutual-series, order: 2}\nintegrator: {plugin: lgvi, step: 0.01}\n"
                                           "run: {t_end: 1, output_every: 1}\n",
                                       "integrated");
  const Scene prescribed = parse_scene(std::string("G: 1\nbodies:\n") + body +
                                           "potential: {plugin: point-mass}\n"
                                           "forces: [{plugin: prescribed-body, name: planet, mass: 5, center: origin, "
                                           "mu: 7, position: [1.5, -1, 0.7], velocity: [0, 1, 0]}]\n"
                                           "integrator: {plugin: lgvi, step: 0.01}\nrun: {t_end: 1, output_every: 1}\n",
                                       "prescribed");
  Forces series;
  series.resize(integrated.system);
  make_scene_potential(integrated, registry())->evaluate(integrated.initial, series);
  const auto force = registry().make_force("prescribed-body", prescribed.system, prescribed.forces[0].params);
  Forces f;
  f.resize(prescribed.system);
  auto ws = force->make_workspace();
  force->evaluate(prescribed.initial, f, *ws);
  const double df = (Vec3(f.f.col(0)) - Vec3(series.f.col(0))).norm() / series.f.col(0).norm();
  const double dM = (Vec3(f.M.col(0)) - Vec3(series.M.col(0))).norm() / series.M.col(0).norm();
  std::printf("prescribed against mutual-series order 2: force %.2e, torque %.2e\n", df, dM);
  EXPECT_LT(df, 1e-13);
  EXPECT_LT(dM, 1e-13);
}

namespace {

// A binary of two ellipsoids (1 and 0.1, 1 apart, circular) and a planet 1000 times heavier on a
// hyperbola about the binary's barycentre (v∞ ≈ 10, closest approach ≈ 30: its tide is 7 % of the
// binary's own pull there), integrated (`prescribed` false: a third body, mutual-series of order 2)
// or prescribed; from 200 before closest approach to about as far after.
const double kPlanet = 1000, kAlpha = 1, kBeta = 0.1;
const Vec3 kPlanetFromBarycentre(-200, 38.7, 3), kPlanetVelocity(10.5, 0, 0.5);

Scene flyby(bool planet, bool prescribed, const std::string& integrator = "{plugin: lgvi, step: 0.01}") {
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
  return parse_scene(yaml.str(), "flyby");
}

struct Outcome {
  Vec3 separation, velocity, spin_alpha, spin_beta;
  RunSummary summary;
};

Outcome run(const Scene& scene) {
  Simulation sim(scene, registry());
  sim.integrate(scene.run.t_end);
  const State s = sim.state();
  Outcome o{s.x.col(1) - s.x.col(0), s.p.col(1) / kBeta - s.p.col(0) / kAlpha,
            s.R[0] * scene.system.body(0).inertia_inverse * Vec3(s.Pi.col(0)),
            s.R[1] * scene.system.body(1).inertia_inverse * Vec3(s.Pi.col(1)), sim.finish()};
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
