// Forces beyond the potential (docs/forces.md, docs/equations.md §33–34): the forced LGVI and rk
// with constant-time-lag tides — total momenta conserved to round-off while the spin changes,
// energy that only decreases, E − W conserved to the integrator's error, the orders of the
// forced maps by self-convergence, the two formulations against each other, the tidal torque
// against its closed form, and what refuses forces.
#include "test_support.hpp"

#include <noether/diagnostics.hpp>
#include <noether/simulation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace noether;

namespace {

PluginRegistry& registry() {
  static PluginRegistry r = test::bundled_plugins();
  return r;
}

// A fast-spinning, slightly triaxial primary (spin 5, tilted 20° from the orbit normal) and a
// point-mass moon from r = 1 on an orbit of a ≈ 1.25, e ≈ 0.2 (n ≈ 0.74): the tide the moon raises spins the
// primary down and pushes the moon out.
Scene tidal_scene(const std::vector<std::string>& overrides = {}) {
  return parse_scene(R"(G: 1
bodies:
  - name: planet
    mass: 1
    inertia: [0.0324, 0.036, 0.0396]
    radius: 0.3
    position: [0, 0, 0]
    velocity: [0, 0, 0]
    attitude: {euler_angles: [0, 20, 0]}
    angular_velocity: [0, 0, 5]
  - {name: moon, mass: 0.1, position: [1, 0, 0], velocity: [0, 1.15, 0]}
barycentric: true
potential: {plugin: point-mass}
forces: [{plugin: tides, body: planet, k2: 0.5, time_lag: 0.1}]
integrator: {plugin: lgvi, step: 0.01}
run: {t_end: 50, output_every: 0.5}
)",
                     "tidal", overrides);
}

Vec3 angular_momentum(const System& system, const State& s) {
  return diagnose(system, s, 0.0).angular_momentum;
}

struct Frames {
  std::vector<State> states;
  std::vector<double> energy;
  RunSummary summary;
};

Frames run(const Scene& scene) {
  Frames out;
  Simulation sim(scene, registry());
  for (double t = scene.run.output_every; t <= scene.run.t_end * (1 + 1e-12); t += scene.run.output_every) {
    sim.integrate(std::min(t, scene.run.t_end));
    out.states.push_back(sim.state());
  }
  out.summary = sim.finish();
  return out;
}

double energy(const Scene& scene, const State& s) {
  const auto potential = make_scene_potential(scene, registry());
  Forces f;
  f.resize(scene.system);
  potential->evaluate(s, f);
  return diagnose(scene.system, s, f.U).energy;
}

}  // namespace

// Internal tides: total linear and angular momentum to round-off (the kicks are equal and
// opposite, the torque is −r × F) while the spin's angular momentum changes by ≥ 1e-3 of itself.
TEST(Tides, ConserveTotalMomentaWhileTheSpinChanges) {
  for (const char* integrator : {"integrator={plugin: lgvi, step: 0.01}", "integrator={plugin: lgvi, step: 0.02, order: 4}",
                                 "integrator={plugin: rk, method: rkf78, rtol: 1e-12, atol: 1e-14}"}) {
    SCOPED_TRACE(integrator);
    const Scene scene = tidal_scene({integrator, "run.t_end=100"});
    const Frames r = run(scene);
    const State& s0 = scene.initial;
    const State& s1 = r.states.back();
    const Vec3 L0 = angular_momentum(scene.system, s0), L1 = angular_momentum(scene.system, s1);
    const Vec3 S0 = s0.R[0] * Vec3(s0.Pi.col(0)), S1 = s1.R[0] * Vec3(s1.Pi.col(0));
    const double spin_change = (S1 - S0).norm() / S0.norm();
    EXPECT_GT(spin_change, 2e-3);
    const double L_scale = S0.norm() + Vec3(s0.x.col(1)).cross(Vec3(s0.p.col(1))).norm();
    if (std::string(integrator).find("lgvi") != std::string::npos) {
      EXPECT_LT((L1 - L0).norm() / L_scale, 1e-12);
      EXPECT_LT((s1.p.rowwise().sum() - s0.p.rowwise().sum()).norm() / s0.p.col(1).norm(), 1e-12);
    } else {  // rk conserves them to its tolerance only
      EXPECT_LT((L1 - L0).norm() / L_scale, 1e-9);
    }
    // The balance's ΔL of internal tides is round-off; the summary says what the tide did.
    ASSERT_EQ(r.summary.forces.size(), 1u);
    EXPECT_EQ(r.summary.forces[0].name, "tides planet");
    EXPECT_LT(r.summary.forces[0].angular_momentum.norm() / L_scale, 1e-9);
    EXPECT_LT(r.summary.forces[0].work, 0.0);
    std::printf("%s: spin change %.3e, |ΔL|/L %.2e, W %.6e\n", integrator, spin_change, (L1 - L0).norm() / L_scale,
                r.summary.forces[0].work);
  }
}

// Without the static bulge the tide only dissipates (34.3): E = T + U falls at every frame, and
// E − W stays at E0 to the LGVI's energy error — bounded, no drift: the second half of the run
// errs no more than twice the first half, while W grows steadily.
TEST(Tides, EnergyFallsAndEnergyMinusWorkIsConserved) {
  const Scene scene = tidal_scene({"forces.0.static_bulge=false", "run.t_end=100"});
  const Frames r = run(scene);
  const double E0 = energy(scene, scene.initial);
  double previous = E0, first_half = 0.0, second_half = 0.0;
  for (std::size_t k = 0; k < r.states.size(); ++k) {
    const double E = energy(scene, r.states[k]);
    EXPECT_LT(E, previous) << "frame " << k;
    previous = E;
    const double W = r.states[k].force_balance(0, 0);
    const double err = std::abs(E - W - E0);
    (k < r.states.size() / 2 ? first_half : second_half) = std::max(k < r.states.size() / 2 ? first_half : second_half, err);
  }
  const double W = r.states.back().force_balance(0, 0);
  std::printf("W %.6e, max |E - W - E0|: first half %.3e, second half %.3e\n", W, first_half, second_half);
  EXPECT_LT(W, -1e-3);
  EXPECT_LT(std::max(first_half, second_half), 1e-3 * std::abs(W));
  EXPECT_LT(second_half, 2.0 * first_half);
  EXPECT_NEAR(r.summary.max_abs_energy_error, std::max(first_half, second_half), 1e-3 * std::abs(W));
}

// The forced maps' orders by self-convergence: the final state's error at h, h/2, h/4 against
// h/8 falls by 2^p (the closing kick is solved to round-off, so the forced map is symmetric and
// its compositions keep order 4).
TEST(Tides, ForcedLgviConvergesAtOrdersTwoAndFour) {
  for (const int order : {2, 4}) {
    SCOPED_TRACE(order);
    const double h0 = order == 2 ? 0.02 : 0.04;
    auto final_state = [&](double h) {
      const std::string integrator = "integrator={plugin: lgvi, step: " + std::to_string(h) + ", order: " +
                                     std::to_string(order) + "}";
      Simulation sim(tidal_scene({integrator, "run.t_end=10", "run.output_every=10"}), registry());
      sim.integrate(10.0);
      return sim.state();
    };
    const State ref = final_state(h0 / 16);
    std::vector<double> errors;
    for (const double h : {h0, h0 / 2, h0 / 4}) {
      const State s = final_state(h);
      errors.push_back((State::difference(ref, s)).norm());
    }
    for (std::size_t k = 0; k + 1 < errors.size(); ++k) {
      const double rate = std::log2(errors[k] / errors[k + 1]);
      std::printf("order %d: error %.3e -> %.3e, observed order %.3f\n", order, errors[k], errors[k + 1], rate);
      EXPECT_NEAR(rate, order, 0.15);
    }
  }
}

// Two independent formulations of the same forced flow: the forced LGVI of order 4 (kicks around
// the discrete flow) and rkf78 on the continuous equations with the force added agree.
TEST(Tides, ForcedLgviAgreesWithRungeKutta) {
  auto final_state = [](const std::string& integrator) {
    Simulation sim(tidal_scene({integrator, "run.t_end=10", "run.output_every=10"}), registry());
    sim.integrate(10.0);
    return sim.state();
  };
  const State lgvi = final_state("integrator={plugin: lgvi, step: 0.001, order: 4}");
  const State rk = final_state("integrator={plugin: rk, method: rkf78, rtol: 1e-13, atol: 1e-15}");
  const double dx = State::difference(rk, lgvi).norm() / State::difference(tidal_scene().initial, rk).norm();
  std::printf("lgvi order 4 vs rkf78 after 10: %.3e of the motion; work %.12e vs %.12e\n", dx, lgvi.force_balance(0, 0),
              rk.force_balance(0, 0));
  EXPECT_LT(dx, 1e-8);
  EXPECT_NEAR(lgvi.force_balance(0, 0), rk.force_balance(0, 0), 1e-9 * std::abs(rk.force_balance(0, 0)));
}

// The tidal torque on a spin aligned with a circular orbit's normal against its closed form,
// N_z = −3 k2 G m² R⁵ Δt (ω − n) / r⁶ (docs/equations.md §34, Hut 1981 at e = 0), and the
// static bulge's pull, −3 k2 G m² R⁵ / r⁷.
TEST(Tides, TorqueOnACircularOrbitIsTheClosedForm) {
  const Scene scene = tidal_scene({"bodies.planet.attitude={euler_angles: [0, 0, 0]}", "bodies.moon.velocity=[0, 1.0488088481701516, 0]"});
  const auto model = registry().make_force("tides", scene.system, scene.forces[0].params);
  Forces f;
  f.resize(scene.system);
  auto ws = model->make_workspace();
  model->evaluate(scene.initial, f, *ws);
  const State& s = scene.initial;
  const double r = (s.x.col(1) - s.x.col(0)).norm();
  const Vec3 v = s.p.col(1) / 0.1 - s.p.col(0) / 1.0;
  const double n = v.norm() / r, omega = 5.0;
  const double k2 = 0.5, dt = 0.1, R = 0.3, m = 0.1;
  const double N = -3 * k2 * m * m * std::pow(R, 5) * dt * (omega - n) / std::pow(r, 6);
  EXPECT_NEAR(f.M(2, 0), N, 1e-13 * std::abs(N));
  EXPECT_NEAR(f.M(0, 0), 0.0, 1e-15 * std::abs(N));
  const Vec3 rhat = (s.x.col(1) - s.x.col(0)) / r;
  const double radial = 3 * k2 * m * m * std::pow(R, 5) / std::pow(r, 7);
  EXPECT_NEAR(f.f.col(1).dot(rhat), -radial, 1e-13 * radial);
  EXPECT_NEAR((f.f.col(0) + f.f.col(1)).norm(), 0.0, 1e-18);
}

// What refuses forces, by name: methods and forms that do not take them, a tangent with them, a
// point mass tidally deformed, a continued run.
TEST(Tides, RefusalsSayWhy) {
  auto refused = [](const std::vector<std::string>& overrides, const std::string& fragment) {
    SCOPED_TRACE(fragment);
    try {
      Simulation sim(tidal_scene(overrides), registry());
      ADD_FAILURE() << "not refused";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  refused({"integrator={plugin: lgvi, step: 0.01, form: lagrangian}"}, "form: hamiltonian");
  refused({"integrator={plugin: cvode}"},
          "forces: integrator 'cvode' cannot take them: this method does not take forces beyond the potential");
  refused({"run.stm=true"}, "has no tangent map yet");
  refused({"forces.0.body=moon"}, "is a point mass");
  refused({"forces.0.k2=-1"}, "k2 must be");
  refused({"forces.0.plugin=point-mass"}, "is a potential, not a force");
}
