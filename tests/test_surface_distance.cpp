// Distances to a solid's surface for contact events (docs/equations.md eqs. 16.5–16.7):
// against closed forms (a box, a sphere), a brute-force search (an ellipsoid), and the event
// they drive (a fall onto an ellipsoid's short axis, inside its bounding sphere).
#include "shapes.hpp"
#include "test_support.hpp"

#include <noether/simulation.hpp>
#include <noether/surface_distance.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

using namespace noether;

namespace {

// The signed distance to the box [−h, h]³ in closed form.
double box_distance(const Vec3& h, const Vec3& p) {
  const Vec3 q = p.cwiseAbs() - h;
  const double outside = q.cwiseMax(0.0).norm();
  return outside > 0 ? outside : q.maxCoeff();
}

}  // namespace

TEST(SurfaceDistance, BoxAgreesWithItsClosedForm) {
  const Vec3 half(1.0, 0.5, 0.25);
  const auto box = make_polyhedron(test::box_mesh(half), 1.0, false);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  int inside = 0;
  for (int k = 0; k < 3000; ++k) {
    const Vec3 p(u(rng), u(rng), u(rng) * 0.5);
    const double expected = box_distance(half, p);
    inside += expected < 0;
    EXPECT_NEAR(surface_gap(*box, p), expected, 1e-12) << p.transpose();
  }
  EXPECT_GT(inside, 50);  // both signs were tried
  EXPECT_NEAR(surface_gap(*box, Vec3(3, 2.5, 1.25)), std::sqrt(4.0 + 4.0 + 1.0), 1e-12);  // a corner
}

TEST(SurfaceDistance, SphereIsRadialDistance) {
  const auto sphere = make_ellipsoid(Vec3(2, 2, 2), 1.0);
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, 2.0);
  for (int k = 0; k < 1000; ++k) {
    const Vec3 p(n(rng), n(rng), n(rng));
    EXPECT_NEAR(surface_gap(*sphere, p), p.norm() - 2.0, 1e-12) << p.transpose();
  }
}

// Outside an ellipsoid the gap is the distance to its nearest point: no point of a fine
// (θ, φ) grid is closer, and the grid's nearest is as near to within its resolution.
TEST(SurfaceDistance, EllipsoidOutsideIsTheNearestPoint) {
  const Vec3 axes(3.0, 2.0, 1.0);
  const auto ellipsoid = make_ellipsoid(axes, 1.0);
  for (const Vec3& p : {Vec3(4, 0.5, 0.3), Vec3(0.2, 2.6, -0.4), Vec3(1.5, 1.5, 1.5), Vec3(-0.1, 0.05, 1.3),
                        Vec3(10, -7, 3)}) {
    const double g = surface_gap(*ellipsoid, p);
    double nearest = 1e300;
    const int n = 1500;
    for (int i = 0; i <= n; ++i) {
      const double theta = std::numbers::pi * i / n;
      for (int j = 0; j < 2 * n; ++j) {
        const double phi = std::numbers::pi * j / n;
        const Vec3 x(axes.x() * std::sin(theta) * std::cos(phi), axes.y() * std::sin(theta) * std::sin(phi),
                     axes.z() * std::cos(theta));
        nearest = std::min(nearest, (x - p).norm());
      }
    }
    EXPECT_GT(g, 0.0);
    EXPECT_GE(nearest, g - 1e-12) << p.transpose();
    EXPECT_LT(nearest - g, 1e-5) << p.transpose();
  }
  // Inside: the radial distance, negative; on a sample of the surface: 0.
  EXPECT_NEAR(surface_gap(*ellipsoid, Vec3(1.5, 0, 0)), -1.5, 1e-12);
  EXPECT_NEAR(surface_gap(*ellipsoid, Vec3(0, 0, 0)), -1.0, 1e-12);
  const Eigen::Matrix3Xd samples = surface_samples(*ellipsoid);
  EXPECT_EQ(samples.cols(), 2000);
  for (Eigen::Index k = 0; k < samples.cols(); k += 37) EXPECT_NEAR(surface_gap(*ellipsoid, samples.col(k)), 0.0, 1e-12);
}

// A sphere of radius 0.05 falls onto an ellipsoid (0.05 × 0.2 × 0.2) along its short axis: the
// event comes at centre separation 0.1, the closed-form time (16.4) — not at 0.25, where the
// ellipsoid's bounding sphere is touched.
TEST(SurfaceDistance, AFallStopsOnTheShortAxisNotOnTheBoundingSphere) {
  const double u = 0.1;
  const double exact = std::sqrt(1.0 / 2.0) * (std::sqrt(u * (1 - u)) + std::acos(std::sqrt(u)));
  for (const char* integrator : {"{plugin: lgvi, step: 1.0e-4}", "{plugin: rk, method: dopri5, rtol: 1.0e-10, atol: 1.0e-12}"}) {
    SCOPED_TRACE(integrator);
    auto registry = test::bundled_plugins();
    const Scene scene = load_scene(test::source_path("examples/collision.yaml"),
                                   {std::string("integrator=") + integrator, "bodies.right.radius=~",
                                    "bodies.right.shape={ellipsoid: {semi_axes: [0.05, 0.2, 0.2]}}"});
    ASSERT_NEAR(scene.system.body(1).radius, 0.2, 1e-15);
    const RunSummary s = run_scene(scene, registry, {});
    EXPECT_NE(s.stop_reason.find("collision: the surfaces of bodies 'left' and 'right' touched"), std::string::npos)
        << s.stop_reason;
    EXPECT_NEAR(s.final_state.t, exact, 5e-8);
    EXPECT_NEAR((s.final_state.x.col(0) - s.final_state.x.col(1)).norm(), 0.1, 1e-6);
    EXPECT_TRUE(s.verdict.trustworthy) << s.verdict.reasons.front();
  }
}
