// Relative periodic orbits of a rigid binary by shooting on an integrator's map (docs/equations.md
// §19): on the LGVI's discrete map a periodic orbit closes to round-off, and its multipliers
// converge to the continuous ones, exp(λ T) of the equilibrium's linearisation, at the method's
// order as h → 0. The continuous flow (rkf78) gives the same multipliers.
#include "test_support.hpp"

#include <noether/relative_equilibrium.hpp>
#include <noether/relative_periodic_orbit.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <sstream>

using namespace noether;

namespace {

Scene point_and_ellipsoid() {
  return parse_scene(
      "G: 1\nbarycentric: true\nbodies:\n"
      "  - {name: point, mass: 1, position: [0, 0, 0]}\n"
      "  - name: ellipsoid\n    mass: 1.0e-3\n    shape: {ellipsoid: {semi_axes: [0.2, 0.18, 0.15]}}\n"
      "    orbit: {around: point, a: 8, nu: 0}\n"
      "potential: {plugin: mutual-series, order: 2}\nintegrator: {plugin: lgvi, step: 0.2}\n"
      "run: {t_end: 1, output_every: 1}\n",
      "point-ellipsoid.yaml");
}

// The largest distance from a continuous multiplier to the nearest discrete one.
double multiplier_error(const std::vector<std::complex<double>>& continuous, const std::vector<std::complex<double>>& discrete) {
  double worst = 0;
  for (auto c : continuous) {
    double best = INFINITY;
    for (auto m : discrete) best = std::min(best, std::abs(c - m));
    worst = std::max(worst, best);
  }
  return worst;
}

// Two ellipsoids, tilted, spinning, off the barycentre (every term of the forces, moments and
// momenta nonzero).
Scene tilted_pair() {
  return parse_scene(
      "G: 1\nbodies:\n"
      "  - {name: a, mass: 1, position: [0.1, -0.2, 0.05], velocity: [0.01, 0.02, -0.03],\n"
      "     shape: {ellipsoid: {semi_axes: [0.5, 0.4, 0.3]}}, angular_velocity: [0.1, -0.2, 0.3],\n"
      "     attitude: {euler_angles: [0.3, 0.5, 0.7]}}\n"
      "  - name: b\n    mass: 0.3\n    shape: {ellipsoid: {semi_axes: [0.2, 0.18, 0.15]}}\n"
      "    position: [3, 1, -0.5]\n    velocity: [-0.1, 0.5, 0.2]\n"
      "    attitude: {euler_angles: [1.1, -0.4, 0.2]}\n    angular_velocity: [0.4, 0.1, -0.2]\n"
      "potential: {plugin: mutual-series, order: 4}\nintegrator: {plugin: lgvi, step: 0.1}\n"
      "run: {t_end: 1, output_every: 1}\n",
      "tilted.yaml");
}

}  // namespace

TEST(RelativePeriodicOrbit, DiscreteLgviOrbitClosesAndItsMultipliersConvergeAtTheMethodsOrder) {
  auto registry = test::bundled_plugins();
  const Scene s = point_and_ellipsoid();
  const auto model = FullBodyModel::from_scene(s, registry);
  const auto eq = find_relative_equilibrium(model, s.initial);
  ASSERT_TRUE(eq.converged);
  const auto st = linear_stability(model, eq);
  const double T = 0.25 * 2 * M_PI / eq.rate;  // a quarter of an orbit: the multipliers are far from 1
  std::vector<std::complex<double>> continuous;
  for (auto l : st.eigenvalues) continuous.push_back(std::exp(l * T));
  ASSERT_EQ(continuous.size(), 8u);  // point mass + rigid body: 4 modes

  // The continuous flow by rkf78: the same orbit (the equilibrium) and multipliers.
  const auto flow = test::plugin_config("{plugin: rk, method: rkf78, rtol: 1.0e-13, atol: 1.0e-16}");
  const auto orbit = shoot_relative_periodic_orbit(model, flow, eq.state, T, eq.rate * T, 1e-11);
  EXPECT_LT(orbit.closure, 1e-11);
  EXPECT_NEAR(orbit.angle, eq.rate * T, 1e-9);
  const auto mu = relative_orbit_multipliers(model, flow, orbit);
  ASSERT_EQ(mu.multipliers.size(), continuous.size());
  std::printf("flow (rkf78): closure %.1e, multipliers within %.1e of exp(lambda T), invariance defect %.1e\n",
              orbit.closure, multiplier_error(continuous, mu.multipliers), mu.invariance_defect);
  EXPECT_LT(multiplier_error(continuous, mu.multipliers), 1e-6);
  EXPECT_EQ(mu.verdict, "linearly stable");

  for (int order : {2, 4}) {
    double previous = 0;
    // Order 4 from 20 steps: at 320 its error (5e-9) meets the differencing's floor (the flow's
    // own multipliers are within 5e-9).
    for (int steps : order == 2 ? std::vector<int>{40, 80, 160, 320} : std::vector<int>{20, 40, 80, 160}) {
      std::ostringstream spec;
      spec.precision(17);
      spec << "{plugin: lgvi, step: " << T / steps << (order == 4 ? ", order: 4}" : "}");
      const auto lgvi = test::plugin_config(spec.str());
      const auto discrete = shoot_relative_periodic_orbit(model, lgvi, eq.state, T, eq.rate * T);
      const auto m = relative_orbit_multipliers(model, lgvi, discrete);
      const double error = multiplier_error(continuous, m.multipliers);
      std::printf("lgvi order %d, %3d steps: closure %.1e -> %.1e in %d Newton steps, alpha - omega T = %+.2e, "
                  "multiplier error %.3e%s, max |mu| - 1 = %.1e\n",
                  order, steps, discrete.initial_closure, discrete.closure, discrete.iterations, discrete.angle - eq.rate * T,
                  error, previous > 0 ? (" (ratio " + std::to_string(previous / error) + ")").c_str() : "",
                  m.max_modulus - 1);
      EXPECT_LT(discrete.closure, 1e-12);  // the discrete map's own orbit, closed to round-off
      EXPECT_GT(discrete.initial_closure, 1e3 * discrete.closure);  // and not the continuous one
      EXPECT_LT(m.max_modulus - 1, 1e-6);  // symplectic: on the unit circle
      if (previous > 0) EXPECT_NEAR(std::log2(previous / error), order, 0.35);
      previous = error;
    }
  }
}

// The gradients of E and L in a chart (used to reduce the monodromy) against central differences
// of the model's own energy and angular momentum, at a state with a tilted, spinning ellipsoid off
// the barycentre (every term of the forces, moments and momenta nonzero).
TEST(RelativePeriodicOrbit, ConservedGradientsAgreeWithDifferences) {
  auto registry = test::bundled_plugins();
  const Scene s = tilted_pair();
  const auto model = FullBodyModel::from_scene(s, registry);
  const PhaseChart chart(model.system, s.initial, 3.0, 0.3);
  Eigen::Matrix3Xd axes(3, 2);
  axes.col(0) = Vec3(0.3, -0.4, 0.866).normalized();
  axes.col(1) = Vec3(1, 0, 0);
  const Eigen::MatrixXd analytic = conserved_gradients(model, chart, axes);
  ASSERT_EQ(analytic.rows(), 3);
  const double h = 1e-5;
  double worst = 0;
  for (Eigen::Index j = 0; j < chart.dimension(); ++j) {
    Eigen::VectorXd d = Eigen::VectorXd::Zero(chart.dimension());
    d[j] = h;
    const State up = chart.retract(d), down = chart.retract(-d);
    Eigen::Vector3d differenced;
    differenced[0] = (model.energy(up) - model.energy(down)) / (2 * h);
    const Vec3 dL = (model.angular_momentum(up) - model.angular_momentum(down)) / (2 * h);
    differenced[1] = dL.dot(axes.col(0));
    differenced[2] = dL.dot(axes.col(1));
    for (int r = 0; r < 3; ++r)
      worst = std::max(worst, std::abs(analytic(r, j) - differenced[r]) / std::max(1e-3, analytic.row(r).norm()));
  }
  std::printf("conserved gradients against differences: worst relative difference %.2e\n", worst);
  EXPECT_LT(worst, 1e-8);  // the differences' own error (h² and round-off / h)
}

// The chart's derivatives in the tangent coordinates z (used by Newton on the tangent map, eq.
// 19.6) away from the base, attitudes turned by up to 1.2 rad: D retract against differences of
// retract (θ = log(R(δ)ᵀ R(δ + h e_j))/h), and D local · D retract = I (local ∘ retract = id).
TEST(PhaseChart, DerivativesAgreeWithDifferencesAwayFromTheBase) {
  auto registry = test::bundled_plugins();
  const Scene s = tilted_pair();
  const auto model = FullBodyModel::from_scene(s, registry);
  const PhaseChart chart(model.system, s.initial, 3.0, 0.3);
  const Eigen::Index d = chart.dimension(), N = State::tangent_rows(model.system);
  Eigen::VectorXd delta = Eigen::VectorXd::LinSpaced(d, -0.7, 0.9);  // η of body a: |η| ≈ 1.2 rad
  const State at = chart.retract(delta);
  const Eigen::MatrixXd A = chart.retract_derivative(delta), B = chart.local_derivative(at);
  ASSERT_EQ(A.rows(), N);
  ASSERT_EQ(A.cols(), d);
  const double h = 1e-6;
  double worst = 0;
  for (Eigen::Index j = 0; j < d; ++j) {
    Eigen::VectorXd up = delta, down = delta;
    up[j] += h, down[j] -= h;
    // z-coordinates of retract(δ ± h e_j) relative to retract(δ) (State::difference: (21.1)).
    const Eigen::VectorXd column = State::difference(chart.retract(down), chart.retract(up)) / (2 * h);
    worst = std::max(worst, (column - A.col(j)).norm() / std::max(1e-12, A.col(j).norm()));
  }
  const double identity = (B * A - Eigen::MatrixXd::Identity(d, d)).cwiseAbs().maxCoeff();
  std::printf("D retract against differences %.1e; |D local D retract - I| %.1e\n", worst, identity);
  EXPECT_LT(worst, 1e-8);
  EXPECT_LT(identity, 1e-13);
}
