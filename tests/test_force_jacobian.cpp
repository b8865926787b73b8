// The force Jacobian K = ∂(f, M)/∂(x, θ) (docs/equations.md §20): the analytic ones of the bundled
// models against central differences of their forces, the symmetry (20.3) that holds exactly when
// f and M are the gradient of one U, translation invariance, and the differenced fallback.
#include "test_support.hpp"

#include <noether/force_jacobian.hpp>
#include <noether/lie.hpp>
#include <noether/simulation.hpp>

#include <gtest/gtest.h>

#include <random>

using namespace noether;

namespace {

// Three bodies: two dumbbells at a generic attitude and a point mass (every block of 20.2).
const char* kClusters = R"(G: 0.7
bodies:
  - {name: alpha, mass: 1.5, inertia: [0.0004, 0.0238, 0.0238], position: [0.67, 0, 0.2],
     shape: {dumbbell: {length: 0.25}}, attitude: {quaternion: [0.8, 0.36, 0.48, 0.0]}}
  - {name: beta, mass: 3, inertia: [0.0030, 0.1905, 0.1905], position: [-0.33, 0, -0.1],
     shape: {spheres: [{mass: 1, position: [0.2, 0.1, 0]}, {mass: 1, position: [-0.2, 0, 0.1]},
                       {mass: 1, position: [0, -0.1, -0.1]}]}, attitude: {quaternion: [0.6, 0, 0.8, 0]}}
  - {name: probe, mass: 0.01, position: [-0.8, -0.9, 0.5]}
potential: {plugin: sphere-cluster}
integrator: {plugin: lgvi, step: 0.01}
run: {t_end: 1, output_every: 0.1}
)";

struct Model {
  Scene scene;
  std::shared_ptr<const Potential> potential;
  std::unique_ptr<Workspace> workspace;
};

Model model(const std::string& text, const std::vector<std::string>& overrides = {}) {
  static PluginRegistry registry = test::bundled_plugins();
  Model m{parse_scene(text, "jacobian", overrides), nullptr, nullptr};
  m.potential = make_scene_potential(m.scene, registry);
  m.workspace = m.potential->make_workspace();
  return m;
}

// The state moved at random: centres by ~5 % of their distance, attitudes by ~0.5 rad.
State perturbed(const State& s, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  State p = s;
  for (Eigen::Index i = 0; i < p.x.cols(); ++i)
    for (int a = 0; a < 3; ++a) p.x(a, i) += 0.03 * normal(rng);
  for (auto& R : p.R) {
    const double a = normal(rng), b = normal(rng), c = normal(rng);
    R = R * exp_so3(0.5 * Vec3(a, b, c));
  }
  return p;
}

double relative(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

// K − ½ diag(S(M_k)): symmetric by (20.3).
Eigen::MatrixXd symmetrised(const Eigen::MatrixXd& K, const Potential& potential, const State& s, Workspace& w) {
  Forces f;
  f.f.resize(3, s.x.cols());
  f.M.resize(3, static_cast<Eigen::Index>(s.R.size()));
  potential.evaluate(s, f, w);
  Eigen::MatrixXd sym = K;
  const Eigen::Index N = 3 * s.x.cols();
  for (Eigen::Index k = 0; k < f.M.cols(); ++k) sym.block<3, 3>(N + 3 * k, N + 3 * k) -= 0.5 * hat(Vec3(f.M.col(k)));
  return sym;
}

}  // namespace

TEST(ForceJacobian, SphereClustersAgreeWithDifferencesAndAreSymmetric) {
  Model m = model(kClusters);
  for (unsigned seed = 0; seed < 4; ++seed) {
    const State s = seed == 0 ? m.scene.initial : perturbed(m.scene.initial, seed);
    const ForceJacobian J = force_jacobian(*m.potential, s, *m.workspace);
    ASSERT_TRUE(J.analytic);
    ASSERT_EQ(J.K.rows(), 3 * (3 + 2));
    const Eigen::MatrixXd D = differenced_force_jacobian(*m.potential, s, *m.workspace);
    EXPECT_LT(relative(J.K, D), 1e-8) << "state " << seed;
    const Eigen::MatrixXd S = symmetrised(J.K, *m.potential, s, *m.workspace);
    EXPECT_LT((S - S.transpose()).cwiseAbs().maxCoeff() / J.K.cwiseAbs().maxCoeff(), 1e-13) << "state " << seed;
    // Without the ½ S(M) term the attitude blocks are not symmetric: (20.3) is not vacuous.
    EXPECT_GT((J.K - J.K.transpose()).cwiseAbs().maxCoeff() / J.K.cwiseAbs().maxCoeff(), 1e-6);
    // Moving every centre alike changes no force or moment: the x columns sum to zero.
    Eigen::MatrixXd translation = Eigen::MatrixXd::Zero(J.K.rows(), 3);
    for (Eigen::Index i = 0; i < 3; ++i) translation += J.K.middleCols(3 * i, 3);
    EXPECT_LT(translation.cwiseAbs().maxCoeff() / J.K.cwiseAbs().maxCoeff(), 1e-13);
  }
}

TEST(ForceJacobian, PointMassesAndACentralFieldAgreeWithDifferences) {
  // The figure-eight under point-mass (K_xx only; the rigid rows of a scene with attitudes stay 0).
  Model eight = model(R"(G: 1
bodies:
  - {name: a, mass: 1, position: [0.97000436, -0.24308753, 0.1]}
  - {name: b, mass: 1, position: [-0.97000436, 0.24308753, 0]}
  - {name: c, mass: 1, position: [0, 0, -0.1]}
potential: {plugin: point-mass}
integrator: {plugin: lgvi, step: 0.01}
run: {t_end: 1, output_every: 0.1}
)");
  const ForceJacobian J = force_jacobian(*eight.potential, eight.scene.initial, *eight.workspace);
  ASSERT_TRUE(J.analytic);
  EXPECT_LT(relative(J.K, differenced_force_jacobian(*eight.potential, eight.scene.initial, *eight.workspace)), 1e-8);
  EXPECT_LT((J.K - J.K.transpose()).cwiseAbs().maxCoeff(), 1e-15 * J.K.cwiseAbs().maxCoeff());
  // Rigid bodies under point-mass: no moment, so zero attitude rows and columns.
  Model rigid = model(kClusters, {"potential.plugin=point-mass"});
  const ForceJacobian Jr = force_jacobian(*rigid.potential, rigid.scene.initial, *rigid.workspace);
  EXPECT_TRUE(Jr.analytic);
  EXPECT_EQ(Jr.K.bottomRows(6).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(Jr.K.rightCols(6).cwiseAbs().maxCoeff(), 0.0);
  // central-field plus point-mass: a sum of two analytic models is analytic, and right.
  Model sum = model(kClusters, {"potential=[{plugin: point-mass}, {plugin: central-field, mu: 2, center: [0.1, 0.2, 0.3]}]"});
  const ForceJacobian Js = force_jacobian(*sum.potential, sum.scene.initial, *sum.workspace);
  ASSERT_TRUE(Js.analytic);
  EXPECT_LT(relative(Js.K, differenced_force_jacobian(*sum.potential, sum.scene.initial, *sum.workspace)), 1e-8);
}

// The largest relative difference of K's 3×3 blocks against D's, each block against its own size
// (a far pair's small blocks are checked too), blocks below `floor` × max |D| (the differences'
// own noise) skipped.
double blockwise(const Eigen::MatrixXd& K, const Eigen::MatrixXd& D, double floor = 1e-10) {
  double worst = 0;
  const double largest = D.cwiseAbs().maxCoeff();
  for (Eigen::Index i = 0; i < K.rows(); i += 3)
    for (Eigen::Index j = 0; j < K.cols(); j += 3) {
      const double size = D.block<3, 3>(i, j).cwiseAbs().maxCoeff();
      if (size <= floor * largest) continue;
      const double e = (K.block<3, 3>(i, j) - D.block<3, 3>(i, j)).cwiseAbs().maxCoeff() / size;
      worst = std::max(worst, e);
    }
  return worst;
}

// A model's analytic K against (20.4) at the scene's state and `states − 1` random ones: the
// largest blockwise difference and asymmetry (20.3) over them, each state's printed.
struct Agreement {
  double error = 0, asymmetry = 0;
};
Agreement against_differences(const std::string& name, Model& m, unsigned states) {
  Agreement worst;
  for (unsigned seed = 0; seed < states; ++seed) {
    const State s = seed == 0 ? m.scene.initial : perturbed(m.scene.initial, seed);
    const ForceJacobian J = force_jacobian(*m.potential, s, *m.workspace);
    EXPECT_TRUE(J.analytic) << name;
    const Eigen::MatrixXd D = differenced_force_jacobian(*m.potential, s, *m.workspace);
    const Eigen::MatrixXd S = symmetrised(J.K, *m.potential, s, *m.workspace);
    const double error = blockwise(J.K, D), asymmetry = (S - S.transpose()).cwiseAbs().maxCoeff() / J.K.cwiseAbs().maxCoeff();
    std::printf("%-30s state %u: blockwise %.1e, asymmetry %.1e\n", name.c_str(), seed, error, asymmetry);
    worst.error = std::max(worst.error, error);
    worst.asymmetry = std::max(worst.asymmetry, asymmetry);
  }
  return worst;
}

// mutual-series' K from the series one degree higher (docs/equations.md §25) against central
// differences of its forces and moments, block by block: two ellipsoids at order 2, 4 and 8, a
// point mass and an ellipsoid, a rigid body given by its inertia alone (order 2), at the scene's
// state and three random ones; (20.3) to round-off. Measured: ≤ 2.6e-9 (the differences' error).
TEST(ForceJacobian, MutualSeriesAgreesWithDifferencesBlockByBlock) {
  const std::string two = R"(G: 0.7
bodies:
  - {name: alpha, density: 1, shape: {ellipsoid: {semi_axes: [0.5, 0.35, 0.25]}}, position: [0, 0, 0],
     attitude: {quaternion: [0.8, 0.36, 0.48, 0.0]}}
  - {name: beta, density: 1, shape: {ellipsoid: {semi_axes: [0.3, 0.2, 0.15]}}, position: [1.6, 0.4, -0.2],
     attitude: {quaternion: [0.6, 0, 0.8, 0]}}
potential: {plugin: mutual-series, order: 4}
integrator: {plugin: lgvi, step: 0.01}
run: {t_end: 1, output_every: 0.1}
)";
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
      {"ellipsoids, order 2", {"potential.order=2"}},
      {"ellipsoids, order 4", {}},
      {"ellipsoids, order 8", {"potential.order=8"}},
      {"point and ellipsoid", {"bodies.beta.shape=~", "bodies.beta.attitude=~", "bodies.beta.density=~", "bodies.beta.mass=0.02"}},
      {"inertia alone, order 2",
       {"bodies.alpha.shape=~", "bodies.alpha.density=~", "bodies.alpha.mass=0.18", "bodies.alpha.inertia=[0.0066, 0.0108, 0.0128]",
        "potential.order=2"}}};
  for (const auto& [name, set] : cases) {
    Model m = model(two, set);
    const Agreement a = against_differences(name, m, 4);
    EXPECT_LT(a.error, 1e-7) << name;
    EXPECT_LT(a.asymmetry, 1e-13) << name;
  }
  // kw4-heliocentric: the binary 1 au from the Sun (its pairs with the Sun at order 0, chosen by
  // the tolerance). Differences cannot check it: the Sun's pull (1e10 N) over a step of 2 cm
  // leaves them 5e-4 of the binary's blocks. K is translation invariant and (20.3) holds.
  Model helio{load_scene(test::source_path("examples/kw4-heliocentric.yaml")), nullptr, nullptr};
  static PluginRegistry registry = test::bundled_plugins();
  helio.potential = make_scene_potential(helio.scene, registry);
  helio.workspace = helio.potential->make_workspace();
  const ForceJacobian J = force_jacobian(*helio.potential, helio.scene.initial, *helio.workspace);
  ASSERT_TRUE(J.analytic);
  const Eigen::MatrixXd S = symmetrised(J.K, *helio.potential, helio.scene.initial, *helio.workspace);
  EXPECT_LT((S - S.transpose()).cwiseAbs().maxCoeff() / J.K.cwiseAbs().maxCoeff(), 1e-11);  // measured 1.9e-12
  Eigen::MatrixXd translation = Eigen::MatrixXd::Zero(J.K.rows(), 3);
  for (Eigen::Index i = 0; i < 3; ++i) translation += J.K.middleCols(3 * i, 3);
  EXPECT_LT(translation.cwiseAbs().maxCoeff() / J.K.cwiseAbs().maxCoeff(), 1e-12);
}

// mutual-exact's K from its own surface quadrature, differentiated (docs/equations.md §26), block
// by block against central differences of its forces: an ellipsoid and a polyhedron in both roles
// (the field's gradient over the other's surface, and the roles swapped (26.6)), each with a point
// mass (the field's gradient tensor (26.1), (26.2), (26.5)); and against the series' K (§25) for
// two ellipsoids apart, converging with the series' order: two independent formulations of one
// derivative. The differences are the noisier side here: a torque is a sum over a surface of
// Φ x × n dS whose terms nearly cancel, and (20.4) divides its round-off by 1e-5 (measured: the
// blocks between two attitudes to 1.0e-6, the others ≤ 2e-8; K symmetric (20.3) to 2e-14).
TEST(ForceJacobian, MutualExactAgreesWithDifferencesAndWithTheSeries) {
  const std::string shapes = R"(G: 0.7
bodies:
  - {name: alpha, density: 1, shape: {ellipsoid: {semi_axes: [0.5, 0.35, 0.25]}},
     position: [0.67, 0, 0.2], attitude: {quaternion: [0.8, 0.36, 0.48, 0.0]}}
  - {name: beta, density: 0.1, position: [-2.5, 0.5, -0.4], attitude: {quaternion: [0.6, 0, 0.8, 0]},
     shape: {polyhedron: {file: )" + test::source_path("examples/shapes/hou2017_B.obj") + R"(, units: m, frame: mesh}}}
  - {name: probe, mass: 0.01, position: [-0.8, -1.9, 1.5]}
potential: {plugin: mutual-exact}
integrator: {plugin: lgvi, step: 0.01}
run: {t_end: 1, output_every: 0.1}
)";
  // The polyhedron first: the ellipsoid (the field) is then B, the surface A.
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
      {"ellipsoid, polyhedron, point", {}},
      {"polyhedron, ellipsoid, point", {"bodies.alpha.position=[-2.5, 0.5, -0.4]", "bodies.beta.position=[0.67, 0, 0.2]"}}};
  for (const auto& [name, set] : cases) {
    Model m = model(shapes, set);
    const Agreement a = against_differences(name, m, 3);
    EXPECT_LT(a.error, 3e-6) << name;
    EXPECT_LT(a.asymmetry, 1e-12) << name;
  }
  // Two ellipsoids 3 radii apart (measured: 7.9e-6 at order 10, 1.2e-6 at 12, 2.1e-8 at 14).
  const std::string two = R"(G: 0.7
bodies:
  - {name: alpha, density: 1, shape: {ellipsoid: {semi_axes: [0.5, 0.35, 0.25]}}, position: [0, 0, 0],
     attitude: {quaternion: [0.8, 0.36, 0.48, 0.0]}}
  - {name: beta, density: 1, shape: {ellipsoid: {semi_axes: [0.3, 0.2, 0.15]}}, position: [1.6, 0.9, -0.6],
     attitude: {quaternion: [0.6, 0, 0.8, 0]}}
potential: {plugin: mutual-exact}
integrator: {plugin: lgvi, step: 0.01}
run: {t_end: 1, output_every: 0.1}
)";
  Model exact = model(two);
  const ForceJacobian Je = force_jacobian(*exact.potential, exact.scene.initial, *exact.workspace);
  ASSERT_TRUE(Je.analytic);
  auto against_series = [&](int order) {
    Model series = model(two, {"potential={plugin: mutual-series, order: " + std::to_string(order) + "}"});
    const ForceJacobian Js = force_jacobian(*series.potential, series.scene.initial, *series.workspace);
    const double error = blockwise(Je.K, Js.K, 1e-6);
    std::printf("two ellipsoids: exact against the series at order %d, blockwise %.1e\n", order, error);
    return error;
  };
  const double at10 = against_series(10), at14 = against_series(14);
  EXPECT_LT(at14, 1e-7);
  EXPECT_LT(at14, at10 / 100);
}

// A model without a K of its own (here a test potential: softened point masses) is differenced
// and labelled so; the differences agree with the analytic K of the same forces.
TEST(ForceJacobian, AModelWithoutOneIsDifferencedAndSaysSo) {
  class Softened final : public Potential {
   public:
    void evaluate(const State& s, Forces& out, Workspace&) const override {
      out.set_zero();
      for (Eigen::Index i = 0; i < s.x.cols(); ++i)
        for (Eigen::Index j = i + 1; j < s.x.cols(); ++j) {
          const Vec3 d = s.x.col(j) - s.x.col(i);
          const double r2 = d.squaredNorm() + 0.01, r = std::sqrt(r2);
          out.U -= 1.0 / r;
          out.f.col(i) += d / (r2 * r);
          out.f.col(j) -= d / (r2 * r);
        }
    }
  };
  Model m = model(kClusters);
  const Softened softened;
  auto w = softened.make_workspace();
  const ForceJacobian J = force_jacobian(softened, m.scene.initial, *w);
  EXPECT_FALSE(J.analytic);
  // The analytic K of the softened pair: ∂f_i/∂x_j = (I − 3 d dᵀ/r²)/r³ for i ≠ j.
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(J.K.rows(), J.K.cols());
  const State& s = m.scene.initial;
  for (Eigen::Index i = 0; i < 3; ++i)
    for (Eigen::Index j = 0; j < 3; ++j) {
      if (i == j) continue;
      const Vec3 d = s.x.col(j) - s.x.col(i);
      const double r2 = d.squaredNorm() + 0.01, r = std::sqrt(r2);
      const Eigen::Matrix3d B = (Eigen::Matrix3d::Identity() - 3 * d * d.transpose() / r2) / (r2 * r);
      K.block<3, 3>(3 * i, 3 * j) += B;
      K.block<3, 3>(3 * i, 3 * i) -= B;
    }
  EXPECT_LT(relative(J.K, K), 1e-8);
}
