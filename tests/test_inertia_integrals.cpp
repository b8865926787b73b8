// Inertia integrals T^{lmn} (docs/equations.md §12): closed forms of the box, the ellipsoid
// and the tetrahedron, convergence of tessellated ellipsoids, rotation against rotated
// meshes, and the mass properties of the shipped shapes.
#include "shapes.hpp"

#include <noether/error.hpp>
#include <noether/gravity_field.hpp>
#include <noether/inertia_integrals.hpp>

#include <gtest/gtest.h>

using namespace noether;
using namespace noether::test;
using multi_index::count;
using multi_index::exponents;

namespace {

double max_relative(const InertiaIntegrals& a, const InertiaIntegrals& b, int degree, double scale) {
  double worst = 0.0;
  for (int i = multi_index::first_of_degree(degree); i < multi_index::first_of_degree(degree + 1); ++i)
    worst = std::max(worst, std::abs(a.T[static_cast<std::size_t>(i)] - b.T[static_cast<std::size_t>(i)]) / scale);
  return worst;
}

}  // namespace

TEST(InertiaIntegrals, BoxMatchesItsClosedForm) {
  const Vec3 h(1.3, 0.7, 0.4);
  const double rho = 2.5;
  const auto T = polyhedron_integrals(box_mesh(h), rho, 10);
  for (int i = 0; i < count(10); ++i) {
    const auto [l, m, n] = exponents(i);
    auto one = [](double s, int k) { return k % 2 ? 0.0 : 2.0 * std::pow(s, k + 1) / (k + 1); };
    const double exact = rho * one(h.x(), l) * one(h.y(), m) * one(h.z(), n);
    const double scale = rho * 8 * h.prod() * std::pow(h.maxCoeff(), l + m + n);
    EXPECT_NEAR(T.T[static_cast<std::size_t>(i)], exact, 1e-13 * scale) << l << m << n;
  }
}

TEST(InertiaIntegrals, TetrahedronMatchesIndependentQuadrature) {
  // A tetrahedron off the origin: the signed-tetrahedra sum against a collapsed Gauss rule
  // on the tetrahedron itself, exact for degree ≤ 2·8 − 1 ≥ 8 + 2.
  const Vec3 a(0.3, -0.2, 0.1), b(1.4, 0.1, -0.3), c(0.2, 1.1, 0.4), d(0.5, 0.3, 1.6);
  const auto T = polyhedron_integrals(tetrahedron_mesh(a, b, c, d), 1.0, 8);
  std::vector<double> s, w;
  gauss_legendre01(9, s, w);
  Mat3 J;
  J << b - a, c - a, d - a;
  const double jac = std::abs(J.determinant());
  std::vector<double> Q(static_cast<std::size_t>(count(8)), 0.0);
  for (std::size_t i = 0; i < s.size(); ++i)
    for (std::size_t j = 0; j < s.size(); ++j)
      for (std::size_t k = 0; k < s.size(); ++k) {
        // (u, v, w) in the unit simplex by the Duffy map; weight (1−u)² (1−v)
        const double u = s[i], v = s[j] * (1 - u), x3 = s[k] * (1 - u) * (1 - s[j]);
        const double weight = w[i] * w[j] * w[k] * (1 - u) * (1 - u) * (1 - s[j]) * jac;
        const Vec3 p = a + J * Vec3(u, v, x3);
        for (int q = 0; q < count(8); ++q) {
          const auto [l, m, n] = exponents(q);
          Q[static_cast<std::size_t>(q)] += weight * std::pow(p.x(), l) * std::pow(p.y(), m) * std::pow(p.z(), n);
        }
      }
  for (int q = 0; q < count(8); ++q)
    EXPECT_NEAR(T.T[static_cast<std::size_t>(q)], Q[static_cast<std::size_t>(q)],
                1e-12 * std::max(1.0, std::abs(Q[static_cast<std::size_t>(q)])));
}

TEST(InertiaIntegrals, EllipsoidClosedFormValues) {
  const double M = 3.7, a = 2.0, b = 1.5, c = 0.8;
  const auto T = ellipsoid_integrals(M, Vec3(a, b, c), 8);
  EXPECT_DOUBLE_EQ(T(0, 0, 0), M);
  EXPECT_DOUBLE_EQ(T(2, 0, 0), M * a * a / 5);
  EXPECT_DOUBLE_EQ(T(4, 0, 0), 3 * M * std::pow(a, 4) / 35);
  EXPECT_DOUBLE_EQ(T(2, 2, 0), M * a * a * b * b / 35);
  EXPECT_DOUBLE_EQ(T(6, 0, 0), M * std::pow(a, 6) / 21);
  EXPECT_DOUBLE_EQ(T(4, 2, 0), M * std::pow(a, 4) * b * b / 105);
  EXPECT_DOUBLE_EQ(T(2, 2, 2), M * a * a * b * b * c * c / 315);
  EXPECT_EQ(T(1, 0, 0), 0.0);
  EXPECT_EQ(T(3, 1, 0), 0.0);
  EXPECT_GT(T(8, 0, 0), 0.0);  // degree 6 and 8 are not zero
}

TEST(InertiaIntegrals, TessellatedEllipsoidConvergesToClosedForm) {
  // The mass-normalised integrals of inscribed polyhedra approach the ellipsoid's at every
  // order 2–8, by about 4× per subdivision (second order in the edge length).
  const Vec3 axes(1.6, 1.1, 0.7);
  double previous[9] = {0};
  for (int level = 3; level <= 5; ++level) {
    const Mesh mesh = ellipsoid_mesh(axes, level);
    auto T = polyhedron_integrals(mesh, 1.0, 8);
    const double M = T.mass();
    for (auto& t : T.T) t /= M;
    const auto E = ellipsoid_integrals(1.0, axes, 8);
    for (int d = 2; d <= 8; d += 2) {
      const double err = max_relative(T, E, d, std::pow(axes.maxCoeff(), d));
      if (level > 3) EXPECT_LT(err, previous[d] / 3.0) << "degree " << d << " level " << level;
      if (level == 5) EXPECT_LT(err, 2e-3) << "degree " << d;
      previous[d] = err;
    }
  }
}

TEST(InertiaIntegrals, RotationMatchesTheRotatedMesh) {
  // T' from IntegralRotation against the integrals of the mesh whose vertices were rotated.
  const Mesh mesh = shipped_mesh("hou2017_B.obj");
  const Mat3 C = (Eigen::AngleAxisd(0.7, Vec3(0.3, -0.5, 0.8).normalized()) *
                  Eigen::AngleAxisd(-1.1, Vec3::UnitY())).toRotationMatrix();
  Mesh turned = mesh;
  for (Eigen::Index i = 0; i < turned.vertices.cols(); ++i) turned.vertices.col(i) = C * mesh.vertices.col(i);
  for (const int N : {2, 10}) {  // the direct path of degree ≤ 2 and the monomial tables
    const auto T = polyhedron_integrals(mesh, 2000, N);
    const auto expected = polyhedron_integrals(turned, 2000, N);
    InertiaIntegrals rotated;
    IntegralRotation rotation(N);
    rotation.apply(C, T, rotated);
    const double r = 2.0;  // the mesh's extent
    for (int d = 0; d <= N; ++d)
      EXPECT_LT(max_relative(rotated, expected, d, T.mass() * std::pow(r, d)), 1e-13) << "N " << N << " degree " << d;
  }
}

TEST(InertiaIntegrals, SecondMomentsGiveTheInertiaTensor) {
  const Mat3 J = (Mat3() << 3.0, 0.2, -0.1, 0.2, 2.5, 0.05, -0.1, 0.05, 2.0).finished();
  const auto T = integrals_from_inertia(4.0, J);
  const Mat3 S = T.second_moment();
  EXPECT_LT((S.trace() * Mat3::Identity() - S - J).cwiseAbs().maxCoeff(), 1e-15);
  // And a polyhedron's: tr(S) I − S is the inertia that make_polyhedron reports.
  const auto solid = make_polyhedron(shipped_mesh("hou2017_A.obj"), 2000, false);
  const auto TA = solid->integrals(2);
  const Mat3 SA = TA.second_moment();
  EXPECT_LT((SA.trace() * Mat3::Identity() - SA - solid->inertia).cwiseAbs().maxCoeff(), 1e-12 * solid->inertia.norm());
  EXPECT_LT(std::abs(TA(1, 0, 0)) + std::abs(TA(0, 1, 0)) + std::abs(TA(0, 0, 1)), 1e-12 * TA.mass());
}

TEST(Solid, PublishedMassesAndPlacementOfTheShippedShapes) {
  // Hou et al. 2017 §5.1 octahedra at 2000 kg/m³; their vertex frames are not principal.
  const auto A = make_polyhedron(shipped_mesh("hou2017_A.obj"), 2000, false);
  const auto B = make_polyhedron(shipped_mesh("hou2017_B.obj"), 2000, false);
  EXPECT_NEAR(A->mass, 5.121320343560e+03, 1e-8);
  EXPECT_NEAR(B->mass, 6.765874735806e+03, 1e-8);
  EXPECT_GT(std::abs(A->integrals(2)(1, 1, 0)), 1.0);
  // Fahnestock et al. 2006 Table 1: B2 4500 kg, I = (1377.0, 814.5, 1462.5) kg m².
  const auto B2 = make_polyhedron(shipped_mesh("fahnestock2006_B2.obj"), 2500, true);
  EXPECT_NEAR(B2->mass, 4500.0, 1e-9);
  EXPECT_NEAR(B2->inertia(0, 0), 1377.0, 1e-9);
  EXPECT_NEAR(B2->inertia(1, 1), 814.5, 1e-9);
  EXPECT_NEAR(B2->inertia(2, 2), 1462.5, 1e-9);
  // KW4 (Ostro et al. 2006 meshes, km): volumes, centre-of-mass offsets and axis rotations.
  const auto alpha = make_polyhedron(shipped_mesh("a66391_1999kw4_primary.obj", 1000), 1970, true);
  const auto beta = make_polyhedron(shipped_mesh("a66391_1999kw4_secondary.obj", 1000), 2810, true);
  EXPECT_NEAR(alpha->volume / 1e9, 1.195308026, 1e-9);
  EXPECT_NEAR(beta->volume / 1e9, 0.0480345094, 1e-10);
  EXPECT_NEAR((alpha->offset - Vec3(0.288, 0.342, 0.138)).norm(), 0.0, 1e-3);
  EXPECT_NEAR((beta->offset - Vec3(-0.336, -0.378, 0.080)).norm(), 0.0, 1e-3);
  EXPECT_NEAR(log_so3(alpha->rotation).norm() * 180 / M_PI, 0.048, 5e-4);
  EXPECT_NEAR(log_so3(beta->rotation).norm() * 180 / M_PI, 0.207, 5e-4);
  const Vec3 iv = alpha->inertia.diagonal() / alpha->mass / 1e6;  // I/M in km²
  EXPECT_NEAR(iv.x(), 0.164770, 2e-6);
  EXPECT_NEAR(iv.y(), 0.172618, 2e-6);
  EXPECT_NEAR(iv.z(), 0.195718, 2e-6);
  EXPECT_NEAR(alpha->radius, 783.43, 0.01);
  EXPECT_NEAR(beta->radius, 296.12, 0.01);
  // On its principal axes, the products of inertia vanish and the centre of mass is the origin.
  const auto T = beta->integrals(2);
  EXPECT_LT(std::abs(T(1, 1, 0)) + std::abs(T(1, 0, 1)) + std::abs(T(0, 1, 1)), 1e-12 * T(2, 0, 0));
  EXPECT_LT(Vec3(T(1, 0, 0), T(0, 1, 0), T(0, 0, 1)).norm(), 1e-12 * T.mass() * beta->radius);
}

TEST(Mesh, ValidationNamesTheFaultyFace) {
  Mesh box = box_mesh(Vec3(1, 1, 1));
  EXPECT_NO_THROW(validate_mesh(box));
  Mesh open = box;
  open.faces.pop_back();
  EXPECT_THROW(
      {
        try {
          validate_mesh(open);
        } catch (const SceneError& e) {
          EXPECT_NE(std::string(e.what()).find("not closed"), std::string::npos) << e.what();
          throw;
        }
      },
      SceneError);
  Mesh flipped = box;
  std::swap(flipped.faces[3][1], flipped.faces[3][2]);
  try {
    validate_mesh(flipped);
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("not consistently oriented"), std::string::npos) << e.what();
  }
  Mesh inward = box;
  for (auto& f : inward.faces) std::swap(f[1], f[2]);
  try {
    validate_mesh(inward);
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("point inwards"), std::string::npos) << e.what();
  }
  Mesh degenerate = box;
  degenerate.faces[0][1] = degenerate.faces[0][0];
  try {
    validate_mesh(degenerate);
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("face 1 repeats a vertex"), std::string::npos) << e.what();
  }
}

TEST(Mesh, ReadsTheGubasCsvPair) {
  const Mesh m = read_vertex_facet_csv(source_path("examples/shapes/Didymos_A_vert_met.csv"),
                                       source_path("examples/shapes/Didymos_A_facet.csv"), 1.0);
  EXPECT_EQ(m.vertices.cols(), 1000);
  EXPECT_EQ(m.faces.size(), 1996u);
  EXPECT_NO_THROW(validate_mesh(m));
  EXPECT_NEAR(mesh_volume(m) / 1e9, 0.2485481580, 1e-10);
}
