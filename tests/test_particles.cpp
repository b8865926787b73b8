// Massless particles (particles.hpp, body_field.hpp; docs/equations.md §38): the bodies' fields
// they feel, their Verlet map, their landings against the real shapes, and a run that carries them.
#include <noether/body_field.hpp>
#include <noether/error.hpp>
#include <noether/particles.hpp>
#include <noether/simulation.hpp>
#include <noether/surface_distance.hpp>

#include "io/checksum.hpp"
#include "test_support.hpp"

#include <boost/numeric/odeint/stepper/runge_kutta_fehlberg78.hpp>
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <random>
#include <sstream>

using namespace noether;
using test::source_path;

namespace {

// One body at rest at the origin (turning at `spin` about its body z), G and shape from `body`.
Scene lone_body_scene(const std::string& body, double spin, const std::string& particles,
                      const std::string& integrator = "{plugin: lgvi, step: 10}", const std::string& run = "{t_end: 100, output_every: 100}") {
  char omega[32];
  std::snprintf(omega, sizeof omega, "%.17g", spin);
  return parse_scene("units: SI\nG: 6.674e-11\nbodies:\n  - {name: rock, " + body +
                         ", position: [0, 0, 0], angular_velocity: [0, 0, " + omega + "]}\n" +
                         "potential: {plugin: point-mass}\nintegrator: " + integrator + "\nrun: " + run +
                         "\nparticles: " + particles + "\n",
                     source_path("examples/particles-test.yaml"));
}

// The bodies' state at t, at rest, turned by the uniform spin of the scene's first body.
State turned(const Scene& scene, double t) {
  State s = scene.initial;
  s.t = t;
  if (!s.R.empty()) s.R[0] = exp_so3(t * (scene.system.body(0).inertia_inverse * s.Pi.col(0)));
  return s;
}

}  // namespace

// (38.2): beyond the measured series radius the series' acceleration is within the tolerance of
// the exact field at points the ladder did not try; inside it the field is the exact one.
TEST(Particles, TheSeriesRadiusIsWhereTheSeriesMeetsTheTolerance) {
#ifdef NOETHER_TEST_SANITIZED
  GTEST_SKIP() << "Alpha's exact field ~10^5 times: the ladder itself runs in ARunWritesEachParticlesFate";
#endif
  const Scene scene = parse_scene(R"(G: 1
bodies:
  - {name: a, density: 1, shape: {polyhedron: {file: shapes/a66391_1999kw4_primary.obj, units: km}}, position: [0, 0, 0]}
potential: {plugin: point-mass}
integrator: {plugin: lgvi, step: 1}
run: {t_end: 1, output_every: 1}
)", source_path("examples/x.yaml"));
  const Body& body = scene.system.body(0);
  const PolyhedronField exact(body.solid->mesh, body.solid->density);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  double previous = std::numeric_limits<double>::infinity();
  for (const double tolerance : {1e-6, 1e-9, 1e-12}) {
    BodyField field(body, 1.0, {16, tolerance});
    const double rs = field.series_radius();
    ASSERT_TRUE(std::isfinite(rs)) << tolerance;
    EXPECT_GT(rs, body.solid->radius);
    EXPECT_GE(rs, previous == std::numeric_limits<double>::infinity() ? 0.0 : previous) << "a tighter tolerance, a larger radius";
    previous = rs;
    double worst = 0.0;
    for (int k = 0; k < 300; ++k) {
      const Vec3 u = Vec3(normal(rng), normal(rng), normal(rng)).normalized();
      const double r = rs * (1.0 + 0.0001 + 2.0 * k / 300.0);
      const Vec3 g = exact(r * u).g;
      worst = std::max(worst, (field(r * u).acceleration - g).norm() / g.norm());
      const Vec3 inside = 0.999 * rs * u;  // the exact field itself, bit for bit
      EXPECT_EQ(field(inside).acceleration, exact(inside).g);
    }
    std::printf("tolerance %.0e: series radius %.4f bounding radii, worst %.2e beyond it\n", tolerance,
                rs / body.solid->radius, worst);
    EXPECT_LE(worst, 2 * tolerance);
  }
}

// A particle on a circular orbit about a spinning sphere keeps its energy to the Verlet map's
// error, bounded over 20 orbits (no drift); on an eccentric one the error is of order 2 in the step.
TEST(Particles, AnOrbitAboutASphereKeepsItsEnergy) {
  for (const double e : {0.0, 0.4}) {
  double errors[2];
  Vec3 ends[2];
  ParticleCheck checked;  // of the run at h: its particle carried again at h/2
  for (int halving = 0; halving < 2; ++halving) {
    const double h = 40.0 / (1 << halving);
    const Scene scene = lone_body_scene("density: 2000, shape: {ellipsoid: {semi_axes: [500, 500, 500]}}", 3e-4,
                                        "{around: rock, orbits: [{a: 1500, e: " + std::to_string(e) + ", i: 30, Omega: 10}]}");
    ParticleSwarm swarm(scene.system, scene.particles, scene.initial);
    const double E0 = swarm.energy(0, scene.initial);
    const double mu = scene.system.G() * scene.system.body(0).mass, period = 2 * M_PI * std::sqrt(std::pow(1500.0, 3) / mu);
    const int steps = static_cast<int>(std::round(20 * period / 40.0)) << halving;  // both to the same time
    double worst = 0.0, late = 0.0;
    State from = turned(scene, 0.0);
    for (int k = 1; k <= steps; ++k) {
      const State to = turned(scene, k * h);
      swarm.advance(from, to, 1);
      const double e = std::abs(swarm.energy(0, to) - E0) / std::abs(E0);
      worst = std::max(worst, e);
      if (k > steps / 2) late = std::max(late, e);
      from = to;
    }
    ASSERT_EQ(swarm.outcomes()[0].fate, ParticleFate::in_flight);
    if (e == 0.0) EXPECT_NEAR((swarm.positions().col(0) - scene.initial.x.col(0)).norm(), 1500.0, 1e-6 * 1500.0);
    ends[halving] = swarm.positions().col(0);
    if (halving == 0) checked = swarm.check(from);
    std::printf("e = %g, h = %g (%d steps an orbit): max |dE/E| %.3e, in the second half %.3e\n", e, h,
                static_cast<int>(period / h), worst, late);
    EXPECT_LT(worst, e == 0.0 ? 1e-9 : 1e-4);
    EXPECT_GT(late, 0.5 * worst) << "bounded: the second half's error is the first's, not a drift";
    EXPECT_LE(late, worst);
    errors[halving] = worst;
  }
  // The step-halving check (particles.check) carried the particle at h/2 beside the run at h:
  // it is the run at h/2 (whose bodies were turned exactly at the midpoints, where the check
  // interpolates them: the same to round-off).
  EXPECT_EQ(checked.checked, 1u);
  EXPECT_EQ(checked.fates_differ, 0u);
  EXPECT_NEAR(checked.position, (ends[0] - ends[1]).norm() / ends[0].norm(), 1e-6 * checked.position);
  EXPECT_GT(checked.position, 0.0);
  // A circular orbit's error is of order 4 (the h² term of the modified energy is constant on it).
  const double order = std::log2(errors[0] / errors[1]);
  std::printf("e = %g: order %.3f\n", e, order);
  EXPECT_NEAR(order, e == 0.0 ? 4.0 : 2.0, 0.1);
  }
}

// A particle that crosses the bounding sphere of an elongated body but misses its shape flies
// on; one aimed at it lands on its surface (eq. 16.5), not on the sphere.
TEST(Particles, LandOnTheShapeNotOnItsBoundingSphere) {
  // Nearly no gravity (G ρ ~ 1e-20): straight lines at 1 m/s along x.
  const Scene scene = lone_body_scene("density: 1.0e-10, shape: {ellipsoid: {semi_axes: [1000, 200, 200]}}", 0.0,
                                      "{states: [[-2000, 300, 0, 1, 0, 0], [-2000, 150, 0, 1, 0, 0], [0, 0, 1500, 0, 0, -1]]}");
  ParticleSwarm swarm(scene.system, scene.particles, scene.initial);
  State from = turned(scene, 0.0);
  for (int k = 1; k <= 400; ++k) {  // 4000 s
    const State to = turned(scene, 10.0 * k);
    swarm.advance(from, to, 1);
    from = to;
  }
  const auto& o = swarm.outcomes();
  EXPECT_EQ(o[0].fate, ParticleFate::in_flight) << "inside the bounding sphere (r = 1000), outside the ellipsoid";
  ASSERT_EQ(o[1].fate, ParticleFate::impact);
  // x² / 1000² + 150² / 200² = 1 at x = −661.4: after 1338.6 s.
  const double x = -1000.0 * std::sqrt(1.0 - 0.75 * 0.75);
  EXPECT_NEAR(o[1].t, x + 2000.0, 1e-6);
  EXPECT_NEAR(o[1].point.x(), x, 1e-6);
  EXPECT_NEAR(o[1].velocity.x(), 1.0, 1e-9);
  ASSERT_EQ(o[2].fate, ParticleFate::impact);
  EXPECT_NEAR(o[2].t, 1300.0, 1e-6);  // the top at z = 200
  EXPECT_NEAR(o[2].point.z(), 200.0, 1e-6);
}

// Each particle is independent: any number of threads gives the same bits.
TEST(Particles, TheSameBitsOnAnyNumberOfThreads) {
  std::string states = "[";
  for (int k = 0; k < 64; ++k) {
    const double a = 0.7 * k;
    states += (k ? ", [" : "[") + std::to_string(1200 + 10 * k) + ", " + std::to_string(40 * std::sin(a)) + ", " +
              std::to_string(30 * std::cos(a)) + ", 0, " + std::to_string(0.15 + 0.002 * k) + ", 0.01]";
  }
  const Scene scene = lone_body_scene("density: 2000, shape: {polyhedron: {file: shapes/hou2017_B.obj, units: km}}", 2e-4,
                                      "{states: " + states + "]}");
  std::array<Eigen::Matrix3Xd, 2> x;
  for (int threads = 1; threads <= 2; ++threads) {
    ParticleSwarm swarm(scene.system, scene.particles, scene.initial);
    State from = turned(scene, 0.0);
    for (int k = 1; k <= 200; ++k) {
      const State to = turned(scene, 30.0 * k);
      swarm.advance(from, to, threads);
      from = to;
    }
    x[static_cast<std::size_t>(threads - 1)] = swarm.positions();
  }
  EXPECT_EQ(x[0], x[1]);
}

// A particle thrown down onto KW4 Alpha (its radar shape, 9168 faces, spinning once in 2.76 h)
// lands where and when an independent calculation says: the same fall integrated by Fehlberg's
// 7(8) pair at a fixed 1 s in Alpha's exact field everywhere (the same to 1e-9 s at 0.5 s), its
// landing found by bisection on states integrated afresh from the last step's start (not on an
// interpolant). Alpha itself is integrated by rkf78 at tolerances that make its turn exact to
// round-off: the LGVI turns a spinning body by asin(hω) a step instead of hω, which at h = 1 s
// moves Alpha's surface by 4e-5 m over the fall — the bodies' error, not the particles'.
TEST(Particles, ADropOntoKw4AlphaLandsWhereAndWhenRkf78Says) {
#ifdef NOETHER_TEST_SANITIZED
  GTEST_SKIP() << "Alpha's exact field ~10^4 times: the landing itself is checked by LandOnTheShapeNotOnItsBoundingSphere";
#endif
  const double spin = 6.313486162248933e-4;
  const Scene scene = lone_body_scene("density: 1970, shape: {polyhedron: {file: shapes/a66391_1999kw4_primary.obj, units: km}}",
                                      spin, "{states: [[700, 500, 400, -0.2, -0.15, -0.1]], step: 0.1, check: 0}",
                                      "{plugin: rk, method: rkf78, rtol: 1.0e-13, atol: 1.0e-13}",
                                      "{t_end: 3000, output_every: 100}");
  PluginRegistry registry = test::bundled_plugins();
  Simulation sim(scene, registry, RunOptions{});
  sim.integrate(scene.run.t_end);
  const ParticleSwarm& swarm = *sim.particles();
  const ParticleOutcome& landed = swarm.outcomes()[0];
  ASSERT_EQ(landed.fate, ParticleFate::impact);

  // The independent fall: z = (x, v), a = R(t) g(R(t)ᵀ x), R(t) = exp(t ω ẑ).
  const Solid& alpha = *scene.system.body(0).solid;
  const PolyhedronField exact(alpha.mesh, scene.system.G() * alpha.density);
  using Z = std::array<double, 6>;
  auto rotation = [&](double t) { return exp_so3(Vec3(0, 0, spin * t)); };
  auto rhs = [&](const Z& z, Z& dz, double t) {
    const Mat3 R = rotation(t);
    const Vec3 a = R * exact(R.transpose() * Vec3(z[0], z[1], z[2])).g;
    dz = {z[3], z[4], z[5], a.x(), a.y(), a.z()};
  };
  auto gap = [&](const Z& z, double t) { return surface_gap(alpha, rotation(t).transpose() * Vec3(z[0], z[1], z[2])); };
  boost::numeric::odeint::runge_kutta_fehlberg78<Z> rkf78;
  const double h = 1.0;
  Z z{700, 500, 400, -0.2, -0.15, -0.1}, start = z;
  double t = 0.0;
  while (gap(z, t) > 0.0) {
    start = z;
    rkf78.do_step(rhs, z, t, h);
    t += h;
    ASSERT_LT(t, 3000.0);
  }
  double a = t - h, b = t;  // outside at a, inside at b
  Z at = z;
  while (b - a > 1e-10) {
    const double c = 0.5 * (a + b);
    at = start;
    rkf78.do_step(rhs, at, t - h, c - (t - h));
    (gap(at, c) > 0.0 ? a : b) = c;
  }
  const Vec3 point = rotation(b).transpose() * Vec3(at[0], at[1], at[2]);
  std::printf("landed at t = %.9f s (rkf78: %.9f s, difference %.2e s), %.3e m apart, at %.4f m/s; %s\n", landed.t,
              b, landed.t - b, (landed.point - point).norm(), landed.velocity.norm(), swarm.fields()[0].c_str());
  EXPECT_NEAR(landed.t, b, 1e-6);
  EXPECT_LT((landed.point - point).norm(), 1e-6);
  // Where it stays: on the surface, in Alpha's frame, at the landing time.
  EXPECT_NEAR(surface_gap(alpha, landed.point), 0.0, 1e-9);
}

// A run with particles: the summary counts their fates, and bad particle input is refused with
// the scene's line.
TEST(Particles, SceneErrorsNameTheField) {
  auto refused = [](const std::string& particles, const std::string& says) {
    try {
      lone_body_scene("density: 2000, shape: {ellipsoid: {semi_axes: [500, 400, 300]}}", 0.0, particles);
      ADD_FAILURE() << particles << " was accepted";
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  };
  refused("{orbits: [{a: 1000}]}", "needs 'particles.around'");
  refused("{states: [[1, 2, 3]]}", "six finite numbers");
  refused("{around: rock}", "gives no particle");
  refused("{around: stone, orbits: [{a: 1000}]}", "no body 'stone'");
  refused("{states: [[2000, 0, 0, 0, 0, 0]], step: 0}", "'particles.step' must be");
  refused("{states: [[2000, 0, 0, 0, 0, 0]], speed: 1}", "speed");
  refused("{file: no-such-file.csv}", "not found");
  const std::string cloud = "{ejecta: {body: rock, site: [10, 20], count: 10, speed: [0.1, 0.5]";
  refused(cloud + ", cone: 90}}", "'particles.ejecta.cone'");
  refused(cloud + ", exponent: 0}}", "'particles.ejecta.exponent'");
  refused("{ejecta: {body: rock, site: [10, 20], count: 10, speed: [0.5, 0.1]}}", "'particles.ejecta.speed' is [min, max]");
  refused("{ejecta: {body: rock, site: [100, 20], count: 10, speed: [0.1, 0.5]}}", "latitude in [-90, 90]");
  refused("{ejecta: {body: rock, site: [10, 20], count: 0, speed: [0.1, 0.5]}}", "'particles.ejecta.count' must be");
  refused("{ejecta: {body: rock, count: 10, speed: [0.1, 0.5]}}", "'particles.ejecta' needs 'site'");
  refused("{ejecta: {body: stone, site: [10, 20], count: 10, speed: [0.1, 0.5]}}", "no body 'stone'");
  refused(cloud + ", angle: 30}}", "angle");
  try {  // a point mass has no surface to leave
    parse_scene("units: SI\nG: 6.674e-11\nbodies:\n  - {name: rock, mass: 1.0e12, position: [0, 0, 0]}\n"
                "potential: {plugin: point-mass}\nintegrator: {plugin: lgvi, step: 10}\nrun: {t_end: 100}\n"
                "particles: " + cloud + "}}\n",
                source_path("examples/particles-test.yaml"));
    ADD_FAILURE() << "ejecta from a point mass were accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("'rock' has no surface to throw ejecta from"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("particles-test.yaml:"), std::string::npos) << e.what();
  }
  const Scene inside = lone_body_scene("density: 2000, shape: {ellipsoid: {semi_axes: [500, 400, 300]}}", 0.0,
                                       "{states: [[2000, 0, 0, 0, 0, 0], [100, 0, 0, 0, 0, 0]]}");
  {  // a bodies' step of 10^9 particle steps: an error, not an overflowing count
    const Scene far = lone_body_scene("density: 2000, shape: {ellipsoid: {semi_axes: [500, 400, 300]}}", 0.0,
                                      "{states: [[2000, 0, 0, 0, 0, 0]], step: 1.0e-3}");
    ParticleSwarm swarm(far.system, far.particles, far.initial);
    try {
      swarm.advance(turned(far, 0.0), turned(far, 1.0e6), 1);
      ADD_FAILURE() << "10^9 substeps were taken";
    } catch (const IntegrationError& e) {
      EXPECT_NE(std::string(e.what()).find("raise particles.step"), std::string::npos) << e.what();
    }
  }
  try {
    ParticleSwarm swarm(inside.system, inside.particles, inside.initial);
    ADD_FAILURE() << "a particle inside the body was accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("particle 1 (from 0: particles.states, then file, orbits, ejecta) starts inside body 'rock'"), std::string::npos) << e.what();
  }
}

// A run of the Didymos binary with particles: each particle's fate is in /test_particles as the
// run saw it, the summary counts them, and an adaptive integrator without a particle step is
// refused.
TEST(Particles, ARunWritesEachParticlesFate) {
  const std::string particles =
      "particles={around: didymos, orbits: [{a: 1190, M: 180}, {a: 800, e: 0.3}, {a: 600, e: 0.1, i: 90}], "
      "states: [[1189, 0, 200, 0, 0.17, -0.1], [1300, 0, 300, 2, 0, 0]], escape: 3000}";
  const Scene scene = load_scene(source_path("examples/didymos.yaml"), {"run.t_end=3600", "run.output_every=600", particles});
  const std::filesystem::path file = std::filesystem::temp_directory_path() / ("noether-particles-" + std::to_string(::getpid()) + ".h5");
  PluginRegistry registry = test::bundled_plugins();
  RunOptions options;
  options.output = file;
  options.overwrite = true;
  Simulation sim(scene, registry, options);
  sim.integrate(scene.run.t_end);
  const std::vector<ParticleOutcome> outcomes = sim.particles()->outcomes();
  const Eigen::Matrix3Xd x = sim.particles()->positions();
  const State bodies = sim.state();
  const RunSummary s = sim.finish();
  ASSERT_EQ(s.particles.count, 5u);
  EXPECT_EQ(s.particles.impacts[1], 1u) << "the first lands on dimorphos";
  EXPECT_EQ(s.particles.escaped, 1u) << "the one thrown at 2 m/s";
  EXPECT_EQ(s.particles.in_flight, 3u);
  EXPECT_EQ(outcomes[0].fate, ParticleFate::impact);
  EXPECT_EQ(outcomes[1].fate, ParticleFate::escape);
  // 3000 m from Didymos after ≥ 842 s at ≤ 2 m/s (from 1334 m), at the end of a 30 s step.
  EXPECT_GE(outcomes[1].t, 842.0);
  EXPECT_LE(outcomes[1].t, 900.0);
  EXPECT_EQ(std::fmod(outcomes[1].t, 30.0), 0.0);

  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  auto read = [&](const char* path, hid_t type, std::size_t n, void* into) {
    const hid_t d = H5Dopen2(f, path, H5P_DEFAULT);
    ASSERT_GE(d, 0) << path;
    const hid_t space = H5Dget_space(d);
    EXPECT_EQ(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)), n) << path;
    EXPECT_GE(H5Dread(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, into), 0) << path;
    H5Sclose(space);
    H5Dclose(d);
  };
  std::vector<int> fate(5), body(5);
  std::vector<double> t(5), position(15), track(7 * 5 * 3);  // 7 frames: 0, 600, …, 3600
  read("/particles/test_particles/position/value", H5T_NATIVE_DOUBLE, track.size(), track.data());
  for (std::size_t i = 0; i < 5; ++i)
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_EQ(track[3 * i + k], scene.particles.position[i][static_cast<Eigen::Index>(k)]) << "frame 0: the start";
      if (outcomes[i].fate != ParticleFate::impact)
        EXPECT_EQ(track[6 * 15 + 3 * i + k], x(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(i))) << "the last frame";
    }
  {  // the landed one rides on Dimorphos at its impact point
    const Vec3 last(track[6 * 15], track[6 * 15 + 1], track[6 * 15 + 2]);
    const Vec3 riding = bodies.x.col(1) + bodies.R[1] * outcomes[0].point;
    EXPECT_LT((last - riding).norm(), 1e-9 * riding.norm());
    EXPECT_GT((last - x.col(0)).norm(), 1.0) << "Dimorphos moved on since the landing";
  }
  read("/test_particles/fate", H5T_NATIVE_INT, 5, fate.data());
  read("/test_particles/body", H5T_NATIVE_INT, 5, body.data());
  read("/test_particles/time", H5T_NATIVE_DOUBLE, 5, t.data());
  read("/test_particles/position", H5T_NATIVE_DOUBLE, 15, position.data());
  H5Fclose(f);
  std::filesystem::remove(file);
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(fate[i], static_cast<int>(outcomes[i].fate));
    EXPECT_EQ(body[i], outcomes[i].body);
    if (outcomes[i].fate != ParticleFate::in_flight) EXPECT_EQ(t[i], outcomes[i].t);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(position[3 * i + static_cast<std::size_t>(k)], x(k, static_cast<Eigen::Index>(i)));
  }

  const Scene adaptive = load_scene(source_path("examples/didymos.yaml"),
                                    {"run.t_end=3600", particles, "integrator={plugin: rk, method: rkf78}"});
  try {
    Simulation refused(adaptive, registry, RunOptions{});
    ADD_FAILURE() << "an adaptive integrator without particles.step was accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("give particles.step"), std::string::npos) << e.what();
  }
}

// Between the bodies' steps (an adaptive method's interpolated frames) the recorded positions are
// the cubic Hermite path of the step: against particles carried to that time exactly, within the
// path's error (~(30 s / 5300 s)⁴ of the orbit's size; 3.7e-9 m measured).
TEST(Particles, RecordedPositionsBetweenStepsFollowThePath) {
  const Scene scene = lone_body_scene("density: 2000, shape: {ellipsoid: {semi_axes: [500, 450, 400]}}", 3e-4,
                                      "{around: rock, orbits: [{a: 1500, e: 0.2, i: 30}, {a: 2500, i: 100, M: 40}], step: 1, "
                                      "record: 1}");
  ASSERT_EQ(scene.particles.record, 1u);
  ParticleSwarm stepped(scene.system, scene.particles, scene.initial), exact(scene.system, scene.particles, scene.initial);
  stepped.advance(turned(scene, 0.0), turned(scene, 30.0), 1);
  exact.advance(turned(scene, 0.0), turned(scene, 17.0), 1);
  Eigen::Matrix3Xd between, at;
  stepped.recorded_positions(turned(scene, 17.0), between);
  exact.recorded_positions(turned(scene, 17.0), at);
  ASSERT_EQ(between.cols(), 1);
  std::printf("between the steps: %.3e m from the particle carried to t = 17 s\n", (between - at).norm());
  EXPECT_LT((between - at).norm(), 1e-7);
  stepped.recorded_positions(turned(scene, 30.0), between);
  EXPECT_EQ(between.col(0), stepped.positions().col(0));
}

// Ejecta (39.1)–(39.2): every particle leaves from the site on the real surface (a spinning
// ellipsoid's and a polyhedron's), at the cone's angle from the normal (the gap's gradient there,
// found independently), with its speed relative to the spinning surface distributed as the power
// law says; azimuths uniform; the first k particles of a larger cloud are the same k particles.
TEST(Particles, EjectaLeaveTheSiteAtTheConeWithThePowerLawsSpeeds) {
  const double vmin = 0.05, vmax = 5.0, gamma = 1.2, cone = 45.0;
  const auto cloud = [&](int count) {
    return "{ejecta: {body: rock, site: [20, 60], count: " + std::to_string(count) +
           ", speed: [0.05, 5.0], exponent: 1.2, cone: 45, height: 1.0, seed: 7}}";
  };
  for (const std::string shape : {"density: 2200, shape: {ellipsoid: {semi_axes: [103.16, 79.35, 66.13]}}",
                                  "density: 2000, shape: {polyhedron: {file: shapes/hou2017_B.obj, units: km}}"}) {
    SCOPED_TRACE(shape);
    const int n = 20000;
    const double spin = 1.46e-4;
    const Scene scene = lone_body_scene(shape, spin, cloud(n));
    ASSERT_EQ(scene.particles.position.size(), static_cast<std::size_t>(n));
    const Body& body = scene.system.body(0);
    const Solid& solid = *body.solid;
    const Vec3 Omega = body.inertia_inverse * scene.initial.Pi.col(0);
    const Mat3& R = scene.initial.R[0];
    const Vec3 s0 = R.transpose() * (scene.particles.position[0] - scene.initial.x.col(0));
    // The outward normal at the site: the gap's gradient (distance to the face or the ellipsoid).
    Vec3 normal;
    const double d = 0.01;  // outside the surface on either side (the height is 1)
    for (int k = 0; k < 3; ++k)
      normal[k] = (surface_gap(solid, s0 + d * Vec3::Unit(k)) - surface_gap(solid, s0 - d * Vec3::Unit(k))) / (2 * d);
    normal.normalize();
    EXPECT_NEAR(surface_gap(solid, s0), 1.0, 1e-9 * solid.radius) << "the height above the surface";
    const double lat = 20 * M_PI / 180, lon = 60 * M_PI / 180;
    const Vec3 site = s0 - normal;  // 1 below, along the normal
    EXPECT_NEAR(surface_gap(solid, site), 0.0, 1e-9 * solid.radius) << "on the surface";
    EXPECT_NEAR(site.normalized().dot(Vec3(std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat))),
                1.0, 1e-12) << "on the ray of the site's latitude and longitude";
    std::array<int, 3> faster{};
    const std::array<double, 3> v_test{0.1, 0.5, 2.0};
    Vec3 mean_tangent = Vec3::Zero();
    for (int i = 0; i < n; ++i) {
      const Vec3 s = R.transpose() * (scene.particles.position[static_cast<std::size_t>(i)] - scene.initial.x.col(0));
      ASSERT_EQ(s, s0);
      const Vec3 v = R.transpose() * (scene.particles.velocity[static_cast<std::size_t>(i)] - scene.initial.p.col(0) / body.mass) -
                     Omega.cross(s);
      const double speed = v.norm();
      ASSERT_GE(speed, vmin * (1 - 1e-12));
      ASSERT_LE(speed, vmax * (1 + 1e-12));
      ASSERT_NEAR(std::acos(std::clamp(v.dot(normal) / speed, -1.0, 1.0)) * 180 / M_PI, cone, 1e-5);
      mean_tangent += (v / speed - v.dot(normal) / speed * normal) / std::sin(cone * M_PI / 180);
      for (std::size_t k = 0; k < 3; ++k) faster[k] += speed > v_test[k];
    }
    // N(>v) ∝ v^-γ truncated to [vmin, vmax] (39.1): each fraction within 4σ of its binomial spread.
    for (std::size_t k = 0; k < 3; ++k) {
      const double p = (std::pow(v_test[k], -gamma) - std::pow(vmax, -gamma)) / (std::pow(vmin, -gamma) - std::pow(vmax, -gamma));
      EXPECT_NEAR(faster[k] / double(n), p, 4 * std::sqrt(p * (1 - p) / n)) << "faster than " << v_test[k];
    }
    EXPECT_LT((mean_tangent / n).norm(), 4 * std::sqrt(1.0 / n)) << "azimuths uniform about the normal";
    // Two clouds without seeds in one scene (the k-th's default seed k + 1) draw differently.
    const Scene two = lone_body_scene(shape, spin, "{ejecta: [{body: rock, site: [20, 60], count: 3, speed: [0.05, 5.0]}, "
                                                   "{body: rock, site: [20, 60], count: 3, speed: [0.05, 5.0]}]}");
    ASSERT_EQ(two.particles.velocity.size(), 6u);
    for (std::size_t i = 0; i < 3; ++i) EXPECT_NE(two.particles.velocity[i], two.particles.velocity[3 + i]);
    const Scene first = lone_body_scene(shape, spin, cloud(100));
    for (std::size_t i = 0; i < 100; ++i) {
      EXPECT_EQ(first.particles.position[i], scene.particles.position[i]);
      EXPECT_EQ(first.particles.velocity[i], scene.particles.velocity[i]);
    }
  }
}

// A particle thrown straight up from a sphere below the escape speed falls back where it left,
// when the radial Kepler orbit says: r = a (1 − cos η), t = √(a³/μ) (η − sin η), 2a the apex; the
// time's error falls as the step's square (Verlet's order).
// The verdict judges the particles by the step-halving check (particles.check): two orbits about
// a sphere (a = 1500 m, e = 0.2; a = 2500 m), two revolutions. The check's measure is the
// particles' own error (order 2: a quarter at each halving of the step); at 500 s (87 steps an
// orbit) halving the step still moves them by 4 % of their distance — not resolved —, at 125 s
// by 0.3 %. `check: 0` leaves the particles unjudged, and the particles at h are the same.
TEST(Particles, TheVerdictHalvesTheirStep) {
  PluginRegistry registry = test::bundled_plugins();
  auto run = [&](const std::string& step, const std::string& check) {
    const Scene scene = lone_body_scene("density: 2000, shape: {ellipsoid: {semi_axes: [500, 500, 500]}}", 3e-4,
                                        "{around: rock, orbits: [{a: 1500, e: 0.2, i: 30}, {a: 2500, e: 0.1}], step: " +
                                            step + ", check: " + check + "}",
                                        "{plugin: lgvi, step: 1000}", "{t_end: 88000, output_every: 88000}");
    Simulation sim(scene, registry, RunOptions{});
    sim.integrate(scene.run.t_end);
    return std::make_pair(sim.finish(), Eigen::Matrix3Xd(sim.particles()->positions()));
  };
  const auto [coarse, x_coarse] = run("500", "32");
  const auto [middle, x_middle] = run("250", "32");
  const auto [fine, x_fine] = run("125", "32");
  const auto [unchecked, x_unchecked] = run("500", "0");
  const double p[] = {coarse.particles.check.position, middle.particles.check.position, fine.particles.check.position};
  std::printf("the check at particle steps 500, 250, 125 s moves them by %.3e, %.3e, %.3e\n", p[0], p[1], p[2]);
  EXPECT_EQ(coarse.particles.check.checked, 2u);  // of two particles, both
  EXPECT_EQ(coarse.particles.check.fates_differ, 0u);
  EXPECT_NEAR(std::log2(p[0] / p[1]), 2.0, 0.1);
  EXPECT_NEAR(std::log2(p[1] / p[2]), 2.0, 0.1);
  EXPECT_GT(p[0], 1e-2);
  EXPECT_FALSE(coarse.verdict.trustworthy);
  ASSERT_FALSE(coarse.verdict.reasons.empty());
  EXPECT_NE(coarse.verdict.reasons.back().find("the particles are not resolved: halving their step moves the checked "
                                               "ones in flight by up to 4.2"),
            std::string::npos)
      << coarse.verdict.reasons.back();
  EXPECT_LT(p[2], 1e-2);
  EXPECT_TRUE(fine.verdict.trustworthy) << (fine.verdict.reasons.empty() ? "" : fine.verdict.reasons[0]);
  EXPECT_EQ(unchecked.particles.check.checked, 0u);
  EXPECT_TRUE(unchecked.verdict.trustworthy);
  EXPECT_EQ(x_unchecked, x_coarse) << "the check leaves the particles at h as they were";
  EXPECT_NE(format_summary(coarse).find("particles at half the step    2 checked: 0 fates differ; in flight moved <= "
                                        "0.042 of their distance"),
            std::string::npos)
      << format_summary(coarse);
}

TEST(Particles, AThrowStraightUpFallsBackWhenKeplerSays) {
  const double R = 500.0, v0 = 0.3;
  double errors[2];
  ParticleOutcome landed[2];
  ParticleCheck checked;  // of the run at h: its particle carried again at h/2
  for (int halving = 0; halving < 2; ++halving) {
    const double h = 5.0 / (1 << halving);  // 2 and 4 Verlet steps a step of the bodies (10 s)
    const Scene scene = lone_body_scene("density: 2000, shape: {ellipsoid: {semi_axes: [500, 500, 500]}}", 0.0,
                                        "{ejecta: {body: rock, site: [30, 40], count: 1, speed: [0.3, 0.3], cone: 0}, "
                                        "step: " + std::to_string(h) + "}");
    const double mu = scene.system.G() * scene.system.body(0).mass;
    const Vec3 x0 = scene.particles.position[0];
    const double r0 = x0.norm();
    ASSERT_NEAR(r0, R * (1 + 1e-6), 1e-9);
    ASSERT_NEAR(scene.particles.velocity[0].dot(x0 / r0), v0, 1e-15);
    const double a = -mu / (2 * (0.5 * v0 * v0 - mu / r0));
    auto t_of = [&](double r) {
      const double eta = std::acos(1 - r / a);
      return std::sqrt(a * a * a / mu) * (eta - std::sin(eta));
    };
    const double flight = 2 * std::sqrt(a * a * a / mu) * M_PI - t_of(r0) - t_of(R);
    ParticleSwarm swarm(scene.system, scene.particles, scene.initial);
    State from = turned(scene, 0.0);
    for (int k = 1; k <= static_cast<int>(flight / 10) + 2 && swarm.outcomes()[0].fate == ParticleFate::in_flight; ++k) {
      const State to = turned(scene, 10.0 * k);
      swarm.advance(from, to, 1);
      from = to;
    }
    const ParticleOutcome& o = swarm.outcomes()[0];
    ASSERT_EQ(o.fate, ParticleFate::impact);
    errors[halving] = std::abs(o.t - flight);
    landed[halving] = o;
    if (halving == 0) checked = swarm.check(from);
    std::printf("h = %g: lands after %.9f s, Kepler %.9f s (%.3e s); %.3e m from the site\n", h, o.t, flight,
                errors[halving], (o.point - R * x0 / r0).norm());
    EXPECT_LT(errors[halving], 1e-5 * flight);
    EXPECT_LT((o.point - R * x0 / r0).norm(), 1e-6 * R) << "straight down onto the site";
    EXPECT_NEAR(o.velocity.norm(), std::sqrt(v0 * v0 + 2 * mu * (1 / R - 1 / r0)), 1e-4 * v0);
  }
  EXPECT_NEAR(std::log2(errors[0] / errors[1]), 2.0, 0.2) << "order 2";
  // The check at h landed its particle as the run at h/2 did, bit for bit (the bodies' step a
  // multiple of both: the same bodies at the same substeps).
  EXPECT_EQ(checked.fates_differ, 0u);
  EXPECT_EQ(checked.landing_time, std::abs(landed[0].t - landed[1].t));
  const Scene scene = lone_body_scene("density: 2000, shape: {ellipsoid: {semi_axes: [500, 500, 500]}}", 0.0,
                                      "{states: [[600, 0, 0, 0, 0, 0]]}");
  const BodyField field(scene.system.body(0), scene.system.G(), BodyFieldOptions{});
  EXPECT_EQ(checked.landing_point, (landed[0].point - landed[1].point).norm() / field.bounding_radius());
}

namespace {

// Whether two swarms stand in the same place with the same fates, the check's particles and the
// Verlet steps counted too, bit for bit.
void expect_same_swarm(const Simulation& x, const Simulation& y, const char* how) {
  const ParticleSwarm &a = *x.particles(), &b = *y.particles();
  EXPECT_EQ(a.positions(), b.positions()) << how;
  EXPECT_EQ(a.velocities(), b.velocities()) << how;
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    const ParticleOutcome &p = a.outcomes()[i], &q = b.outcomes()[i];
    EXPECT_EQ(p.fate, q.fate) << how << i;
    EXPECT_EQ(p.body, q.body) << how << i;
    EXPECT_TRUE(p.t == q.t || (std::isnan(p.t) && std::isnan(q.t))) << how << i;
    EXPECT_EQ(p.point, q.point) << how << i;
    EXPECT_EQ(p.velocity, q.velocity) << how << i;
  }
  EXPECT_EQ(a.particle_steps(), b.particle_steps()) << how;
  const ParticleCheck ca = a.check(x.state()), cb = b.check(y.state());
  EXPECT_EQ(ca.checked, 5u);
  EXPECT_EQ(ca.steps, cb.steps) << how;
  EXPECT_EQ(ca.position, cb.position) << how;
  EXPECT_GT(ca.position, 0.0);
  EXPECT_EQ(ca.fates_differ, cb.fates_differ) << how;
}

// A run broken at kBreak and continued to kEnd. Under the sanitizers (~50× slower) a third as
// long: the break then comes before any particle lands or escapes.
#ifdef NOETHER_TEST_SANITIZED
constexpr double kBreak = 600, kEnd = 1200;
#else
constexpr double kBreak = 1800, kEnd = 3600;
#endif

// The Didymos binary with five particles to kEnd (frames every 600 s): 0 lands on dimorphos and
// 1 (thrown at 2 m/s) escapes before t = 1800, the three on orbits stay in flight.
Scene didymos_with_five_particles() {
  const std::string particles =
      "particles={around: didymos, orbits: [{a: 1190, M: 180}, {a: 800, e: 0.3}, {a: 600, e: 0.1, i: 90}], "
      "states: [[1189, 0, 200, 0, 0.17, -0.1], [1300, 0, 300, 2, 0, 0]], escape: 3000, step: 5}";
  return load_scene(source_path("examples/didymos.yaml"),
                    {"run.t_end=" + std::to_string(kEnd), "run.output_every=600", particles});
}

// /checkpoint/particles' latest slot (its frame the highest): header (t, steps, the check's steps,
// seconds, frame) and rows, read, or written back with a checksum that matches them.
void particle_checkpoint(const std::filesystem::path& file, std::vector<double>& header, std::vector<double>& rows,
                         bool write) {
  const hid_t f = H5Fopen(file.c_str(), write ? H5F_ACC_RDWR : H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t g = H5Gopen2(f, "/checkpoint/particles", H5P_DEFAULT);
  std::string slot = "0";
  std::vector<double> other(5, -1.0);
  if (H5Aexists(g, "header_1") > 0) {
    std::vector<double> zero(5);
    const hid_t h0 = H5Aopen(g, "header_0", H5P_DEFAULT), h1 = H5Aopen(g, "header_1", H5P_DEFAULT);
    H5Aread(h0, H5T_NATIVE_DOUBLE, zero.data());
    H5Aread(h1, H5T_NATIVE_DOUBLE, other.data());
    H5Aclose(h0), H5Aclose(h1);
    if (other[4] > zero[4]) slot = "1";
  }
  const hid_t d = H5Dopen2(g, ("rows_" + slot).c_str(), H5P_DEFAULT),
              h = H5Aopen(g, ("header_" + slot).c_str(), H5P_DEFAULT),
              c = H5Aopen(g, ("checksum_" + slot).c_str(), H5P_DEFAULT);
  if (write) {
    H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, rows.data());
    H5Awrite(h, H5T_NATIVE_DOUBLE, header.data());
    const std::uint64_t sum = io::particle_checksum(header, rows);
    H5Awrite(c, H5T_NATIVE_UINT64, &sum);
  } else {
    header.resize(5);
    const hid_t space = H5Dget_space(d);
    rows.resize(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
    H5Sclose(space);
    H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, rows.data());
    H5Aread(h, H5T_NATIVE_DOUBLE, header.data());
  }
  H5Aclose(c), H5Aclose(h), H5Dclose(d), H5Gclose(g), H5Fclose(f);
}

}  // namespace

// A run with particles continues bit for bit — saved and loaded (a fresh simulation: its own
// fields and its own check), its output file loaded, and its output file continued (--resume) —:
// every particle's state and fate (one landed and one escaped before the break, the others in
// flight through it), the check's particles at half the step and the Verlet steps counted. The
// output's blocks carry the particles where they stand at their last frame; a file whose
// particles are not at its last frame, or do not match their checksum, is refused by name.
TEST(Particles, ARunWithParticlesContinuesBitwise) {
  const Scene scene = didymos_with_five_particles();
  PluginRegistry registry = test::bundled_plugins();
  const std::string tag = std::to_string(::getpid());
  const auto saved = std::filesystem::temp_directory_path() / ("noether-particles-saved-" + tag + ".h5");
  const auto output = std::filesystem::temp_directory_path() / ("noether-particles-output-" + tag + ".h5");
  Simulation whole(scene, registry);
  whole.integrate(kEnd);
  {
    RunOptions options;
    options.output = output;
    options.overwrite = true;
    Simulation first(scene, registry, options);
    first.integrate(kBreak);
    first.save(saved);
    const std::vector<ParticleOutcome>& o = first.particles()->outcomes();
    if (kBreak == 1800)
      EXPECT_EQ(std::count_if(o.begin(), o.end(), [](const ParticleOutcome& p) { return p.fate == ParticleFate::in_flight; }), 3);
    first.finish();
  }
  const RunSummary summary = whole.finish();
  if (kEnd == 3600) EXPECT_EQ(summary.particles.escaped, 1u);
  for (const auto& [from, how] : {std::pair{saved, "saved "}, std::pair{output, "output "}}) {
    const auto loaded = Simulation::load(from, registry);
    loaded->integrate(kEnd);
    expect_same_swarm(whole, *loaded, how);
    EXPECT_EQ(loaded->finish().particles.impacts, summary.particles.impacts);
  }
  std::vector<double> header, rows;
  particle_checkpoint(output, header, rows, false);
  EXPECT_EQ(header[0], kBreak);
  EXPECT_EQ(header[4], kBreak / 600);  // frames 0, 600, …, kBreak
  {
    const auto resumed = Simulation::resume(output, registry, RunOptions{}, kEnd);
    resumed->integrate(kEnd);
    expect_same_swarm(whole, *resumed, "resumed ");
    resumed->finish();
  }
  particle_checkpoint(output, header, rows, false);
  EXPECT_EQ(header[0], kEnd);
  EXPECT_EQ(header[4], kEnd / 600);
  // A kill between a block and its particles leaves them a block behind. (Which slot is the
  // other depends on how many blocks a run wrote, which wall time decides: the message names the
  // frame, and the time of whichever slot it took.)
  header[4] = kEnd / 600 - 1;
  particle_checkpoint(output, header, rows, true);
  try {
    Simulation::resume(output, registry, RunOptions{}, kEnd + 400);
    ADD_FAILURE() << "particles behind the last frame were continued";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("and the file holds them at frame " + std::to_string(int(kEnd / 600) - 1) + " (t = "),
              std::string::npos) << e.what();
  }
  particle_checkpoint(saved, header, rows, false);
  rows[20] = std::nextafter(rows[20], 1e300);  // one number changed, the checksum not
  {
    const hid_t f = H5Fopen(saved.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    const hid_t d = H5Dopen2(f, "/checkpoint/particles/rows_0", H5P_DEFAULT);
    H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, rows.data());
    H5Dclose(d), H5Fclose(f);
  }
  try {
    Simulation::load(saved, registry);
    ADD_FAILURE() << "a damaged particle checkpoint was loaded";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("/checkpoint/particles does not match its checksum"), std::string::npos) << e.what();
  }
  std::filesystem::remove(saved);
  std::filesystem::remove(output);
}

// set_state with particles keeps them where they stand, in the bodies' new field: the same state
// set again mid-run continues as the uninterrupted run (each particle's acceleration made again in
// the same field); a state at another time, or one that puts a body over a particle in flight, is
// refused by name and changes nothing.
TEST(Particles, SetStateKeepsTheParticlesWhereTheyStand) {
  const Scene scene = didymos_with_five_particles();
  PluginRegistry registry = test::bundled_plugins();
  Simulation whole(scene, registry);
  whole.integrate(kEnd);
  Simulation again(scene, registry);
  again.integrate(kBreak);
  const State here = again.state();
  State later = here;
  later.t = kBreak + 1;
  try {
    again.set_state(later);
    ADD_FAILURE() << "a state at another time than the particles' was set";
  } catch (const Error& e) {
    std::ostringstream expected;
    expected << "the particles stand at t = " << kBreak << ", the new state of the bodies is at t = " << kBreak + 1;
    EXPECT_NE(std::string(e.what()).find(expected.str()), std::string::npos) << e.what();
  }
  State over = here;  // didymos moved onto particle 2 (in flight on its orbit)
  ASSERT_EQ(again.particles()->outcomes()[2].fate, ParticleFate::in_flight);
  over.x.col(0) = again.particles()->positions().col(2);
  try {
    again.set_state(over);
    ADD_FAILURE() << "a body was set over a particle";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("particle 2 (from 0) would be inside body 'didymos'"), std::string::npos) << e.what();
  }
  EXPECT_EQ(again.state().x, here.x);
  again.set_state(here);
  again.integrate(kEnd);
  const ParticleSwarm &a = *whole.particles(), &b = *again.particles();
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a.outcomes()[i].fate, b.outcomes()[i].fate) << i;
    const double scale = a.positions().col(static_cast<Eigen::Index>(i)).norm();
    const double difference = (a.positions().col(static_cast<Eigen::Index>(i)) - b.positions().col(static_cast<Eigen::Index>(i))).norm();
    std::printf("particle %zu after set_state: %.3e of its distance from the origin off the uninterrupted run\n", i,
                difference / scale);
    EXPECT_LT(difference, 1e-12 * scale) << i;  // (0 here: the same bits)
  }
  // The new field from the next step on: a swarm made at t0 whose bodies are then set (didymos
  // 20 m over) steps as one made with the bodies there; one that kept the old accelerations does not.
  State moved = scene.initial, next = scene.initial;
  moved.x(0, 0) += 20.0;
  next.x(0, 0) += 20.5;
  next.t += 10.0;
  ParticleSwarm made_there(scene.system, scene.particles, moved), set_there(scene.system, scene.particles, scene.initial),
      not_set(scene.system, scene.particles, scene.initial);
  set_there.set_bodies(moved);
  for (ParticleSwarm* swarm : {&made_there, &set_there, &not_set}) swarm->advance(moved, next, 1);
  EXPECT_EQ(made_there.positions(), set_there.positions());
  EXPECT_NE(made_there.positions(), not_set.positions());
}
