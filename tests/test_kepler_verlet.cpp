// With point masses only, lgvi is velocity Verlet; on a Kepler orbit its energy error stays
// bounded and its phase error falls as h².
#include "test_support.hpp"

#include <noether/error.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace noether;

namespace {

constexpr double kPi = std::numbers::pi;

// Two bodies, G (m1 + m2) = 1, a = 1, e = 0.5, starting at periapsis in the centre-of-mass
// frame: period 2π.
Scene kepler(double h, double t_end, double output_every) {
  const double m1 = 0.999, m2 = 0.001, e = 0.5;
  const double r = 1.0 - e, v = std::sqrt((1.0 + e) / (1.0 - e));
  char text[1024];
  std::snprintf(text, sizeof text, R"(G: 1
bodies:
  - {name: sun, mass: %.17g, position: [%.17g, 0, 0], velocity: [0, %.17g, 0]}
  - {name: planet, mass: %.17g, position: [%.17g, 0, 0], velocity: [0, %.17g, 0]}
potential: {plugin: point-mass}
integrator: {plugin: lgvi, step: %.17g}
run: {t_end: %.17g, output_every: %.17g}
)",
                m1, -m2 * r, -m2 * v, m2, m1 * r, m1 * v, h, t_end, output_every);
  return parse_scene(text, "kepler");
}

struct Recorder final : Observer {
  std::vector<State> states;
  std::vector<double> energies;
  const System* system = nullptr;
  void observe(const State& s, const Forces& f, bool) override {
    states.push_back(s);
    double T = 0;
    for (Eigen::Index i = 0; i < s.p.cols(); ++i)
      T += s.p.col(i).squaredNorm() / (2 * system->body(static_cast<std::size_t>(i)).mass);
    energies.push_back(T + f.U);
  }
};

Recorder integrate(const Scene& scene) {
  auto registry = test::bundled_plugins();
  auto potential = registry.make_potential("point-mass", scene.system, Params());
  auto lgvi = registry.make_integrator("lgvi", scene.system, potential, scene.integrator.params);
  Recorder rec;
  rec.system = &scene.system;
  State s = scene.initial;
  noether::advance(*lgvi, *potential, scene.system, s, {scene.run.t_end, scene.run.output_every}, rec);
  return rec;
}

}  // namespace

// Velocity Verlet written out by hand, the same step size: the same trajectory to round-off.
TEST(LgviPointMasses, IsVelocityVerlet) {
  const double h = 2 * kPi / 256;
  const Scene scene = kepler(h, 256 * h, h);
  const Recorder rec = integrate(scene);
  const double G = scene.system.G();
  const double m1 = scene.system.body(0).mass, m2 = scene.system.body(1).mass;
  Eigen::Matrix3Xd x = scene.initial.x, v(3, 2);
  v.col(0) = scene.initial.p.col(0) / m1;
  v.col(1) = scene.initial.p.col(1) / m2;
  auto accel = [&](const Eigen::Matrix3Xd& xx) {
    const Vec3 d = xx.col(1) - xx.col(0);
    const double r3 = std::pow(d.norm(), 3);
    Eigen::Matrix3Xd a(3, 2);
    a.col(0) = G * m2 * d / r3;
    a.col(1) = -G * m1 * d / r3;
    return a;
  };
  Eigen::Matrix3Xd a = accel(x);
  double worst = 0;
  for (std::size_t k = 1; k < rec.states.size(); ++k) {
    const Eigen::Matrix3Xd v_half = v + 0.5 * h * a;
    x += h * v_half;
    a = accel(x);
    v = v_half + 0.5 * h * a;
    worst = std::max(worst, (rec.states[k].x - x).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-13);
}

// Over 100 orbits the energy error oscillates without drifting: the worst error of the last
// ten orbits is no larger than that of the first ten.
TEST(LgviPointMasses, KeplerEnergyStaysBounded) {
  const double T = 2 * kPi, h = T / 500;
  const Recorder rec = integrate(kepler(h, 100 * T, 10 * h));
  const double E0 = rec.energies.front();
  const std::size_t per_orbit = 50, n = rec.energies.size();
  double first = 0, last = 0;
  for (std::size_t k = 0; k < 10 * per_orbit; ++k) first = std::max(first, std::abs(rec.energies[k] - E0));
  for (std::size_t k = n - 10 * per_orbit; k < n; ++k) last = std::max(last, std::abs(rec.energies[k] - E0));
  EXPECT_GT(first, 0.0);
  EXPECT_LT(last, 1.05 * first) << "first ten orbits " << first << ", last ten " << last;
  EXPECT_LT(first / std::abs(E0), 1e-3);
}

// The phase error after ten periods (a measure of the period error) falls as h².
TEST(LgviPointMasses, KeplerPeriodErrorIsSecondOrder) {
  const double T = 2 * kPi;
  std::vector<double> errors;
  for (int n : {400, 800, 1600}) {
    const double h = T / n;
    const Recorder rec = integrate(kepler(h, 10 * T, 10 * T));
    const State& s = rec.states.back();
    const Vec3 r = s.x.col(1) - s.x.col(0);
    errors.push_back(std::abs(std::atan2(r.y(), r.x())));  // periapsis is at angle 0
  }
  EXPECT_NEAR(errors[0] / errors[1], 4.0, 0.4) << errors[0] << " " << errors[1];
  EXPECT_NEAR(errors[1] / errors[2], 4.0, 0.4) << errors[1] << " " << errors[2];
}
