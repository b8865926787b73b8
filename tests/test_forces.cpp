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
#include <sstream>

using namespace noether;
using test::registry;

namespace {

using test::tidal_scene;

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
                                 "integrator={plugin: rk, method: rkf78, rtol: 1e-12, atol: 1e-14}",
                                 "integrator={plugin: cvode, rtol: 1e-12, atol: 1e-14}"}) {
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
    } else {  // rk and cvode conserve them to their tolerance only
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
  // And CVODE's Adams method, a third: its balance integrated outside its error control.
  const State cvode = final_state("integrator={plugin: cvode, rtol: 1e-12, atol: 1e-15}");
  const double dc = State::difference(rk, cvode).norm() / State::difference(tidal_scene().initial, rk).norm();
  std::printf("cvode vs rkf78: %.3e of the motion; work %.12e\n", dc, cvode.force_balance(0, 0));
  EXPECT_LT(dc, 1e-8);
  EXPECT_NEAR(cvode.force_balance(0, 0), rk.force_balance(0, 0), 1e-8 * std::abs(rk.force_balance(0, 0)));
}

// The forced Lagrangian form (docs/equations.md (33.10)) is the forced Hamiltonian form's map
// through the discrete Legendre transform: the same run to round-off — state, energy and the
// tide's work and momenta — though one carries x_k − x_{k−1} and the other the momenta; and its
// own E − W is conserved as the Hamiltonian form's is (tides depend on the momenta, so the
// closing kick is iterated in both).
TEST(Tides, ForcedLagrangianFormIsTheHamiltonianFormsMap) {
  const std::vector<std::string> common = {"run.t_end=20", "run.output_every=0.5"};
  auto with = [&](const std::string& form) {
    std::vector<std::string> o = common;
    o.push_back("integrator={plugin: lgvi, step: 0.01, form: " + form + "}");
    return run(tidal_scene(o));
  };
  const Frames hamiltonian = with("hamiltonian"), lagrangian = with("lagrangian");
  double dz = 0.0, dbalance = 0.0;
  const double scale = State::difference(tidal_scene().initial, hamiltonian.states.back()).norm();
  for (std::size_t k = 0; k < hamiltonian.states.size(); ++k) {
    dz = std::max(dz, State::difference(hamiltonian.states[k], lagrangian.states[k]).norm() / scale);
    const Eigen::MatrixXd& a = hamiltonian.states[k].force_balance;
    dbalance = std::max(dbalance, (a - lagrangian.states[k].force_balance).cwiseAbs().maxCoeff() / a.cwiseAbs().maxCoeff());
  }
  const State& end = lagrangian.states.back();
  std::printf("lagrangian vs hamiltonian over 2000 forced steps: state %.2e of the motion, balance %.2e; work %.6e; "
              "max |E - W - E0| %.3e vs %.3e\n",
              dz, dbalance, end.force_balance(0, 0), lagrangian.summary.max_abs_energy_error,
              hamiltonian.summary.max_abs_energy_error);
  EXPECT_LT(dz, 1e-11);
  EXPECT_LT(dbalance, 1e-11);
  EXPECT_LT(end.force_balance(0, 0), -1e-4);  // the tide did work (it spun the planet down)
  EXPECT_NEAR(lagrangian.summary.max_abs_energy_error, hamiltonian.summary.max_abs_energy_error,
              1e-6 * hamiltonian.summary.max_abs_energy_error);
  EXPECT_EQ(lagrangian.summary.verdict.trustworthy, true);
}

// The relative forms with forces (docs/equations.md (33.11)): the kicks in the reduced momenta
// around the relative map are the inertial forms' forced map in other variables — the same run to
// round-off, state, energy and the tide's balance, for the Hamiltonian form at orders 2 and 4 and
// for the Lagrangian form. The moon made rigid (a small sphere's inertia) so that the relative
// frame takes the pair.
TEST(Tides, ForcedRelativeFormsAreTheInertialFormsMap) {
  const std::vector<std::string> common = {"run.t_end=20", "run.output_every=0.5",
                                           "bodies.moon.inertia=[1e-3, 1e-3, 1e-3]"};
  auto with = [&](const std::string& integrator) {
    std::vector<std::string> o = common;
    o.push_back("integrator={plugin: lgvi, step: 0.01, " + integrator + "}");
    return run(tidal_scene(o));
  };
  const double scale = State::difference(tidal_scene(common).initial, with("order: 2").states.back()).norm();
  for (const std::string form : {"order: 2", "order: 4", "form: lagrangian"}) {
    const Frames inertial = with(form), relative = with(form + ", frame: relative");
    double dz = 0.0, dbalance = 0.0;
    for (std::size_t k = 0; k < inertial.states.size(); ++k) {
      dz = std::max(dz, State::difference(inertial.states[k], relative.states[k]).norm() / scale);
      const Eigen::MatrixXd& a = inertial.states[k].force_balance;
      dbalance = std::max(dbalance, (a - relative.states[k].force_balance).cwiseAbs().maxCoeff() / a.cwiseAbs().maxCoeff());
    }
    std::printf("%s, relative vs inertial over 2000 forced steps: state %.2e of the motion, balance %.2e; "
                "max |E - W - E0| %.3e vs %.3e\n",
                form.c_str(), dz, dbalance, relative.summary.max_abs_energy_error, inertial.summary.max_abs_energy_error);
    EXPECT_LT(dz, 1e-11) << form;
    EXPECT_LT(dbalance, 1e-11) << form;
    EXPECT_LT(relative.states.back().force_balance(0, 0), -1e-4) << form;  // the tide did work
    EXPECT_NEAR(relative.summary.max_abs_energy_error, inertial.summary.max_abs_energy_error,
                std::max(1e-6 * inertial.summary.max_abs_energy_error, 1e-13))  // order 4's is 8.7e-11
        << form;
    EXPECT_TRUE(relative.summary.verdict.trustworthy) << form;
  }
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

// What refuses forces, by name: methods and forms that do not take them, a sensitivity to what is
// not a number of a force, a point mass tidally deformed, a bad Love number.
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
  refused({"integrator={plugin: lgvi, step: 0.01, frame: relative}"}, "frame: relative needs exactly two rigid bodies");
  refused({"integrator={plugin: cvode, form: lagrangian}"},
          "forces: integrator 'cvode' cannot take them: cvode takes forces beyond the potential in its inertial "
          "Hamiltonian equations only");
  refused({"run.sensitivities=[forces.0.body]"}, "is not a number of the force");
  refused({"run.sensitivities=[forces.1.k2]"}, "names no force (the scene has 1)");
  refused({"run.sensitivities=[forces.0.love]"}, "the force gives no 'love'");
  refused({"run.sensitivities=[forces.k2]"}, "a force is named by its index");
  refused({"forces.0.body=moon"}, "is a point mass");
  refused({"forces.0.k2=-1"}, "k2 must be");
  refused({"forces.0.plugin=point-mass"}, "is a potential, not a force");
}

namespace {

// Hut (1981)'s polynomials in e² of the orbit-averaged constant-time-lag rates.
double f1(double e2) { return 1 + e2 * (31.0 / 2 + e2 * (255.0 / 8 + e2 * (185.0 / 16 + e2 * 25.0 / 64))); }
double f2(double e2) { return 1 + e2 * (15.0 / 2 + e2 * (45.0 / 8 + e2 * 5.0 / 16)); }
double f3(double e2) { return 1 + e2 * (15.0 / 4 + e2 * (15.0 / 8 + e2 * 5.0 / 64)); }
double f4(double e2) { return 1 + e2 * (3.0 / 2 + e2 / 8); }
double f5(double e2) { return 1 + e2 * (3 + e2 * 3.0 / 8); }

struct Elements {
  double a, e, spin;
};

// The relative orbit's osculating a, e and the primary's spin rate at a state (point masses,
// μ = G (m_A + m_B)).
Elements elements(const Scene& scene, const State& s) {
  const double mA = scene.system.body(0).mass, mB = scene.system.body(1).mass, mu = scene.system.G() * (mA + mB);
  const Vec3 r = s.x.col(1) - s.x.col(0), v = s.p.col(1) / mB - s.p.col(0) / mA;
  const double energy = 0.5 * v.squaredNorm() - mu / r.norm();
  const double a = -mu / (2 * energy);
  const double e = (v.cross(r.cross(v)) / mu - r.normalized()).norm();
  const Vec3 Omega = scene.system.body(0).inertia_inverse * Vec3(s.Pi.col(0));
  return {a, e, Omega.norm()};
}

}  // namespace

// The secular tidal rates of a two-body system — a primary spinning faster than the orbit, its
// spin along the orbit's normal, a point-mass moon — against the orbit-averaged
// constant-time-lag formulas of Hut (1981), q = m_B/m_A:
//   da/dt = −6 (k/T) q (1 + q) (R/a)⁸ a (1 − e²)^(−15/2) [f1 − (1 − e²)^(3/2) f2 ω/n]
//   de/dt = −27 (k/T) q (1 + q) (R/a)⁸ e (1 − e²)^(−13/2) [f3 − (11/18)(1 − e²)^(3/2) f4 ω/n]
//   dω/dt = 3 (k/T) q² (m_A R²/C) (R/a)⁶ n (1 − e²)^(−6) [f2 − (1 − e²)^(3/2) f5 ω/n]
// with k/T = k2 G m_A Δt / R³: the normalisation that makes dω/dt at e = 0 the circular torque's
// closed form, −3 k2 G m_B² R⁵ Δt (ω − n)/(C a⁶) (TorqueOnACircularOrbitIsTheClosedForm); what
// this test checks is the averaging over the orbit and the eccentricity functions f1–f5. The
// rates are measured from the means of a, e and ω over the first and the last orbit of 20 (the
// lagged tide alone: the static bulge changes none of them secularly). The formulas'
// assumptions hold: |ω − n| Δt = 0.04, weak tides (the elements change by 1e-4–5e-3 over the run).
TEST(Tides, SecularRatesAreTheOrbitAveragedFormulas) {
  for (const double e0 : {0.0, 0.3}) {
    SCOPED_TRACE(e0);
    const double mA = 1, mB = 0.1, R = 0.3, k2 = 0.3, lag = 0.01, C = 0.4 * mA * R * R, a0 = 1;
    const double mu = mA + mB, n0 = std::sqrt(mu / (a0 * a0 * a0)), P = 2 * std::numbers::pi / n0;
    const int per_orbit = 200, orbits = 20;
    const double dt_out = P / per_orbit;
    const double vp = std::sqrt(mu * (1 + e0) / (a0 * (1 - e0)));  // at pericentre
    std::ostringstream yaml;
    yaml.precision(17);
    yaml << "G: 1\nbarycentric: true\nbodies:\n"
         << "  - {name: planet, mass: " << mA << ", inertia: [" << C << ", " << C << ", " << C << "], radius: " << R
         << ", position: [0, 0, 0], velocity: [0, 0, 0], angular_velocity: [0, 0, 5]}\n"
         << "  - {name: moon, mass: " << mB << ", position: [" << a0 * (1 - e0) << ", 0, 0], velocity: [0, " << vp
         << ", 0]}\npotential: {plugin: point-mass}\n"
         << "forces: [{plugin: tides, body: planet, k2: " << k2 << ", time_lag: " << lag << ", static_bulge: false}]\n"
         << "integrator: {plugin: rk, method: rkf78, rtol: 1.0e-13, atol: 1.0e-16}\n"
         << "run: {t_end: " << orbits * P << ", output_every: " << dt_out << "}\n";
    const Scene scene = parse_scene(yaml.str(), "tidal-rates");
    Simulation sim(scene, registry());
    std::vector<Elements> samples{elements(scene, scene.initial)};
    for (int k = 1; k <= orbits * per_orbit; ++k) {
      sim.integrate(std::min(k * dt_out, scene.run.t_end));
      samples.push_back(elements(scene, sim.state()));
    }
    auto mean = [&](std::size_t first, double Elements::*field) {  // trapezoid over one orbit
      double sum = 0;
      for (int k = 0; k < per_orbit; ++k)
        sum += 0.5 * (samples[first + k].*field + samples[first + k + 1].*field);
      return sum / per_orbit;
    };
    const std::size_t last = samples.size() - 1 - per_orbit;
    const double span = (orbits - 1) * P;
    const double a = 0.5 * (mean(0, &Elements::a) + mean(last, &Elements::a));
    const double e = 0.5 * (mean(0, &Elements::e) + mean(last, &Elements::e));
    const double w = 0.5 * (mean(0, &Elements::spin) + mean(last, &Elements::spin));
    const double da = (mean(last, &Elements::a) - mean(0, &Elements::a)) / span;
    const double de = (mean(last, &Elements::e) - mean(0, &Elements::e)) / span;
    const double dw = (mean(last, &Elements::spin) - mean(0, &Elements::spin)) / span;
    const double kT = k2 * mA * lag / (R * R * R), q = mB / mA, n = std::sqrt(mu / (a * a * a)), e2 = e * e;
    const double s = std::pow(1 - e2, 1.5);
    const double da_hut = -6 * kT * q * (1 + q) * std::pow(R / a, 8) * a / std::pow(1 - e2, 7.5) * (f1(e2) - s * f2(e2) * w / n);
    const double de_hut = -27 * kT * q * (1 + q) * std::pow(R / a, 8) * e / std::pow(1 - e2, 6.5) *
                          (f3(e2) - 11.0 / 18 * s * f4(e2) * w / n);
    const double dw_hut = 3 * kT * q * q * (mA * R * R / C) * std::pow(R / a, 6) * n / std::pow(1 - e2, 6) *
                          (f2(e2) - s * f5(e2) * w / n);
    std::printf("e %.2f: da/dt %.6e (Hut %.6e, %+.2e), dω/dt %.6e (Hut %.6e, %+.2e)", e0, da, da_hut, da / da_hut - 1,
                dw, dw_hut, dw / dw_hut - 1);
    if (e0 > 0) std::printf(", de/dt %.6e (Hut %.6e, %+.2e)", de, de_hut, de / de_hut - 1);
    std::printf("; Δa/a %.2e, Δω/ω %.2e\n", da * span / a, dw * span / w);
    EXPECT_NEAR(da / da_hut, 1.0, 1e-3);  // the issue asks for 2 %
    EXPECT_NEAR(dw / dw_hut, 1.0, 1e-3);
    if (e0 > 0) EXPECT_NEAR(de / de_hut, 1.0, 1e-3);
  }
}

// The tide damps a synchronous moon's libration: linearised, C φ̈ + D φ̇ + K φ = 0 with
// K = 3 (G M / a³)(B − A) (the primary's gravity gradient) and, from (34.1)–(34.2) on a circular
// orbit (ω − n = φ̇), D = 3 k2 G M² R⁵ Δt / a⁶ — a damped pendulum whose amplitude falls as
// exp(−D t / 2C). Measured by the forced LGVI on an ellipsoidal moon (mutual-series, order 2)
// over 12 libration periods, by a least-squares fit of φ(t). The measured rate is 2.1 % below the
// pendulum's and the frequency 0.5 % below, the same with k2 → 0 (the frequency), with a 100
// times lighter moon and with 1° instead of 5°; an independent planar model (point planet,
// MacCullagh's potential, the same tide, SciPy's RK45 at rtol 1e-11), measured by the same peaks
// and zero crossings, gave the same offsets (decay −3.5 % by peaks here and there, frequency
// 0.7306 there and 0.7307 here): they are the coupled spin–orbit problem's, not the pendulum's.
// So: within 3 % and 1 %.
TEST(Tides, DampLibrationAtTheDampedPendulumRate) {
  const double M = 1, m = 1e-3, a = 1, R = 0.05, k2 = 0.5, lag = 0.1;
  const Vec3 axes(0.06, 0.05, 0.04);
  const double n = std::sqrt((M + m) / (a * a * a));
  // The moon on the circular orbit of the whole potential (its quadrupole included: a Kepler
  // speed would leave e ≈ 5e-4, whose forced libration beats with the free one).
  auto scene_with = [&](double speed) {
    std::ostringstream yaml;
    yaml.precision(17);
    yaml << "G: 1\nbarycentric: true\nbodies:\n"
         << "  - {name: planet, mass: " << M << ", position: [0, 0, 0], velocity: [0, 0, 0]}\n"
         << "  - name: moon\n    mass: " << m << "\n    shape: {ellipsoid: {semi_axes: [" << axes.x() << ", " << axes.y()
         << ", " << axes.z() << "]}}\n    position: [" << a << ", 0, 0]\n    velocity: [0, " << speed
         << ", 0]\n    attitude: {euler_angles: [5, 0, 0]}\n    angular_velocity: [0, 0, " << speed / a << "]\n"
         << "potential: {plugin: mutual-series, order: 2}\n"
         << "forces: [{plugin: tides, body: moon, k2: " << k2 << ", time_lag: " << lag << ", radius: " << R
         << ", static_bulge: false}]\n"
         << "integrator: {plugin: lgvi, step: 0.01}\nrun: {t_end: 100, output_every: 0.05}\n";
    return parse_scene(yaml.str(), "libration-damping");
  };
  const Scene kepler = scene_with(n * a);
  Forces f;
  f.resize(kepler.system);
  make_scene_potential(kepler, registry())->evaluate(kepler.initial, f);
  const double reduced = M * m / (M + m);
  const Scene scene = scene_with(std::sqrt(std::abs(f.f(0, 1)) * a / reduced));
  const Body& moon = scene.system.body(1);
  const double A = moon.inertia(0, 0), B = moon.inertia(1, 1), C = moon.inertia(2, 2);
  const double rate = 3 * k2 * M * M * std::pow(R, 5) * lag / (std::pow(a, 6) * 2 * C);
  Simulation sim(scene, registry());
  std::vector<double> t, phi;
  for (int k = 1; k <= 2000; ++k) {
    sim.integrate(std::min(0.05 * k, 100.0));
    const State& s = sim.state();
    const Vec3 r = (s.x.col(0) - s.x.col(1)).normalized(), u = s.R[0].col(0);
    t.push_back(s.t);
    double angle = std::atan2(Vec3::UnitZ().dot(r.cross(u)), r.dot(u));  // the long axis has no sign:
    if (angle > std::numbers::pi / 2) angle -= std::numbers::pi;         // fold into (−90°, 90°]
    if (angle <= -std::numbers::pi / 2) angle += std::numbers::pi;
    phi.push_back(angle);
  }
  // φ(t) fitted by least squares (Gauss–Newton) to a damped free libration and the small forced
  // one at the orbit's frequency ν (the orbit's residual eccentricity, ~5e-4, forces the moon at
  // ν: 1–2 % of the free amplitude, which would bias a fit of the peaks alone by a few %):
  //   φ = e^(−γ t) (c1 cos ω t + c2 sin ω t) + c3 cos ν t + c4 sin ν t + c5.
  const double mean_motion = std::sqrt(std::abs(f.f(0, 1)) / (reduced * a));
  const double omega_lib = std::sqrt(3 * M / (a * a * a) * (B - A) / C - rate * rate);
  const double nu = mean_motion;
  Eigen::VectorXd q(7);  // γ, ω, c1 … c5
  q << rate, omega_lib, phi.front(), 0, 0, 0, 0;
  for (int iteration = 0; iteration < 30; ++iteration) {
    Eigen::MatrixXd Jm(t.size(), 7);
    Eigen::VectorXd res(t.size());
    for (std::size_t k = 0; k < t.size(); ++k) {
      const double tk = t[k] - t.front(), E = std::exp(-q(0) * tk), c = std::cos(q(1) * tk), sn = std::sin(q(1) * tk);
      const double free = E * (q(2) * c + q(3) * sn);
      const auto r = static_cast<Eigen::Index>(k);
      res(r) = phi[k] - free - q(4) * std::cos(nu * tk) - q(5) * std::sin(nu * tk) - q(6);
      Jm.row(r) << -tk * free, E * tk * (-q(2) * sn + q(3) * c), E * c, E * sn, std::cos(nu * tk), std::sin(nu * tk), 1.0;
    }
    const Eigen::VectorXd step = Jm.colPivHouseholderQr().solve(res);
    q += step;
    if (step.norm() < 1e-13 * q.norm()) break;
  }
  const double gamma = q(0), omega_fit = q(1);
  std::printf("libration: decay rate %.6e (damped pendulum %.6e, %+.2e), frequency %.6f (linear %.6f, %+.2e), "
              "forced part %.2e of the free amplitude\n",
              gamma, rate, gamma / rate - 1, omega_fit, omega_lib, omega_fit / omega_lib - 1,
              std::hypot(q(4), q(5)) / std::hypot(q(2), q(3)));
  EXPECT_NEAR(gamma / rate, 1.0, 0.03);
  EXPECT_NEAR(omega_fit / omega_lib, 1.0, 0.01);
}
