// Impulses during a run (the scene's `impulses:`; docs/user-guide.md "Impulses", docs/equations.md
// §24): the same as stopping, changing the velocity and going on; the verdict's references move
// with the jump; sensitivities to the Δv and to the mass against differences of whole runs; and
// what refuses them.
#include "test_support.hpp"

#include <noether/full_body_model.hpp>
#include <noether/simulation.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

using namespace noether;
using test::registry;

namespace {

const std::string kImpulse = "impulses=[{body: planet, time: 1.25, delta_v: [0.01, -0.02, 0.005]}]";

// The Kepler orbit with one impulse on the planet at t = 1.25, run to t = 2.
Scene kicked(std::vector<std::string> overrides = {}) {
  overrides.insert(overrides.begin(), kImpulse);
  return test::kepler_scene(overrides);
}

State final_state(const Scene& scene) {
  Simulation sim(scene, registry());
  sim.integrate(scene.run.t_end);
  return sim.state();
}

}  // namespace

// The impulse is the run stopped at its time, the planet's velocity changed, and the run went
// on: bitwise, for the LGVI and rk4 (both start afresh from the changed state).
TEST(Impulses, AreTheRunStoppedTheVelocityChangedAndGoneOn) {
  for (const char* integrator : {"integrator={plugin: lgvi, step: 0.001}", "integrator={plugin: rk, method: rk4, step: 0.001}"}) {
    SCOPED_TRACE(integrator);
    const State with = final_state(kicked({integrator}));
    Simulation by_hand(test::kepler_scene({integrator}), registry());
    by_hand.integrate(1.25);
    State s = by_hand.state();
    s.p.col(1) += 1e-3 * Vec3(0.01, -0.02, 0.005);
    by_hand.set_state(s);
    by_hand.integrate(2.0);
    EXPECT_EQ((with.x - by_hand.state().x).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ((with.p - by_hand.state().p).cwiseAbs().maxCoeff(), 0.0);
  }
}

// The jump changes the energy by ½ m (|v + Δv|² − |v|²), 1 % of |E0| here; the verdict measures
// the integrator's error from references moved by it (as without the impulse), and says how
// much the impulses changed.
TEST(Impulses, MoveTheVerdictsReferences) {
  Simulation sim(kicked(), registry());
  sim.integrate(2.0);
  const RunSummary s = sim.finish();
  Simulation plain(test::kepler_scene(), registry());
  plain.integrate(2.0);
  const RunSummary p = plain.finish();
  EXPECT_EQ(s.impulses, 1);
  EXPECT_GT(std::abs(s.impulse_energy), 5e-3 * std::abs(p.initial.energy));
  EXPECT_LT(s.max_rel_energy_error, 2 * p.max_rel_energy_error + 1e-12);
  EXPECT_LT(s.max_rel_linear_momentum_error, 1e-13);
  EXPECT_LT(s.max_rel_angular_momentum_error, 1e-13);
  EXPECT_TRUE(s.verdict.trustworthy);
  EXPECT_EQ(s.frames, 5u);  // 0, 1, 1.25 before and after the jump, 2
}

// ∂z/∂Δv starts at 0 and jumps by m at the impulse (24.2); a mass's column gains (∂m/∂p) Δv
// there. Both against central differences of whole runs, for the LGVI, rk4 and cvode (measured:
// 2e-9 and 8e-8 with rk4).
TEST(Impulses, SensitivitiesToTheDeltaVAndTheMassAgreeWithDifferences) {
  for (const char* integrator : {"integrator={plugin: lgvi, step: 0.001}", "integrator={plugin: rk, method: rk4, step: 0.001}",
                                 "integrator={plugin: cvode, rtol: 1e-12, atol: 1e-15}"}) {
    SCOPED_TRACE(integrator);
    Simulation sim(kicked({integrator, "run.sensitivities=[impulses.0.delta_v, bodies.planet.mass]"}), registry());
    sim.integrate(2.0);
    const Eigen::MatrixXd& V = sim.state().tangent;
    ASSERT_EQ(V.cols(), 4);
    const Vec3 dv(0.01, -0.02, 0.005);
    auto moved = [&](const std::string& set) {
      return final_state(test::kepler_scene({integrator, set}));
    };
    const double h = 1e-6;
    for (int a = 0; a < 3; ++a) {
      Vec3 plus = dv, minus = dv;
      plus(a) += h, minus(a) -= h;
      auto impulse = [](const Vec3& v) {
        std::ostringstream text;
        text.precision(17);
        text << "impulses=[{body: planet, time: 1.25, delta_v: [" << v(0) << ", " << v(1) << ", " << v(2) << "]}]";
        return text.str();
      };
      const Eigen::VectorXd column = State::difference(moved(impulse(minus)), moved(impulse(plus))) / (2 * h);
      EXPECT_LE((column - V.col(a)).norm(), 1e-6 * V.col(a).norm()) << "delta_v." << a;
    }
    const double m = 1e-3, d = 1e-4 * m;
    auto with_mass = [&](double mass) {
      std::ostringstream text;
      text.precision(17);
      text << "bodies.planet.mass=" << mass;
      Scene s = kicked({integrator, text.str()});
      Simulation run(s, registry());
      run.integrate(2.0);
      return run.state();
    };
    const Eigen::VectorXd column = State::difference(with_mass(m - d), with_mass(m + d)) / (2 * d);
    EXPECT_LE((column - V.col(3)).norm(), 1e-6 * V.col(3).norm()) << "mass";
  }
}

// A Δv in the RTN frame (radial, along-track, normal of the planet's orbit about the sun at the
// impulse's time) is the inertial Q Δv with Q's columns r̂, n̂ × r̂, n̂ of that state (24.4).
TEST(Impulses, InTheRtnFrameAreTheOrbitsAxesAtTheirTime) {
  const char* integrator = "integrator={plugin: rk, method: rk4, step: 0.001}";
  const State with = final_state(test::kepler_scene(
      {integrator, "impulses=[{body: planet, time: 1.25, delta_v: [0.01, -0.02, 0.005], frame: rtn}]"}));
  Simulation by_hand(test::kepler_scene({integrator}), registry());
  by_hand.integrate(1.25);
  State s = by_hand.state();
  const Vec3 r = s.x.col(1) - s.x.col(0), v = s.p.col(1) / 1e-3 - s.p.col(0) / 1.0;
  const Vec3 rhat = r / r.norm(), nhat = r.cross(v) / r.cross(v).norm(), that = nhat.cross(rhat);
  s.p.col(1) += 1e-3 * (0.01 * rhat - 0.02 * that + 0.005 * nhat);
  by_hand.set_state(s);
  by_hand.integrate(2.0);
  EXPECT_LE((with.x - by_hand.state().x).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LE((with.p - by_hand.state().p).cwiseAbs().maxCoeff(), 1e-18);
  // An along-track Δv on this prograde orbit adds energy: ½ m (2 v·t̂ Δv + Δv²) > 0.
  Simulation along(test::kepler_scene({integrator, "impulses=[{body: planet, time: 1.25, delta_v: [0, 0.01, 0], frame: rtn}]"}),
                   registry());
  along.integrate(2.0);
  EXPECT_GT(along.finish().impulse_energy, 0.0);
  // On a radial orbit (velocity along the position) the along-track direction is undefined: the
  // run stops with an error that names the impulse, its body, what it orbits and its time.
  Simulation radial(test::kepler_scene({integrator, "bodies.planet.velocity=[0.5, 0, 0]",
                                        "impulses=[{body: planet, time: 0.25, delta_v: [0, 0.01, 0], frame: rtn}]"}),
                    registry());
  try {
    radial.integrate(2.0);
    FAIL() << "an RTN impulse on a radial orbit was applied";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("impulses.0 (body 'planet' about 'sun', t = 0.25)"), std::string::npos) << what;
    EXPECT_NE(what.find("needs an orbit"), std::string::npos) << what;
  }
}

// The tangent's jump in the RTN frame turns with the orbit (24.6), and the sensitivity to the
// impulse's time is the jump of the vector field (24.7): the STM (through a velocity key), the
// mass, Δv_RTN and the time against central differences of whole runs, for the adaptive cvode and
// rkf78 (the time moves freely) and, without the time, the LGVI and rk4 on their grid.
TEST(Impulses, SensitivitiesInTheRtnFrameAndToTheTimeAgreeWithDifferences) {
  const std::string base_impulse = "{body: planet, time: 1.25, delta_v: [0.01, -0.02, 0.005], frame: rtn";
  for (const char* integrator : {"integrator={plugin: cvode, rtol: 1e-12, atol: 1e-15}",
                                 "integrator={plugin: rk, method: rkf78, rtol: 1e-13, atol: 1e-16}",
                                 "integrator={plugin: lgvi, step: 0.001}", "integrator={plugin: rk, method: rk4, step: 0.001}"}) {
    SCOPED_TRACE(integrator);
    const bool adaptive = std::string(integrator).find("step:") == std::string::npos;
    const std::string keys = std::string("run.sensitivities=[bodies.planet.velocity.1, bodies.planet.mass, impulses.0.delta_v") +
                             (adaptive ? ", impulses.0.time]" : "]");
    Simulation sim(test::kepler_scene({integrator, "impulses=[" + base_impulse + "}]", keys}), registry());
    sim.integrate(2.0);
    const Eigen::MatrixXd& V = sim.state().tangent;
    ASSERT_EQ(V.cols(), adaptive ? 6 : 5);
    auto run = [&](const std::string& impulse, const std::string& set) {
      std::vector<std::string> o{integrator, "impulses=[" + impulse + "}]"};
      if (!set.empty()) o.push_back(set);
      return final_state(test::kepler_scene(o));
    };
    auto number = [](double x) {
      std::ostringstream t;
      t.precision(17);
      t << x;
      return t.str();
    };
    const auto& names = sim.sensitivity_names();
    auto check = [&](const Eigen::VectorXd& differenced, const std::string& key, const char* what) {
      const auto found = std::find(names.begin(), names.end(), key);
      ASSERT_NE(found, names.end()) << key;
      const auto column = static_cast<Eigen::Index>(found - names.begin());
      const double error = (differenced - V.col(column)).norm() / V.col(column).norm();
      std::printf("%-28s relative difference %.1e\n", what, error);
      EXPECT_LE(error, 1e-6) << what;
    };
    const double hv = 1e-6;  // the velocity's y component (2.0)
    check(State::difference(run(base_impulse, "bodies.planet.velocity.1=" + number(2.0 - hv)),
                            run(base_impulse, "bodies.planet.velocity.1=" + number(2.0 + hv))) / (2 * hv),
          "bodies.planet.velocity.1", "velocity.1 (the STM's column)");
    const double m = 1e-3, dm = 1e-4 * m;
    check(State::difference(run(base_impulse, "bodies.planet.mass=" + number(m - dm)),
                            run(base_impulse, "bodies.planet.mass=" + number(m + dm))) / (2 * dm),
          "bodies.planet.mass", "mass");
    const Vec3 dv(0.01, -0.02, 0.005);
    for (int a = 0; a < 3; ++a) {
      Vec3 plus = dv, minus = dv;
      plus(a) += 1e-6, minus(a) -= 1e-6;
      auto impulse = [&](const Vec3& w) {
        return "{body: planet, time: 1.25, delta_v: [" + number(w(0)) + ", " + number(w(1)) + ", " + number(w(2)) +
               "], frame: rtn";
      };
      check(State::difference(run(impulse(minus), ""), run(impulse(plus), "")) / 2e-6,
            "impulses.0.delta_v." + std::to_string(a),
            a == 0 ? "delta_v.0 (radial)" : a == 1 ? "delta_v.1 (along-track)" : "delta_v.2 (normal)");
    }
    if (adaptive) {
      const double ht = 1e-5;
      auto at = [&](double t) {
        return "{body: planet, time: " + number(t) + ", delta_v: [0.01, -0.02, 0.005], frame: rtn";
      };
      check(State::difference(run(at(1.25 - ht), ""), run(at(1.25 + ht), "")) / (2 * ht), "impulses.0.time", "time");
    }
  }
}

// What is refused, with a message naming the key: an impulse off a fixed step's grid, at or
// before the start, on no body; the orbit tools. (Saving and continuing such a run:
// tests/test_impulse_feature.cpp.)
TEST(Impulses, AreRefusedWhereTheyCannotBeApplied) {
  auto refused = [](const std::vector<std::string>& set, const char* expected) {
    try {
      Scene s = test::kepler_scene(set);
      Simulation sim(s, registry());
      ADD_FAILURE() << "accepted: " << set.back();
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  refused({"impulses=[{body: planet, time: 1.2345, delta_v: [0, 0.01, 0]}]"}, "impulses.0.time");
  refused({"impulses=[{body: planet, time: 0, delta_v: [0, 0.01, 0]}]"}, "must be a time after the start");
  refused({"impulses=[{body: planets, time: 1, delta_v: [0, 0.01, 0]}]"}, "did you mean 'planet'");
  refused({"impulses=[{body: planet, time: 1}]"}, "needs 'delta_v'");
  refused({kImpulse, "run.sensitivities=[impulses.1.delta_v]"}, "names no impulse");
  refused({kImpulse, "run.sensitivities=[impulses.0.mass]"}, "or its time (impulses.0.time)");
  refused({"impulses=[{body: planet, time: 1, delta_v: [0, 0.01, 0], frame: lvlh}]"}, "it must be inertial");
  refused({"impulses=[{body: planet, time: 1, delta_v: [0, 0.01, 0], frame: rtn, around: planet}]"},
          "cannot orbit itself");
  refused({"impulses=[{body: planet, time: 1, delta_v: [0, 0.01, 0], around: sun}]"}, "used only with frame: rtn");
  EXPECT_THROW(FullBodyModel::from_scene(kicked(), registry()), SceneError);
}
