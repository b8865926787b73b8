// MEGNO and the fast Lyapunov indicator (run.chaos; docs/derivatives.md "Chaos indicators",
// docs/equations.md §23): their discretization against closed forms, and the behaviour the
// literature gives them (Cincotta & Simó 2000): ⟨Y⟩ → 2 on regular orbits (the Kepler problem, a
// stable libration), ⟨Y⟩ ≈ λ t / 2 on a chaotic one (a tumbling moon).
#include "test_support.hpp"

#include "run/chaos_indicators.hpp"

#include <noether/output.hpp>
#include <noether/simulation.hpp>

#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <filesystem>
#include <vector>

using namespace noether;
using test::registry;

namespace {

// The Kepler orbit over 1000 time units (156 orbits) with run.chaos, and more overrides.
Scene kepler(std::vector<std::string> overrides = {}) {
  overrides.insert(overrides.begin(), {"run.t_end=1000", "run.output_every=100", "run.chaos=true"});
  return test::kepler_scene(overrides);
}

ChaosValues run_chaos(const Scene& scene) {
  Simulation sim(scene, registry());
  sim.integrate(scene.run.t_end);
  const RunSummary s = sim.finish();
  EXPECT_TRUE(s.chaos);
  return s.chaos_values;
}

const std::vector<std::string> kSynchronous = {"bodies.moon.orbit.e=0", "bodies.moon.angular_velocity=[0,0,1.02]"};

}  // namespace

// The discretization (eqs. 23.2, 23.3) against closed forms: an exponential growth ‖δ‖ = e^{λs}
// gives Y = λ s and ⟨Y⟩ = λ s / 2 exactly (the midpoint and trapezoid rules are exact on it); a
// linear one ‖δ‖ = 1 + b s gives Y = 2 (1 − ln(1 + b s) / (b s)), → 2.
TEST(ChaosIndicators, DiscretizationAgreesWithClosedForms) {
  const Scene scene = kepler();
  ChaosIndicators exponential(scene.system, scene.initial), linear(scene.system, scene.initial);
  const Eigen::VectorXd d0 = exponential.initial_deviation();
  EXPECT_NEAR(exponential.norm(d0), 1.0, 1e-15);
  exponential.start(3.0, d0);
  linear.start(3.0, d0);
  const double lambda = 0.7, b = 5.0;
  for (int k = 1; k <= 20000; ++k) {
    const double s = 1e-3 * k;
    exponential.step(3.0 + s, d0 * std::exp(lambda * s));
    linear.step(3.0 + s, d0 * (1.0 + b * s));
  }
  const double s = 20.0;
  EXPECT_NEAR(exponential.values().megno_y, lambda * s, 1e-10);
  EXPECT_NEAR(exponential.values().megno, lambda * s / 2, 1e-10);
  EXPECT_NEAR(exponential.values().lyapunov, lambda, 1e-12);
  EXPECT_NEAR(exponential.values().fli, lambda * s / std::log(10.0), 1e-10);
  const double y = 2.0 * (1.0 - std::log1p(b * s) / (b * s));
  EXPECT_NEAR(linear.values().megno_y, y, 1e-6);
  // ⟨Y⟩ = (1/s) ∫ Y: 2 − (2/(b s)) ∫_0^{bs} ln(1+u)/u du, the integral by a fine midpoint sum.
  double integral = 0.0;
  const int n = 2000000;
  for (int k = 0; k < n; ++k) {
    const double u = (k + 0.5) * b * s / n;
    integral += std::log1p(u) / u * (b * s / n);
  }
  EXPECT_NEAR(linear.values().megno, 2.0 - 2.0 / (b * s) * integral, 1e-5);
  // A deviation beyond the doubles stops them there, and says so.
  exponential.step(40.0, d0 * std::numeric_limits<double>::infinity());
  EXPECT_TRUE(exponential.values().overflowed);
  EXPECT_DOUBLE_EQ(exponential.values().t, 23.0);
}

// The Kepler problem is regular (non-isochronous: ‖δ‖ grows linearly): ⟨Y⟩ → 2 for each
// integrator's own tangent map, the LGVI's discrete one and the variational equations of rk
// and cvode (measured: 2.0021 at t = 1000, 156 orbits).
TEST(ChaosIndicators, MegnoTendsToTwoOnTheKeplerProblem) {
  for (const char* integrator : {"integrator={plugin: lgvi, step: 0.001}",
                                 "integrator={plugin: rk, method: dopri5, rtol: 1e-11, atol: 1e-14}",
                                 "integrator={plugin: cvode, rtol: 1e-11, atol: 1e-14}"}) {
    SCOPED_TRACE(integrator);
    const ChaosValues c = run_chaos(kepler({integrator}));
    EXPECT_NEAR(c.megno, 2.0, 0.01);
    EXPECT_DOUBLE_EQ(c.t, 1000.0);
    EXPECT_LT(c.fli, 6.0);  // ‖δ‖ ~ t: log10 of a few thousand
  }
}

// A synchronous moon on a circular orbit librates (regular): ⟨Y⟩ stays near 2 (measured 1.9882
// at t = 1000), and the LGVI's discrete tangent map and dopri5's variational equations agree on
// it (at t = 300, where dopri5's run costs a third).
TEST(ChaosIndicators, MegnoStaysNearTwoOnAStableLibration) {
  auto librating = [](std::vector<std::string> set) {
    set.insert(set.end(), kSynchronous.begin(), kSynchronous.end());
    set.push_back("run.chaos=true");
    return run_chaos(load_scene(test::source_path("examples/tumbling-moon.yaml"), set));
  };
  EXPECT_NEAR(librating({}).megno, 2.0, 0.05);
  const ChaosValues lgvi = librating({"run.t_end=300"}),
                    dopri5 = librating({"run.t_end=300", "integrator={plugin: rk, method: dopri5, rtol: 1e-11, atol: 1e-14}"});
  EXPECT_NEAR(lgvi.megno, 2.0, 0.1);
  EXPECT_NEAR(lgvi.megno, dopri5.megno, 1e-3);
}

// The tumbling moon is chaotic: ⟨Y⟩ grows linearly, at the rate λ/2 of the Lyapunov exponent
// that ln‖δ‖/t estimates independently (measured: ⟨Y⟩ = 69.2 at t = 1000, λ ≈ 0.140; slope over
// [500, 1000] 0.056).
TEST(ChaosIndicators, MegnoGrowsLinearlyOnATumblingMoon) {
  Scene scene = load_scene(test::source_path("examples/tumbling-moon.yaml"), {"run.chaos=true"});
  Simulation sim(scene, registry());
  std::vector<double> t, megno;
  for (int k = 1; k <= 10; ++k) {
    sim.integrate(100.0 * k);
    t.push_back(sim.summary().chaos_values.t);
    megno.push_back(sim.summary().chaos_values.megno);
  }
  const ChaosValues c = sim.finish().chaos_values;
  EXPECT_GT(c.megno, 30.0);
  EXPECT_GT(c.fli, 30.0);
  EXPECT_FALSE(c.overflowed);
  // The least-squares slope of ⟨Y⟩ over the second half against λ/2.
  double st = 0, sy = 0, stt = 0, sty = 0;
  for (std::size_t k = 4; k < t.size(); ++k) st += t[k], sy += megno[k], stt += t[k] * t[k], sty += t[k] * megno[k];
  const double n = static_cast<double>(t.size() - 4), slope = (n * sty - st * sy) / (n * stt - st * st);
  EXPECT_GT(slope, 0.6 * c.lyapunov / 2);
  EXPECT_LT(slope, 1.4 * c.lyapunov / 2);
  EXPECT_NEAR(c.megno / (c.lyapunov * c.t / 2), 1.0, 0.3);
}

// The deviation column sits between the STM's and the sensitivities' (docs/derivatives.md): with
// chaos on, the STM and the sensitivities are those of the run without it.
TEST(ChaosIndicators, LeaveTheStmAndTheSensitivitiesAsTheyAre) {
  for (const char* integrator : {"integrator={plugin: lgvi, step: 0.001}", "integrator={plugin: rk, method: rk4, step: 0.001}"}) {
    SCOPED_TRACE(integrator);
    const std::vector<std::string> set = {integrator, "run.t_end=2", "run.output_every=1", "run.chaos=false",
                                          "run.stm=true", "run.sensitivities=[bodies.planet.velocity, G]"};
    Simulation without(kepler(set), registry());
    std::vector<std::string> with_set = set;
    with_set.push_back("run.chaos=true");
    Simulation with(kepler(with_set), registry());
    without.integrate(2.0);
    with.integrate(2.0);
    const Eigen::MatrixXd &a = without.state().tangent, &b = with.state().tangent;
    ASSERT_EQ(b.cols(), a.cols() + 1);
    const Eigen::Index N = a.rows();
    EXPECT_LE((a.leftCols(N) - b.leftCols(N)).norm(), 1e-12 * a.leftCols(N).norm());
    EXPECT_LE((a.rightCols(4) - b.rightCols(4)).norm(), 1e-12 * a.rightCols(4).norm());
    // And the deviation is the STM applied to δ0.
    const ChaosIndicators indicators(with.scene().system, with.scene().initial);
    const Eigen::VectorXd delta = b.leftCols(N) * indicators.initial_deviation();
    EXPECT_LE((b.col(N) - delta).norm(), 1e-10 * delta.norm());
  }
}

// The output file holds ⟨Y⟩ and the FLI at every frame, the last equal to the summary's; a new
// segment (set_state) starts them again.
TEST(ChaosIndicators, AreWrittenAtEveryFrameAndRestartWithANewSegment) {
  const auto file = std::filesystem::temp_directory_path() / "noether-chaos-frames.h5";
  RunOptions options;
  options.output = file;
  options.overwrite = true;
  Simulation sim(kepler({"run.t_end=100", "run.output_every=10"}), registry(), options);
  sim.integrate(100.0);
  const RunSummary s = sim.finish();
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  std::vector<double> megno(11), fli(11);
  for (auto [path, into] : {std::pair<const char*, std::vector<double>*>{"/derivatives/megno/value", &megno},
                            {"/derivatives/fli/value", &fli}}) {
    const hid_t d = H5Dopen2(f, path, H5P_DEFAULT);
    ASSERT_GE(d, 0) << path;
    const hid_t space = H5Dget_space(d);
    hsize_t dims[1];
    H5Sget_simple_extent_dims(space, dims, nullptr);
    ASSERT_EQ(dims[0], 11u) << path;
    H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, into->data());
    H5Sclose(space);
    H5Dclose(d);
  }
  H5Fclose(f);
  std::filesystem::remove(file);
  EXPECT_TRUE(std::isnan(megno[0]));  // no step yet at t0
  EXPECT_DOUBLE_EQ(megno[10], s.chaos_values.megno);
  EXPECT_DOUBLE_EQ(fli[10], s.chaos_values.fli);
  for (std::size_t k = 2; k < fli.size(); ++k) EXPECT_GE(fli[k], fli[k - 1]);  // a running maximum

  Simulation again(kepler({"run.t_end=100", "run.output_every=10"}), registry());
  again.integrate(50.0);
  State s50 = again.state();
  s50.tangent.resize(0, 0);
  again.set_state(s50);
  EXPECT_TRUE(std::isnan(again.summary().chaos_values.megno));
  again.integrate(60.0);
  EXPECT_DOUBLE_EQ(again.summary().chaos_values.t, 60.0);
  EXPECT_GT(again.summary().chaos_values.megno, 0.0);
  EXPECT_LT(again.summary().chaos_values.megno, 3.0);
}

// An integrator without a tangent map refuses run.chaos, naming it. (A run that carries them
// continues: tests/test_chaos_feature.cpp.)
TEST(ChaosIndicators, AreRefusedWhereNoTangentMapIsCarried) {
  try {
    Simulation sim(test::dumbbell_scene({"run.chaos=true", "integrator={plugin: cvode, frame: relative}"}), registry());
    FAIL() << "cvode in the relative frame carried the deviation";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("run.chaos"), std::string::npos) << e.what();
  }
}
