// Radiation pressure facet by facet (docs/forces.md, "Radiation"; docs/equations.md §36): the force
// on a box and on a sphere against their closed forms, YORP — a real shape's spin change in the
// forced LGVI against the rotation-averaged torque in closed form (36.3), and none on a body with
// mirror symmetry — and BYORP — a synchronous secondary's orbit growing at the rate its angular
// momentum balance gives (36.4).
#include "shapes.hpp"
#include "test_support.hpp"

#include <noether/simulation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

using namespace noether;
using test::registry;

namespace {

constexpr double kAu = 1.495978707e11, kSunMu = 1.32712440018e20, kG = 6.674e-11;

struct Optics {
  double specular = 0.0, diffuse = 0.0;
  bool thermal = true;
  std::string yaml() const {
    std::ostringstream o;
    o << "specular: " << specular << ", diffuse: " << diffuse << ", thermal: " << (thermal ? "true" : "false");
    return o.str();
  }
  double lambertian() const { return (2.0 / 3.0) * (diffuse + (thermal ? 1.0 - specular - diffuse : 0.0)); }
};

// The scene's first force, made once: its force on and torque of its first body at a state.
class FirstForce {
 public:
  explicit FirstForce(const Scene& scene)
      : force_(registry().make_force(scene.forces[0].plugin, scene.system, scene.forces[0].params)),
        workspace_(force_->make_workspace()) {
    f_.resize(scene.system);
  }
  std::pair<Vec3, Vec3> operator()(const State& s) {
    force_->evaluate(s, f_, *workspace_);
    return {f_.f.col(0), f_.M.col(0)};
  }

 private:
  std::shared_ptr<const ForceModel> force_;
  std::unique_ptr<Workspace> workspace_;
  Forces f_;
};

std::string obj_file(const Mesh& m, const std::string& name) {
  const std::string path = ::testing::TempDir() + name + ".obj";
  std::ofstream out(path);
  out.precision(17);
  for (Eigen::Index i = 0; i < m.vertices.cols(); ++i)
    out << "v " << m.vertices(0, i) << ' ' << m.vertices(1, i) << ' ' << m.vertices(2, i) << '\n';
  for (const auto& f : m.faces) out << "f " << f[0] + 1 << ' ' << f[1] + 1 << ' ' << f[2] + 1 << '\n';
  return path;
}

// A lone body lit by a Sun at rest `sun` from it (pressure 1 at distance |sun|).
Scene lit_body(const std::string& shape, const Optics& o, const Vec3& sun, const std::string& extra = "") {
  std::ostringstream yaml;
  yaml.precision(17);
  yaml << "G: 1\nbodies:\n  - {name: rock, mass: 1, shape: " << shape
       << ", position: [0, 0, 0], velocity: [0, 0, 0]}\n"
       << "potential: {plugin: point-mass}\n"
       << "forces: [{plugin: radiation, body: rock, pressure: 1, distance: " << sun.norm() << ", " << o.yaml()
       << ", position: [" << sun.x() << ", " << sun.y() << ", " << sun.z() << "], velocity: [0, 0, 0], mu: 1"
       << extra << "}]\n"
       << "integrator: {plugin: lgvi, step: 0.01}\nrun: {t_end: 1, output_every: 1}\n";
  return parse_scene(yaml.str(), "lit");
}

// (36.1) written per face of a box (not per triangle): a face of area A and normal n at c.
std::pair<Vec3, Vec3> box_closed_form(const Vec3& half, const Vec3& u, const Optics& o) {
  Vec3 F = Vec3::Zero(), M = Vec3::Zero();
  for (int axis = 0; axis < 3; ++axis)
    for (const double side : {-1.0, 1.0}) {
      const Vec3 n = side * Vec3::Unit(axis), c = side * half[axis] * Vec3::Unit(axis);
      const double A = 4 * half[(axis + 1) % 3] * half[(axis + 2) % 3], mu = n.dot(u);
      if (mu <= 0) continue;
      const Vec3 f = -A * mu * ((1 - o.specular) * u + (2 * o.specular * mu + o.lambertian()) * n);
      F += f;
      M += c.cross(f);
    }
  return {F, M};
}

// The force and torque per unit pressure averaged over a turn of the Sun's azimuth φ about the
// body's z axis, the Sun in its xy plane, u = (cos φ, sin φ, 0) (36.2)–(36.3): with n⊥ = |(nx, ny)|,
// ⟨max(μ, 0) u⟩ = (nx, ny, 0)/4, ⟨max(μ, 0)⟩ = n⊥/π and ⟨max(μ, 0)²⟩ = n⊥²/4, so per facet
// ⟨f⟩ = −A [(1 − ρs)(nx, ny, 0)/4 + (ρs n⊥²/2 + β n⊥/π) n] and ⟨c × f⟩ = c × ⟨f⟩.
std::pair<Vec3, Vec3> turn_average(const Mesh& mesh, const Optics& o) {
  Vec3 F = Vec3::Zero(), M = Vec3::Zero();
  for (const auto& face : mesh.faces) {
    const Vec3 a = mesh.vertices.col(face[0]), b = mesh.vertices.col(face[1]), c = mesh.vertices.col(face[2]);
    const Vec3 an = 0.5 * (b - a).cross(c - a);
    const double A = an.norm();
    const Vec3 n = an / A, centroid = (a + b + c) / 3;
    const double np = std::hypot(n.x(), n.y());
    const Vec3 f = -A * ((1 - o.specular) * Vec3(n.x(), n.y(), 0) / 4 +
                         (o.specular * np * np / 2 + o.lambertian() * np / M_PI) * n);
    F += f;
    M += centroid.cross(f);
  }
  return {F, M};
}

}  // namespace

// A box lit face-on and obliquely against (36.1) face by face; the lit hemisphere of a sphere
// (the ellipsoid of equal axes, tessellated) against the closed form F = −P π R² (1 + (4/9)(ρd + α)) u
// — a mirror sphere's C_R = 1, a Lambert sphere's 1 + 4ρd/9 — converging at second order in the
// facets' size (the inscribed polyhedron's projected area).
TEST(Radiation, BoxAndSphereAreTheirClosedForms) {
  const Vec3 half(1.0, 0.5, 0.25);
  const std::string box = "{polyhedron: {file: " + obj_file(test::box_mesh(half), "radiation-box") + ", units: m}}";
  for (const Optics& o : {Optics{0, 0, true}, Optics{0.3, 0.2, true}, Optics{0.1, 0.6, false}})
    for (const Vec3& u : {Vec3(1, 0, 0), Vec3(0.6, -0.48, 0.64)}) {
      const Scene scene = lit_body(box, o, 7.0 * u);
      const auto [F, M] = FirstForce(scene)(scene.initial);
      const auto [F0, M0] = box_closed_form(half, u, o);
      EXPECT_LT((F - F0).norm(), 1e-14 * F0.norm()) << o.yaml();
      EXPECT_LT((M - M0).norm(), 1e-14 * F0.norm()) << o.yaml();
    }

  for (const Optics& o : {Optics{0, 0, true}, Optics{1, 0, true}, Optics{0, 1, false}, Optics{0.2, 0.3, true}}) {
    const Vec3 u = Vec3(0.3, -0.2, 0.9).normalized();
    const double exact = M_PI * (1 + (4.0 / 9.0) * (3.0 / 2.0) * o.lambertian());
    double error[2];
    for (const int level : {4, 5}) {
      const Scene scene = lit_body("{ellipsoid: {semi_axes: [1, 1, 1]}}", o, 3.0 * u,
                                   ", tessellation: " + std::to_string(level));
      const Vec3 F = FirstForce(scene)(scene.initial).first;
      EXPECT_LT((F + F.norm() * u).norm(), 1e-3 * F.norm()) << "along −u";
      error[level - 4] = std::abs(F.norm() - exact) / exact;
    }
    std::printf("%s: sphere's |F| / P π R² off the closed form by %.2e (level 4), %.2e (5): ratio %.2f\n",
                o.yaml().c_str(), error[0], error[1], error[0] / error[1]);
    EXPECT_LT(error[1], 2e-3);
    EXPECT_NEAR(error[0] / error[1], 4.0, 0.3);
  }
}

// Bad input names the field.
TEST(Radiation, RefusesWhatItCannotModel) {
  const std::string sphere = "{ellipsoid: {semi_axes: [1, 1, 1]}}";
  auto message = [](const std::string& yaml) {
    try {
      const Scene scene = parse_scene(yaml, "bad.yaml");
      registry().make_force("radiation", scene.system, scene.forces[0].params);
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  const std::string head = "G: 1\nbodies:\n  - {name: rock, mass: 1, shape: " + sphere +
                           ", position: [0, 0, 0], velocity: [0, 0, 0]}\n"
                           "  - {name: dot, mass: 1, position: [5, 0, 0], velocity: [0, 0, 0]}\n"
                           "potential: {plugin: point-mass}\nintegrator: {plugin: lgvi, step: 0.01}\n"
                           "run: {t_end: 1, output_every: 1}\nforces: [{plugin: radiation, distance: 1, ";
  EXPECT_NE(message(head + "pressure: 1, body: dot, sun: rock}]\n").find("'dot' has no surface"), std::string::npos);
  EXPECT_NE(message(head + "pressure: 1, body: rock, sun: rock}]\n").find("'sun' must name another body"), std::string::npos);
  EXPECT_NE(message(head + "pressure: 1, body: rock, sun: dot, specular: 0.7, diffuse: 0.4}]\n").find("more than all the light"),
            std::string::npos);
  EXPECT_NE(message(head + "pressure: 1, body: rock}]\n").find("give the Sun"), std::string::npos);
  EXPECT_NE(message(head + "pressure: 1, body: rock, position: [1, 0, 0], velocity: [0, 1, 0]}]\n").find("give 'mu'"),
            std::string::npos);
  EXPECT_NE(message(head + "pressure: 1, body: rock, sun: dot, position: [1, 0, 0]}]\n").find("not both"), std::string::npos);
  EXPECT_NE(message(head + "pressure: 1, body: rock, sun: dot, tessellation: 9}]\n").find("tessellation must be in [0, 7]"),
            std::string::npos);
  EXPECT_NE(message(head + "body: rock, sun: dot, pressure: -1}]\n").find("'pressure' must be positive"),
            std::string::npos);
}

namespace {

// 1999 KW4 Alpha's radar shape (or an ellipsoid) alone, spinning about its principal z axis, lit by
// the Sun on a circular orbit 1 au away in its equatorial plane (obliquity 0), with a pressure
// 10⁴ times the Sun's (the changes are linear in it) for a measurable change in a short run of
// `turns` synodic days, 160 steps each. |Π| — the body's angular momentum, which only torque
// changes — oscillates within a day; its secular change is that of its mean over a day, taken over
// the first and the last day.
struct SpinChange {
  double dPi, T, C;
  Mesh mesh;
};

constexpr double kYorpPressure = 4.5606e-2, kSpin = 6.313486162248933e-4;

SpinChange yorp_run(const std::string& shape, const Optics& o, int turns, double pressure = kYorpPressure, int kSteps = 160) {
  const double n_sun = std::sqrt(kSunMu / (kAu * kAu * kAu)), synodic = 2 * M_PI / (kSpin - n_sun);
  const double h = synodic / kSteps;
  std::ostringstream yaml;
  yaml.precision(17);
  yaml << "G: " << kG << "\nbodies:\n  - {name: alpha, density: 1970, shape: " << shape
       << ", position: [0, 0, 0], velocity: [0, 0, 0], angular_velocity: [0, 0, " << kSpin << "]}\n"
       << "potential: {plugin: point-mass}\n"
       << "forces: [{plugin: radiation, body: alpha, pressure: " << pressure << ", distance: " << kAu << ", "
       << o.yaml() << ", center: alpha, mu: " << kSunMu << ", position: [" << kAu << ", 0, 0], velocity: [0, "
       << kAu * n_sun << ", 0]}]\n"
       << "integrator: {plugin: lgvi, step: " << h << "}\nrun: {t_end: " << turns * synodic
       << ", output_every: " << turns * synodic << "}\n";
  const Scene scene = parse_scene(yaml.str(), "yorp");
  Simulation sim(scene, registry());
  double first = 0.0, last = 0.0;
  for (int k = 0; k < turns * kSteps; ++k) {
    if (k > 0) sim.integrate(k * h);
    if (k < kSteps) first += sim.state().Pi.col(0).norm() / kSteps;
    if (k >= (turns - 1) * kSteps) last += sim.state().Pi.col(0).norm() / kSteps;
  }
  const Mesh mesh = scene.system.body(0).solid->kind == Solid::Kind::Polyhedron
                        ? scene.system.body(0).solid->mesh
                        : tessellated_ellipsoid(scene.system.body(0).solid->semi_axes, 4);
  return {last - first, (turns - 1) * synodic, scene.system.body(0).inertia(2, 2), mesh};
}

const std::string kAlphaShape =
    "{polyhedron: {file: " + test::source_path("examples/shapes/a66391_1999kw4_primary.obj") + ", units: km}}";

}  // namespace

// YORP: Alpha's spin changes, in the forced LGVI over 12 synodic days, as the rotation-averaged
// torque's closed form (36.3) says, d|Π|/dt = ⟨M_z⟩: within 1e-3 (the issue asks 5 %) for two sets
// of optical properties. The difference is the run's, not the model's: it changes sign when the
// steps are halved (3.5e-4 at 160 steps a day, −3.0e-4 at 320) and does not scale with the pressure.
// An ellipsoid of Alpha's size, with its three mirror planes, has no secular YORP: the closed form
// sums to round-off, and its run's spin changes by less than that sampling error (6e-5 of Alpha's).
TEST(Radiation, YorpIsTheRotationAveragedTorque) {
  double alpha_rate = 0.0;
  for (const Optics& o : {Optics{0, 0, true}, Optics{0.1, 0.2, true}}) {
    const SpinChange run = yorp_run(kAlphaShape, o, 12);
    const double predicted = kYorpPressure * turn_average(run.mesh, o).second.z() * run.T;
    const double rate = run.dPi / run.C / run.T;
    std::printf("%s: Alpha's YORP dω/dt = %.4e rad/s² (run), %.4e (closed form), differing by %.2e\n",
                o.yaml().c_str(), rate, predicted / run.C / run.T, run.dPi / predicted - 1);
    EXPECT_NEAR(run.dPi / predicted, 1.0, 1e-3);
    alpha_rate = rate;
  }
  const Optics o{0.1, 0.2, true};
  const SpinChange sym = yorp_run("{ellipsoid: {semi_axes: [766, 747.5, 673.5]}}", o, 12);
  double scale = 0.0;  // Σ A |c|, the size of one facet's torque summed
  for (const auto& face : sym.mesh.faces) {
    const Vec3 a = sym.mesh.vertices.col(face[0]), b = sym.mesh.vertices.col(face[1]), c = sym.mesh.vertices.col(face[2]);
    scale += 0.5 * (b - a).cross(c - a).norm() * ((a + b + c) / 3).norm();
  }
  const double Mz = turn_average(sym.mesh, o).second.z(), rate = sym.dPi / sym.C / sym.T;
  std::printf("ellipsoid: closed-form ⟨M_z⟩ = %.2e Σ A |c|; the run's dω/dt = %.2e of Alpha's\n", std::abs(Mz) / scale,
              rate / alpha_rate);
  EXPECT_LT(std::abs(Mz), 1e-15 * scale);
  EXPECT_LT(std::abs(rate), 3e-4 * std::abs(alpha_rate));
}

// The plugin's own torque, averaged over N Sun azimuths 2πk/N in the equatorial plane: for Alpha it
// tends to the closed form (36.3) (N = 64: 5e-4, 256: 8e-5, 1024: 2e-6, 4096: 5e-7, 16384: 9e-8);
// for bodies with a mirror plane through the spin axis — the tessellated ellipsoid, a regular octahedron and one stretched along
// its axes, and a concave L of cubes with its shadows on itself — the azimuths pair up by the mirror
// and the average is zero to round-off, at any N. Alpha's own shadows move its averaged torque.
TEST(Radiation, SymmetricBodiesHaveNoAveragedSpinTorque) {
  const Optics o{0.2, 0.3, true};
  auto averaged = [&](const std::string& shape, int N, double* size, const std::string& extra = "") {
    double Mz = 0.0, sum_abs = 0.0;
    const Scene scene = lit_body(shape, o, Vec3(1e3, 0, 0), extra);
    FirstForce evaluate(scene);
    State s = scene.initial;
    for (int k = 0; k < N; ++k) {  // the body turned by −φ: the Sun at azimuth φ in its frame
      const double phi = 2 * M_PI * k / N;
      s.R[0] = Eigen::AngleAxisd(-phi, Vec3::UnitZ()).toRotationMatrix();
      const auto [F, M] = evaluate(s);
      Mz += M.z() / N;
      sum_abs += F.norm() * scene.system.body(0).solid->radius / N;  // the size of a lever's torque
    }
    if (size) *size = sum_abs;
    return Mz;
  };
  const std::string alpha = "{polyhedron: {file: " + test::source_path("examples/shapes/a66391_1999kw4_primary.obj") +
                            ", units: km}}";
  const Scene a = lit_body(alpha, o, Vec3(1e3, 0, 0));
  const double closed = turn_average(a.system.body(0).solid->mesh, o).second.z();  // P = 1 at 1e3
#ifdef NOETHER_TEST_SANITIZED  // 16 times fewer evaluations of Alpha's 9168 facets under the sanitizers
  const int azimuths = 256;
  const double within = 2e-4;
#else
  const int azimuths = 4096;
  const double within = 1e-6;
#endif
  const double error = averaged(alpha, azimuths, nullptr) / closed - 1;
  std::printf("Alpha: the plugin's torque averaged over %d azimuths off the closed form by %.1e\n", azimuths, error);
  EXPECT_LT(std::abs(error), within);
  // Alpha's shadows on itself: its YORP torque at 256 azimuths (measured, for docs/forces.md).
  const double shadowed = averaged(alpha, 256, nullptr, ", self_shadowing: true") / averaged(alpha, 256, nullptr);
  std::printf("Alpha with its own shadows: the averaged spin torque is %.4f of the shadowless one (256 azimuths)\n",
              shadowed);
  EXPECT_GT(std::abs(shadowed - 1), 1e-4);  // they move it (Alpha is not convex)

  auto octahedron = [](const Vec3& axes) {
    Mesh m;
    m.vertices.resize(3, 6);
    m.vertices << axes.x(), -axes.x(), 0, 0, 0, 0, 0, 0, axes.y(), -axes.y(), 0, 0, 0, 0, 0, 0, axes.z(), -axes.z();
    m.faces = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    return m;
  };
  const std::vector<std::pair<std::string, std::string>> shapes = {
      {"ellipsoid", "{ellipsoid: {semi_axes: [3, 2, 1.5]}}"},
      {"regular octahedron", "{polyhedron: {file: " + obj_file(octahedron(Vec3(1, 1, 1)), "radiation-octahedron") + ", units: m}}"},
      {"stretched octahedron",
       "{polyhedron: {file: " + obj_file(octahedron(Vec3(3, 2, 1)), "radiation-octahedron-3-2-1") + ", units: m}}"},
      // Concave, with a mirror plane (y = ½) through its spin axis: its shadows on itself pair up too.
      {"L of cubes, shadowed",
       "{polyhedron: {file: " + obj_file(test::voxel_mesh({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 0, 1}}, 4), "radiation-L") +
           ", units: m}}"}};
  for (const auto& [name, shape] : shapes)
    for (const int N : {7, 64}) {
      double size = 0.0;
      const double Mz = averaged(shape, N, &size,
                                 name == "ellipsoid" ? ", tessellation: 3"
                                 : name == "L of cubes, shadowed" ? ", self_shadowing: true"
                                                                  : "");
      std::printf("%s, %d azimuths: ⟨M_z⟩ = %.1e ⟨|F|⟩ R\n", name.c_str(), N, std::abs(Mz) / size);
      EXPECT_LT(std::abs(Mz), 1e-14 * size) << name;
    }
}

namespace {

// (36.1) summed over a mesh's facets, for a Sun in direction u (body frame), per unit pressure:
// the force and its torque about the origin.
std::pair<Vec3, Vec3> facet_sum(const Mesh& mesh, const Vec3& u, const Optics& o) {
  Vec3 F = Vec3::Zero(), M = Vec3::Zero();
  for (const auto& face : mesh.faces) {
    const Vec3 a = mesh.vertices.col(face[0]), b = mesh.vertices.col(face[1]), c = mesh.vertices.col(face[2]);
    const Vec3 an = 0.5 * (b - a).cross(c - a);
    const double A = an.norm(), mu = an.dot(u) / A;
    if (mu <= 0) continue;
    const Vec3 f = -A * mu * ((1 - o.specular) * u + (2 * o.specular * mu + o.lambertian()) * an / A);
    F += f;
    M += ((a + b + c) / 3).cross(f);
  }
  return {F, M};
}

// 1999 KW4 Beta's radar shape, synchronous on a circular orbit about Alpha (a point mass), its long
// axis towards Alpha, lit with a pressure 10⁴ times the Sun's by a Sun over the mutual orbit's pole
// (a scene body of 1 kg at rest 1 au away). The light comes from Beta's +z at every moment, so its
// force and torque are nearly fixed in Beta's frame: the push along the motion f_t and the torque
// M_n about the orbit's normal move the separation at (36.4), while the force's other components
// only displace the orbit. Measured over `orbits` mutual orbits of 200 steps, from the mean
// separation over the first orbit and over the last; f_t and M_n are averaged over the run's
// states (Beta librates and tilts a little).
struct Byorp {
  double measured, predicted;
};

Byorp byorp_run(const std::string& shape, const Optics& o, int orbits) {
  const double m_alpha = 2.353e12, r = 2548.0, pressure = 4.5606e-2;
  constexpr int kSteps = 200;
  auto yaml = [&](double n) {
    std::ostringstream y;
    y.precision(17);
    const double T = 2 * M_PI / n;
    y << "G: " << kG << "\nbodies:\n  - {name: alpha, mass: " << m_alpha << ", position: [0, 0, 0], velocity: [0, 0, 0]}\n"
      << "  - {name: beta, density: 2810, shape: " << shape << ", position: [" << r << ", 0, 0], velocity: [0, "
      << n * r << ", 0], angular_velocity: [0, 0, " << n << "]}\n"
      << "  - {name: sun, mass: 1, position: [0, 0, " << kAu << "], velocity: [0, 0, 0]}\n"
      << "potential: {plugin: mutual-series, order: 2}\n"
      << "forces: [{plugin: radiation, body: beta, sun: sun, pressure: " << pressure << ", distance: " << kAu << ", "
      << o.yaml() << "}]\n"
      << "integrator: {plugin: lgvi, step: " << T / kSteps << "}\nrun: {t_end: " << orbits * T
      << ", output_every: " << T << "}\n";
    return y.str();
  };
  // The circular orbit's mean motion with Beta's quadrupole (MacCullagh), n² = μ/r³ (1 + ε) (36.4).
  const Scene first = parse_scene(yaml(1e-4), "byorp");
  const Body& beta = first.system.body(1);
  const double mu = kG * (m_alpha + beta.mass), J = beta.inertia.trace() - 3 * beta.inertia(0, 0);
  const double n = std::sqrt(mu / (r * r * r) * (1 + 1.5 * J / (beta.mass * r * r)));
  const Scene scene = parse_scene(yaml(n), "byorp");
  Simulation sim(scene, registry());
  const double h = 2 * M_PI / n / kSteps;
  std::vector<double> orbit_mean(static_cast<std::size_t>(orbits), 0.0);
  // The force along the motion and the torque about the orbit's normal, averaged (f_y and M_z but for
  // Beta's small libration and tilt).
  double f_t = 0.0, M_n = 0.0;
  for (int k = 0; k < orbits * kSteps; ++k) {
    if (k > 0) sim.integrate(k * h);
    const State& s = sim.state();
    const Vec3 x = s.x.col(1) - s.x.col(0), v = s.p.col(1) / beta.mass - s.p.col(0) / m_alpha;
    orbit_mean[static_cast<std::size_t>(k / kSteps)] += x.norm() / kSteps;
    const Vec3 sun = (s.x.col(2) - s.x.col(1)).normalized();
    const auto [f, M] = facet_sum(beta.solid->mesh, s.R[0].transpose() * sun, o);
    f_t += pressure * f.dot(s.R[0].transpose() * v.normalized()) / (orbits * kSteps);
    M_n += pressure * M.dot(s.R[0].transpose() * x.cross(v).normalized()) / (orbits * kSteps);
  }
  const double slope = (orbit_mean.back() - orbit_mean.front()) / ((orbits - 1) * 2 * M_PI / n);
  const double reduced_mass = m_alpha * beta.mass / (m_alpha + beta.mass), C = beta.inertia(2, 2);
  const double eps = 1.5 * J / (beta.mass * r * r), d = eps / (1 + eps);
  const double dL_dr = reduced_mass * r * n * (0.5 - d) - C * n / r * (1.5 + d);
  return {slope, (reduced_mass / beta.mass * r * f_t + M_n) / dL_dr};
}

const std::string kBetaShape =
    "{polyhedron: {file: " + test::source_path("examples/shapes/a66391_1999kw4_secondary.obj") + ", units: km}}";

}  // namespace

// BYORP: the light's push on Beta along its motion, and its torque passed to the orbit by the lock,
// drift the separation at the rate (36.4): the forced LGVI's drift over 20 orbits against it, 1.9e-3
// apart (test: 1 %; the residual is the free libration's, not averaged away in 20 orbits). An
// ellipsoidal secondary (a mirror plane through its orbit's direction) has none: its drift is 5e-4
// of Beta's (test: 1 %).
TEST(Radiation, ByorpMovesTheOrbitAsItsAngularMomentumSays) {
  const Optics o{0.1, 0.2, true};
  const Byorp beta = byorp_run(kBetaShape, o, 20);
  std::printf("Beta's BYORP: dr/dt = %.4e m/s (run), %.4e (36.4), differing by %.2e\n", beta.measured,
              beta.predicted, beta.measured / beta.predicted - 1);
  EXPECT_NEAR(beta.measured / beta.predicted, 1.0, 0.01);
  const Byorp ellipsoid = byorp_run("{ellipsoid: {semi_axes: [285, 231.5, 174.5]}}", o, 20);
  std::printf("an ellipsoid's: dr/dt = %.4e m/s (run) = %.2e of Beta's; (36.4) %.1e\n", ellipsoid.measured,
              ellipsoid.measured / beta.measured, ellipsoid.predicted);
  EXPECT_LT(std::abs(ellipsoid.measured), 0.01 * std::abs(beta.measured));
}

namespace {

// The overlap of two disks of radii R and r whose centres are d apart (R − r < d < R + r).
double lens_area(double R, double r, double d) {
  return r * r * std::acos((d * d + r * r - R * R) / (2 * d * r)) + R * R * std::acos((d * d + R * R - r * r) / (2 * d * R)) -
         0.5 * std::sqrt((-d + r + R) * (d + r - R) * (d - r + R) * (d + r + R));
}

// A unit sphere (tessellated at `level`) at the origin lit from +x (pressure 1; the light absorbed
// and not re-emitted, so the force is −P u Σ A μ over the lit facets: −u times the lit part of
// its silhouette), and another body `occluder` (a YAML mapping's body entries after the name).
Scene eclipse_scene(int level, const std::string& occluder, const std::string& extra = "") {
  std::ostringstream yaml;
  yaml << "G: 1\nbodies:\n  - {name: rock, mass: 1, shape: {ellipsoid: {semi_axes: [1, 1, 1]}}, position: [0, 0, 0], "
          "velocity: [0, 0, 0]}\n";
  if (!occluder.empty()) yaml << "  - {name: moon, " << occluder << "}\n";
  yaml << "potential: {plugin: point-mass}\n"
       << "forces: [{plugin: radiation, body: rock, pressure: 1, distance: 1000, thermal: false, tessellation: " << level
       << ", position: [1000, 0, 0], velocity: [0, 0, 0], mu: 1, center: origin" << extra << "}]\n"
       << "integrator: {plugin: lgvi, step: 0.01}\nrun: {t_end: 1, output_every: 1}\n";
  return parse_scene(yaml.str(), "eclipse");
}

}  // namespace

// Another body's shadow (eclipses, docs/equations.md (36.5)): a unit sphere behind a sphere of
// radius 0.6 whose disk covers part of its own, 0.9 off the line of the light. The sphere takes
// the light its silhouette's uncovered part intercepts, π − lens(1, 0.6, 0.9): converging with its
// facets (lit or shaded whole, by their centroids). The occluder as a point mass with that radius,
// as an ellipsoid of equal axes and as a tessellated polyhedron (its facets seen along the light
// through the occlusion map of noether/occlusion_map.hpp) casts that shadow; in front of a larger sphere the body
// takes no light at all, and behind the lit body, or with `eclipses: false`, it changes nothing.
TEST(Radiation, EclipsesTakeTheLightTheOccludersDiskCovers) {
  const std::string where = "position: [3, 0.9, 0], velocity: [0, 0, 0]";
  const double exact = (M_PI - lens_area(1.0, 0.6, 0.9)) / M_PI;  // the lit fraction of the silhouette
  double previous = 1.0;
  for (const int level : {3, 4, 5, 6}) {
    const double free = -FirstForce(eclipse_scene(level, ""))(eclipse_scene(level, "").initial).first.x();
    const Scene scene = eclipse_scene(level, "mass: 1, radius: 0.6, " + where);
    const double lit = -FirstForce(scene)(scene.initial).first.x();
    const double error = std::abs(lit / free - exact);
    std::printf("level %d (%d facets): lit fraction %.6f, exact %.6f, error %.2e\n", level, 20 << (2 * level), lit / free,
                exact, error);
    EXPECT_LT(error, previous) << level;
    previous = error;
  }
  EXPECT_LT(previous, 2e-3);
  // The same shadow from each kind of occluder, at level 5.
  const Scene sphere = eclipse_scene(5, "mass: 1, radius: 0.6, " + where);
  const Scene ellipsoid = eclipse_scene(5, "mass: 1, shape: {ellipsoid: {semi_axes: [0.6, 0.6, 0.6]}}, " + where);
  const std::string mesh = obj_file(test::ellipsoid_mesh(Vec3(0.6, 0.6, 0.6), 4), "occluder-sphere");
  const Scene polyhedron = eclipse_scene(5, "mass: 1, shape: {polyhedron: {file: " + mesh + ", units: m}}, " + where);
  const auto [f_sphere, M_sphere] = FirstForce(sphere)(sphere.initial);
  const auto [f_ellipsoid, M_ellipsoid] = FirstForce(ellipsoid)(ellipsoid.initial);
  const auto [f_polyhedron, M_polyhedron] = FirstForce(polyhedron)(polyhedron.initial);
  std::printf("occluders: sphere %.9f, ellipsoid %.9f, polyhedron %.9f\n", f_sphere.x(), f_ellipsoid.x(), f_polyhedron.x());
  EXPECT_LT((f_ellipsoid - f_sphere).norm(), 1e-12 * f_sphere.norm());
  EXPECT_LT((f_polyhedron - f_sphere).norm(), 5e-3 * f_sphere.norm());  // the inscribed mesh is a little smaller
  EXPECT_GT(M_sphere.norm(), 1e-3);  // a shadow off the axis twists the sphere
  // Full shade, a body behind, eclipses off.
  const Scene umbra = eclipse_scene(5, "mass: 1, radius: 2, position: [3, 0, 0], velocity: [0, 0, 0]");
  const auto [f_umbra, M_umbra] = FirstForce(umbra)(umbra.initial);
  EXPECT_EQ(f_umbra, Vec3::Zero());
  EXPECT_EQ(M_umbra, Vec3::Zero());
  const auto alone = FirstForce(eclipse_scene(5, ""))(eclipse_scene(5, "").initial);
  const Scene behind = eclipse_scene(5, "mass: 1, radius: 2, position: [-3, 0, 0], velocity: [0, 0, 0]");
  const Scene off = eclipse_scene(5, "mass: 1, radius: 2, position: [3, 0, 0], velocity: [0, 0, 0]", ", eclipses: false");
  EXPECT_EQ(FirstForce(behind)(behind.initial), alone);
  EXPECT_EQ(FirstForce(off)(off.initial), alone);
}

// The body's shadow on itself (`self_shadowing`, (36.5)): an L of four unit cubes — a step of
// three and a tower on its left — lit from the upper left, u = (−1, 0, 2)/√5, so that the tower
// shades the step's top from x = 1 to 1.5, a line its facets' edges fall on. Absorbed light (no
// re-emission) pushes with −P u Σ A μ and twists with −P (Σ A μ c) × u over the lit facets: with
// the shadow, Σ A μ is the silhouette's area, (2·1 + 1·2 + 1.5·2)/√5 = 7/√5 — the light the body
// intercepts — and without it the shaded part of the step counts too, 8/√5. Both to round-off,
// with the torque from the lit faces' centroids. A convex body has no shadows of its own: the same
// bits either way.
TEST(Radiation, SelfShadowingTakesTheLightTheSilhouetteIntercepts) {
  const Mesh L = test::voxel_mesh({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 0, 1}}, 8);
  const std::string shape = "{polyhedron: {file: " + obj_file(L, "step") + ", units: m}}";
  const Optics absorbed{0.0, 0.0, false};
  // The body frame is the mesh's about its centre of mass, turned to its principal axes:
  // x_file = offset + rotation x_body.
  const Scene placed = lit_body(shape, absorbed, Vec3(1000, 0, 0));
  const Solid& solid = *placed.system.body(0).solid;
  const Vec3 u_file = Vec3(-1, 0, 2) / std::sqrt(5.0), u = solid.rotation.transpose() * u_file;
  const double s5 = std::sqrt(5.0);
  // Σ A μ c over the lit faces in the file's frame: the left face (area 2 at (0, ½, 1), μ = 1/√5),
  // the tower's top (1 at (½, ½, 2), μ = 2/√5) and the step's top, its lit part x ∈ [1.5, 3] or all of it.
  const Vec3 left = 2 / s5 * Vec3(0, 0.5, 1), tower = 2 / s5 * Vec3(0.5, 0.5, 2);
  for (const bool shadows : {true, false}) {
    const Scene scene = lit_body(shape, absorbed, 1000 * u, shadows ? ", self_shadowing: true" : "");
    const auto [f, M] = FirstForce(scene)(scene.initial);
    const Vec3 step = shadows ? Vec3(2 / s5 * 1.5 * Vec3(2.25, 0.5, 1)) : Vec3(2 / s5 * 2 * Vec3(2, 0.5, 1));
    const double area = shadows ? 7 / s5 : 8 / s5;
    const Vec3 moment = solid.rotation.transpose() * (left + tower + step - area * solid.offset);
    const Vec3 f_exact = -area * u, M_exact = -moment.cross(u);
    std::printf("self_shadowing %s: |f| %.15f (exact %.15f), torque off by %.1e\n", shadows ? "on " : "off", f.norm(),
                f_exact.norm(), (M - M_exact).norm() / M_exact.norm());
    EXPECT_LT((f - f_exact).norm(), 1e-13 * area) << shadows;
    EXPECT_LT((M - M_exact).norm(), 1e-13 * M_exact.norm()) << shadows;
  }
  // Convex: the sphere of the closed-form test, lit obliquely.
  const Vec3 sun = 1000 * Vec3(0.3, -0.5, 0.8).normalized();
  const std::string sphere = "{ellipsoid: {semi_axes: [1, 0.8, 0.6]}}";
  const Scene plain = lit_body(sphere, Optics{0.1, 0.2, true}, sun);
  const Scene shaded = lit_body(sphere, Optics{0.1, 0.2, true}, sun, ", self_shadowing: true");
  EXPECT_EQ(FirstForce(plain)(plain.initial), FirstForce(shaded)(shaded.initial));
}
