// The baselines on the continuous equations: cvode (Adams, BDF) and rk (rk4, dopri5, rkf78).
// Each converges to the analytic Kepler solution as its tolerance or step tightens, RK4 at
// order 4; R drifts off SO(3) unless renormalize is asked for; CVODE's close-approach event
// and its failures surface as clear results.
#include "test_support.hpp"

#include <noether/error.hpp>
#include <noether/simulation.hpp>

#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <unistd.h>

using namespace noether;

namespace {

constexpr double kPi = std::numbers::pi;

// Circular two-body orbit, G (m1 + m2) = 1, radius 1, period 2π; exactly 3 periods.
Scene circular(const std::string& integrator) {
  const double m1 = 0.75, m2 = 0.25;
  char text[1024];
  std::snprintf(text, sizeof text, R"(G: 1
bodies:
  - {name: a, mass: %.17g, position: [%.17g, 0, 0], velocity: [0, %.17g, 0]}
  - {name: b, mass: %.17g, position: [%.17g, 0, 0], velocity: [0, %.17g, 0]}
potential: {plugin: point-mass}
integrator: %s
run: {t_end: %.17g, output_every: %.17g}
)",
                m1, -m2, -m2, m2, m1, m1, integrator.c_str(), 6 * kPi, kPi / 8);
  return parse_scene(text, "circular");
}

// Distance of the final relative position from the analytic one (back at (1, 0, 0)).
double kepler_error(const std::string& integrator) {
  auto registry = test::bundled_plugins();
  const RunSummary s = run_scene(circular(integrator), registry, {});
  const Vec3 r = s.final_state.x.col(1) - s.final_state.x.col(0);
  return (r - Vec3(1, 0, 0)).norm();
}

}  // namespace

TEST(Baselines, AdaptiveMethodsConvergeAsTolerancesTighten) {
  for (const std::string method : {"cvode, method: adams", "cvode, method: bdf", "rk, method: dopri5",
                                   "rk, method: rkf78"}) {
    std::vector<double> errors;
    for (const char* tol : {"1.0e-5", "1.0e-7", "1.0e-9"})
      errors.push_back(kepler_error("{plugin: " + method + ", rtol: " + tol + ", atol: " + tol + "}"));
    EXPECT_LT(errors[1], 0.5 * errors[0]) << method;
    EXPECT_LT(errors[2], 0.5 * errors[1]) << method;
    EXPECT_LT(errors[2], 1e-4) << method << ": " << errors[2];
  }
}

TEST(Baselines, Rk4IsFourthOrder) {
  auto step = [](double h) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "{plugin: rk, method: rk4, step: %.17g}", h);
    return std::string(buf);
  };
  const double coarse = kepler_error(step(kPi / 128)), fine = kepler_error(step(kPi / 256));
  // Observed order log2(e(h)/e(h/2)); measured 4.23 (the h⁵ term still shows at h = π/128).
  EXPECT_NEAR(std::log2(coarse / fine), 4.0, 0.3) << coarse << " / " << fine;
}

// Lee et al.'s point: a Runge–Kutta on the continuous equations drifts off SO(3); the LGVI does
// not. With renormalize the drift is projected away at every step (opt-in).
TEST(Baselines, RungeKuttaDriftsOffSO3UnlessRenormalized) {
  auto registry = test::bundled_plugins();
  const auto drift = [&](const std::string& integrator) {
    return run_scene(test::dumbbell_scene({"integrator=" + integrator}), registry, {})
        .max_orthogonality_error;
  };
  const double lgvi = drift("{plugin: lgvi, step: 0.001}");
  const double dopri5 = drift("{plugin: rk, method: dopri5, rtol: 1.0e-6, atol: 1.0e-8}");
  const double rk4 = drift("{plugin: rk, method: rk4, step: 0.001}");
  const double rk4_projected = drift("{plugin: rk, method: rk4, step: 0.001, renormalize: true}");
  EXPECT_LE(lgvi, 1e-12);
  EXPECT_GT(dopri5, 1e-6);
  EXPECT_GT(rk4, 1e-11);
  EXPECT_LE(rk4_projected, 1e-14);
}

TEST(Baselines, CvodeStopsAtACloseApproach) {
  auto registry = test::bundled_plugins();
  const RunSummary s = run_scene(
      test::dumbbell_scene({"integrator={plugin: cvode, rtol: 1.0e-10, atol: 1.0e-12}", "run.close_approach=0.5"}),
      registry, {});
  EXPECT_NE(s.stop_reason.find("close approach: bodies 'alpha' and 'beta' came within 0.5"),
            std::string::npos) << s.stop_reason;
  const double d = (s.final_state.x.col(0) - s.final_state.x.col(1)).norm();
  EXPECT_NEAR(d, 0.5, 1e-8);  // the event is located by root finding, not at an output time
  EXPECT_GT(s.final_state.t, 8.0);
  EXPECT_LT(s.final_state.t, 9.0);
}

// Too much work: a clear error with the time reached, and the output so far stays readable.
TEST(Baselines, CvodeFailureKeepsTheOutput) {
  const auto file = std::filesystem::temp_directory_path() /
                    ("noether-cvode-fail-" + std::to_string(getpid()) + ".h5");
  auto registry = test::bundled_plugins();
  RunOptions options;
  options.output = file;
  try {
    run_scene(test::dumbbell_scene({"integrator={plugin: cvode, max_steps: 50}", "run.output_every=5"}),
              registry, options);
    FAIL() << "expected an IntegrationError";
  } catch (const IntegrationError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("CV_TOO_MUCH_WORK"), std::string::npos) << what;
    EXPECT_NE(what.find("raise integrator.max_steps"), std::string::npos) << what;
    EXPECT_GT(e.t_reached(), 0.0);
  }
  hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  hid_t work = H5Gopen2(f, "/work", H5P_DEFAULT);
  ASSERT_GE(work, 0);  // the run's outcome is recorded
  EXPECT_GT(H5Aexists(work, "outcome"), 0);
  H5Gclose(work);
  H5Fclose(f);
  std::filesystem::remove(file);
}

TEST(Baselines, BadSettingsAreRefused) {
  auto registry = test::bundled_plugins();
  EXPECT_THROW(run_scene(test::dumbbell_scene({"integrator={plugin: rk, method: rk45}"}), registry, {}),
               SceneError);
  EXPECT_THROW(run_scene(test::dumbbell_scene({"integrator={plugin: rk, method: rk4}"}), registry, {}),
               SceneError);  // rk4 needs a step
  EXPECT_THROW(run_scene(test::dumbbell_scene({"integrator={plugin: cvode, method: radau}"}), registry, {}),
               SceneError);
}
