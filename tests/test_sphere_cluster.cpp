// sphere-cluster and point-mass: forces and moments against finite differences of U
// (docs/equations.md §2), and Newton's third law for forces and torques.
#include "test_support.hpp"

#include <noether/error.hpp>
#include <noether/forces.hpp>

#include <gtest/gtest.h>

using namespace noether;

namespace {

// Dumbbells, a three-sphere body and a point mass, attitudes away from the identity.
const char* kMixed = R"(G: 0.7
bodies:
  - {name: alpha, mass: 1.5, inertia: [0.0004, 0.0238, 0.0238], position: [0.67, 0, 0.2],
     shape: {dumbbell: {length: 0.25}}, attitude: {quaternion: [0.8, 0.36, 0.48, 0.0]}}
  - {name: beta, mass: 3, inertia: [0.0030, 0.1905, 0.1905], position: [-0.33, 0, -0.1],
     shape: {dumbbell: {length: 0.5}}, attitude: {quaternion: [0.6, 0, 0.64, 0.48]}}
  - name: gamma
    mass: 2
    inertia: [0.05, 0.05, 0.09]
    position: [0.1, 1.1, -0.3]
    attitude: {quaternion: [0.28, 0.96, 0, 0]}
    shape: {spheres: [{mass: 1, position: [0.2, 0, 0]}, {mass: 0.5, position: [-0.2, 0.2, 0]},
                      {mass: 0.5, position: [-0.2, -0.2, 0]}]}
  - {name: probe, mass: 0.01, position: [-0.8, -0.9, 0.5]}
potential: {plugin: sphere-cluster}
integrator: {plugin: lgvi, step: 0.01}
run: {t_end: 1, output_every: 0.1}
)";

struct Checked {
  double worst_force = 0, worst_moment = 0, net_force = 0, net_torque = 0;
};

Checked check_against_finite_differences(const std::string& plugin, const Scene& scene) {
  auto registry = test::bundled_plugins();
  auto potential = registry.make_potential(plugin, scene.system, Params());
  const System& sys = scene.system;
  const State s0 = scene.initial;
  Forces f0, tmp;
  f0.resize(sys);
  tmp.resize(sys);
  potential->evaluate(s0, f0);
  auto U = [&](const State& s) {
    potential->evaluate(s, tmp);
    return tmp.U;
  };
  Checked c;
  const double eps = 1e-5;
  double fscale = 0, mscale = 0;
  for (Eigen::Index i = 0; i < f0.f.cols(); ++i) fscale = std::max(fscale, f0.f.col(i).norm());
  for (Eigen::Index k = 0; k < f0.M.cols(); ++k) mscale = std::max(mscale, f0.M.col(k).norm());
  for (std::size_t i = 0; i < sys.size(); ++i) {
    for (int a = 0; a < 3; ++a) {  // f_i = −∂U/∂x_i
      State sp = s0, sm = s0;
      sp.x(a, static_cast<Eigen::Index>(i)) += eps;
      sm.x(a, static_cast<Eigen::Index>(i)) -= eps;
      const double fd = -(U(sp) - U(sm)) / (2 * eps);
      c.worst_force = std::max(c.worst_force, std::abs(fd - f0.f(a, static_cast<Eigen::Index>(i))) / fscale);
    }
  }
  for (std::size_t k = 0; k < sys.rigid_count(); ++k) {
    for (int a = 0; a < 3; ++a) {  // η · M = −dU/dε along R exp(ε S(η))
      const Vec3 eta = Vec3::Unit(a);
      State sp = s0, sm = s0;
      sp.R[k] = s0.R[k] * exp_so3(eps * eta);
      sm.R[k] = s0.R[k] * exp_so3(-eps * eta);
      const double fd = -(U(sp) - U(sm)) / (2 * eps);
      c.worst_moment = std::max(c.worst_moment, std::abs(fd - f0.M(a, static_cast<Eigen::Index>(k))) / mscale);
    }
  }
  Vec3 F = Vec3::Zero(), T = Vec3::Zero();
  for (std::size_t i = 0; i < sys.size(); ++i) {
    const auto c_ = static_cast<Eigen::Index>(i);
    F += f0.f.col(c_);
    T += Vec3(s0.x.col(c_)).cross(Vec3(f0.f.col(c_)));
    if (const int k = sys.rigid_index(i); k >= 0) T += s0.R[static_cast<std::size_t>(k)] * f0.M.col(k);
  }
  c.net_force = F.norm() / fscale;
  c.net_torque = T.norm() / fscale;
  return c;
}

}  // namespace

TEST(SphereCluster, DumbbellPotentialMatchesTheSeed) {
  // U at t = 0 of docs/equations.md §6: −¼ Σ_{p,q} 1/‖X + ρ2p... ‖ with X = (1, 0, 0.3).
  const Scene scene = test::dumbbell_scene();
  auto registry = test::bundled_plugins();
  auto potential = registry.make_potential("sphere-cluster", scene.system, Params());
  Forces f;
  f.resize(scene.system);
  potential->evaluate(scene.initial, f);
  double expected = 0;
  for (double dx : {1.125 - 0.25, 1.125 + 0.25, 0.875 - 0.25, 0.875 + 0.25})
    expected -= 0.25 / std::hypot(dx, 0.3);
  EXPECT_NEAR(f.U, expected, 1e-15);
}

TEST(SphereCluster, ForcesAndMomentsMatchFiniteDifferences) {
  const Checked c = check_against_finite_differences("sphere-cluster", parse_scene(kMixed, "mixed"));
  EXPECT_LT(c.worst_force, 1e-7);
  EXPECT_LT(c.worst_moment, 1e-7);
  EXPECT_LT(c.net_force, 1e-14);   // Newton's third law
  EXPECT_LT(c.net_torque, 1e-14);  // total torque about the origin vanishes
}

TEST(SphereCluster, DumbbellSceneMatchesFiniteDifferences) {
  const Checked c = check_against_finite_differences("sphere-cluster", test::dumbbell_scene());
  EXPECT_LT(c.worst_force, 1e-7);
  EXPECT_LT(c.worst_moment, 1e-7);
}

TEST(PointMass, ForcesMatchFiniteDifferencesAndMomentsVanish) {
  const Checked c = check_against_finite_differences("point-mass", parse_scene(kMixed, "mixed"));
  EXPECT_LT(c.worst_force, 1e-7);
  EXPECT_EQ(c.worst_moment, 0.0);
  EXPECT_LT(c.net_force, 1e-14);
}

TEST(SphereCluster, ShapesAreValidated) {
  auto registry = test::bundled_plugins();
  auto replaced = [](std::string text, const std::string& from, const std::string& to) {
    text.replace(text.find(from), from.size(), to);
    return text;
  };
  const Scene off_centre = parse_scene(
      replaced(kMixed, "{mass: 1, position: [0.2, 0, 0]}", "{mass: 1, position: [0.3, 0, 0]}"),
      "mixed");
  EXPECT_THROW(registry.make_potential("sphere-cluster", off_centre.system, Params()), SceneError);
  const Scene missing =
      parse_scene(replaced(kMixed, "shape: {dumbbell: {length: 0.25}}, ", ""), "mixed");
  try {
    registry.make_potential("sphere-cluster", missing.system, Params());
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("body 'alpha' is rigid but has no 'shape'"), std::string::npos);
  }
}
