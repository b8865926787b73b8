// The commutative cube of Lee, Leok & McClamroch 2007 (Fig. 1 and 7): eight forms of the full-body equations —
// continuous or discrete, inertial or relative frame, Lagrangian or Hamiltonian — agree where
// the cube says they must.
#include "test_support.hpp"

#include <noether/error.hpp>
#include <noether/simulation.hpp>

#include <gtest/gtest.h>

#include <cmath>

using namespace noether;

namespace {

struct Trajectory final : Observer {
  std::vector<State> states;
  void observe(const State& s, const Forces&, bool) override { states.push_back(s); }
};

Trajectory integrate(const std::string& integrator, const std::vector<std::string>& more = {}) {
  std::vector<std::string> overrides{"integrator=" + integrator};
  overrides.insert(overrides.end(), more.begin(), more.end());
  const Scene scene = test::dumbbell_scene(overrides);
  auto registry = test::bundled_plugins();
  auto potential = registry.make_potential("sphere-cluster", scene.system, Params());
  auto integ = registry.make_integrator(scene.integrator.plugin, scene.system, potential,
                                        scene.integrator.params);
  Trajectory tr;
  State s = scene.initial;
  noether::advance(*integ, *potential, scene.system, s, {scene.run.t_end, scene.run.output_every}, tr);
  return tr;
}

struct Difference {
  double position = 0, attitude = 0;  // max over frames and bodies
};

// Largest difference of positions and of the dumbbell axes R e1 between two trajectories, over
// frames with t ≤ t_max. The rotation of a dumbbell about its own axis is left out: U does not
// depend on it and its moment of inertia is tiny (J1 = 0.0004), so round-off in Π·e1 becomes a
// free phase about the axis (measured 6.6e-10 rad at t = 5 between the inertial and relative
// forms at h = 2e-4, growing with the number of steps, not with h) that affects nothing else.
Difference difference(const Trajectory& a, const Trajectory& b, double t_max = 1e300) {
  Difference d;
  EXPECT_EQ(a.states.size(), b.states.size());
  for (std::size_t k = 0; k < std::min(a.states.size(), b.states.size()); ++k) {
    if (a.states[k].t > t_max) break;
    d.position = std::max(d.position, (a.states[k].x - b.states[k].x).cwiseAbs().maxCoeff());
    for (std::size_t r = 0; r < a.states[k].R.size(); ++r)
      d.attitude = std::max(d.attitude, (a.states[k].R[r].col(0) - b.states[k].R[r].col(0)).cwiseAbs().maxCoeff());
  }
  return d;
}

const char* kForm[] = {"frame: inertial, form: hamiltonian", "frame: inertial, form: lagrangian",
                       "frame: relative, form: hamiltonian", "frame: relative, form: lagrangian"};

std::string lgvi(double h, const std::string& form, int order = 2) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "{plugin: lgvi, step: %.17g, %s, order: %d}", h, form.c_str(), order);
  return buf;
}

}  // namespace

// Right face of the cube: the four discrete forms give one trajectory for one h. Before the
// close approach at t ≈ 9 they agree to round-off (≤ 1e-12); the close approach amplifies any
// round-off difference about 1.5e4-fold (one ulp in x0 grows to 1.6e-12 by t = 20), so over the
// whole run they agree to what round-off allows (measured ≤ 1.2e-10 in x, 1.7e-9 in R e1).
TEST(Cube, DiscreteFormsGiveOneTrajectory) {
  const Trajectory reference = integrate(lgvi(2e-4, kForm[0]));
  for (int f = 1; f < 4; ++f) {
    const Trajectory other = integrate(lgvi(2e-4, kForm[f]));
    const Difference before = difference(reference, other, 8.5);
    const Difference all = difference(reference, other);
    EXPECT_LE(before.position, 1e-12) << kForm[f];
    EXPECT_LE(before.attitude, 1e-11) << kForm[f];  // measured ≤ 4.4e-12
    EXPECT_LE(all.position, 1e-9) << kForm[f];
    EXPECT_LE(all.attitude, 1e-8) << kForm[f];
  }
}

// Vertical edges: reducing the inertial discrete trajectory gives the relative one (the relative
// integrator reconstructs the inertial motion of both bodies, so compare X = R2ᵀ(x1 − x2) and
// the dumbbell axis R e1 with R = R2ᵀ R1), and the reconstruction at t0 is the initial state
// itself. Before the close approach the reduced variables agree to 1e-12 (measured 3e-13 in X);
// over the whole run to 1e-9 (measured 5.5e-10 in X: the amplified round-off as above, in a
// frame that has turned with body 2).
TEST(Cube, RelativeIsTheReducedInertial) {
  const Trajectory inertial = integrate(lgvi(2e-4, kForm[0]));
  const Trajectory relative = integrate(lgvi(2e-4, kForm[2]));
  double dX = 0, dX_before = 0, dR = 0, dR_before = 0;
  for (std::size_t k = 0; k < inertial.states.size(); ++k) {
    const State &a = inertial.states[k], &b = relative.states[k];
    const Vec3 Xa = a.R[1].transpose() * Vec3(a.x.col(0) - a.x.col(1));
    const Vec3 Xb = b.R[1].transpose() * Vec3(b.x.col(0) - b.x.col(1));
    const Vec3 ea = a.R[1].transpose() * a.R[0].col(0), eb = b.R[1].transpose() * b.R[0].col(0);
    dX = std::max(dX, (Xa - Xb).norm());
    dR = std::max(dR, (ea - eb).norm());
    if (a.t <= 8.5) dX_before = dX, dR_before = dR;
  }
  EXPECT_LE(dX_before, 1e-12);
  EXPECT_LE(dR_before, 1e-11);
  EXPECT_LE(dX, 1e-9);
  EXPECT_LE(dR, 1e-8);
  const State& s0 = relative.states.front();
  const State init = test::dumbbell_scene().initial;
  EXPECT_LE((s0.x - init.x).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LE((s0.p - init.p).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LE((s0.Pi - init.Pi).cwiseAbs().maxCoeff(), 1e-15);
}

// Left face: the four continuous forms, integrated at rtol 1e-12, agree to that tolerance.
TEST(Cube, ContinuousFormsAgreeToTheirTolerance) {
  const char* forms[] = {"frame: inertial, form: hamiltonian", "frame: inertial, form: lagrangian",
                         "frame: relative, form: hamiltonian", "frame: relative, form: lagrangian"};
  const Trajectory reference =
      integrate(std::string("{plugin: rk, method: rkf78, rtol: 1.0e-12, atol: 1.0e-14, ") + forms[0] + "}");
  for (int f = 1; f < 4; ++f) {
    const Trajectory other =
        integrate(std::string("{plugin: rk, method: rkf78, rtol: 1.0e-12, atol: 1.0e-14, ") + forms[f] + "}");
    const Difference d = difference(reference, other);
    EXPECT_LE(d.position, 1e-9) << forms[f];   // measured ≤ 3e-11
    EXPECT_LE(d.attitude, 1e-7) << forms[f];   // measured ≤ 5e-9 (spin about the dumbbell axis)
  }
}

// Discretization edges: every discrete form converges to the continuous solution at order 2,
// and at order 4 with Yoshida's composition, over four step sizes.
TEST(Cube, DiscreteFormsConvergeAtTheirOrder) {
  auto registry = test::bundled_plugins();
  const RunSummary ref = run_scene(
      test::dumbbell_scene({"integrator={plugin: rk, method: rkf78, rtol: 1.0e-13, atol: 1.0e-15}"}),
      registry, {});
  auto error = [&](const std::string& integrator) {
    const RunSummary s = run_scene(test::dumbbell_scene({"integrator=" + integrator}), registry, {});
    return (s.final_state.x - ref.final_state.x).cwiseAbs().maxCoeff();
  };
  // Under the sanitizers (65 s there) three step sizes: the smallest, half of the cost, is left out.
#ifdef NOETHER_TEST_SANITIZED
  const std::vector<double> steps{1e-3, 5e-4, 2.5e-4};
#else
  const std::vector<double> steps{1e-3, 5e-4, 2.5e-4, 1.25e-4};
#endif
  for (const char* form : kForm) {
    std::vector<double> e;
    for (double h : steps) e.push_back(error(lgvi(h, form)));
    for (std::size_t k = 1; k < e.size(); ++k)
      EXPECT_NEAR(std::log2(e[k - 1] / e[k]), 2.0, 0.15) << form << " h/" << (1 << k);
  }
  for (const char* form : {kForm[0], kForm[2]}) {
    std::vector<double> e;
    for (double h : {1e-2, 5e-3, 2.5e-3, 1.25e-3}) e.push_back(error(lgvi(h, form, 4)));
    for (std::size_t k = 1; k < e.size(); ++k)
      EXPECT_NEAR(std::log2(e[k - 1] / e[k]), 4.0, 0.3) << form << " order 4, h/" << (1 << k);
  }
}

// What each form conserves: momentum to round-off, SO(3) to round-off, bounded energy.
TEST(Cube, EveryDiscreteFormConservesWhatThePaperSays) {
  auto registry = test::bundled_plugins();
  for (const char* form : kForm) {
    const RunSummary s = run_scene(test::dumbbell_scene({"integrator=" + lgvi(2e-4, form)}), registry, {});
    EXPECT_LE(s.max_rel_linear_momentum_error, 1e-12) << form;
    EXPECT_LE(s.max_rel_angular_momentum_error, 1e-12) << form;
    EXPECT_LE(s.max_orthogonality_error, 1e-11) << form;
    EXPECT_NEAR(s.max_abs_energy_error, 2.6966e-7, 0.01 * 2.6966e-7) << form;
  }
}

TEST(Cube, RelativeFormsRefuseOtherScenes) {
  auto registry = test::bundled_plugins();
  const Scene three = load_scene(test::source_path("examples/figure-eight.yaml"));
  auto potential = registry.make_potential("point-mass", three.system, Params());
  for (const std::string plugin : {"{plugin: lgvi, step: 0.01, frame: relative}", "{plugin: rk, frame: relative}"}) {
    const Scene s = load_scene(test::source_path("examples/figure-eight.yaml"), {"integrator=" + plugin});
    try {
      registry.make_integrator(s.integrator.plugin, s.system, potential, s.integrator.params);
      FAIL() << plugin;
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find("needs exactly two rigid bodies"), std::string::npos) << e.what();
    }
  }
}
