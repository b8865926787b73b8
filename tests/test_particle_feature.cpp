// ParticleFeature (run/particle_feature.cpp): the swarm carried over every step the bodies take,
// exactly as ParticleSwarm::advance carries it; the scene's refusals located; a state set from
// outside refused before anything changes; its checkpoint beside the frames continued from or
// refused.
#include "test_support.hpp"

#include <noether/error.hpp>
#include <noether/lie.hpp>
#include <noether/simulation.hpp>

#include "io/h5.hpp"
#include "run/particle_feature.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <unistd.h>

using namespace noether;
using test::registry;

namespace {

// A spinning ellipsoid of 2000 kg/m³ and three particles about it.
Scene rock(const std::string& integrator = "{plugin: lgvi, step: 10}", const std::string& step = "") {
  return parse_scene("units: SI\nG: 6.674e-11\nbodies:\n"
                     "  - {name: rock, density: 2000, shape: {ellipsoid: {semi_axes: [500, 450, 400]}}, "
                     "position: [0, 0, 0], angular_velocity: [0, 0, 3e-4]}\n"
                     "potential: {plugin: point-mass}\nintegrator: " + integrator +
                         "\nrun: {t_end: 200, output_every: 100}\n"
                         "particles: {" + step + "states: [[900, 0, 0, 0, 0.3, 0], [0, 1200, 0, -0.25, 0, 0.05], "
                         "[0, 0, 700, 0.2, 0, 0]]}\n",
                     test::source_path("examples/particles-test.yaml"));
}

// The bodies' state at t: at rest, turned by the rock's uniform spin.
State turned(const Scene& scene, double t) {
  State s = scene.initial;
  s.t = t;
  s.R[0] = exp_so3(t * (scene.system.body(0).inertia_inverse * s.Pi.col(0)));
  return s;
}

}  // namespace

// Steps of 10 s through the feature's hooks, and the same steps given to a swarm directly: the
// same particles, bit for bit.
TEST(ParticleFeature, CarriesTheSwarmOverEachStepAsTheSwarmDoes) {
  const Scene scene = rock();
  auto integrator = registry().make_integrator(scene.integrator.plugin, scene.system,
                                               make_scene_potential(scene, registry()), scene.integrator.params);
  detail::ParticleFeature feature(scene, *integrator, scene.initial, nullptr, 1);
  ParticleSwarm direct(scene.system, scene.particles, scene.initial);
  Eigen::MatrixXd none(12, 0);
  feature.before_steps(scene.initial);
  for (int k = 1; k <= 20; ++k) {
    feature.after_step(turned(scene, 10.0 * k), none);
    direct.advance(turned(scene, 10.0 * (k - 1)), turned(scene, 10.0 * k), 1);
  }
  EXPECT_EQ(feature.swarm().time(), 200.0);
  EXPECT_TRUE(feature.swarm().positions() == direct.positions());
  EXPECT_TRUE(feature.swarm().velocities() == direct.velocities());
  EXPECT_GT((feature.swarm().positions().col(0) - Eigen::Vector3d(900, 0, 0)).norm(), 10.0);  // they moved
  RunSummary summary;
  summary.final_state = turned(scene, 200.0);
  feature.summarize(summary);
  EXPECT_EQ(summary.particles.count, 3u);
  EXPECT_EQ(summary.particles.in_flight + summary.particles.escaped + summary.particles.impacts.at(0), 3u);
  EXPECT_EQ(summary.particles.steps, direct.particle_steps());
}

// An integrator that chooses its own steps needs particles.step, said at the particles' block; a
// state set at another time than the particles' is refused as set_state's.
TEST(ParticleFeature, RefusalsSayWhereAndWhy) {
  const Scene adaptive = rock("{plugin: rk, method: rkf78, rtol: 1e-10, atol: 1e-12}");
  auto integrator = registry().make_integrator(adaptive.integrator.plugin, adaptive.system,
                                               make_scene_potential(adaptive, registry()), adaptive.integrator.params);
  try {
    detail::ParticleFeature feature(adaptive, *integrator, adaptive.initial, nullptr, 1);
    ADD_FAILURE() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("particles.step"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("particles-test.yaml"), std::string::npos) << e.what();
  }
  const Scene with_step = rock("{plugin: rk, method: rkf78, rtol: 1e-10, atol: 1e-12}", "step: 20, ");
  detail::ParticleFeature feature(with_step, *integrator, with_step.initial, nullptr, 1);
  try {
    feature.accept_state(turned(with_step, 50.0));
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("set_state: ", 0), 0u) << e.what();
  }
  EXPECT_EQ(feature.swarm().time(), 0.0);  // unchanged
}

// The output file keeps the summary's verdict, the particles' check included: particles whose
// step is too long are called untrustworthy in the file as in the summary (the file said
// "trustworthy" before: its verdict was judged without the features' parts).
TEST(ParticleFeature, TheFilesVerdictSeesTheParticlesCheck) {
  const Scene scene = parse_scene(
      "units: SI\nG: 6.674e-11\nbodies:\n"
      "  - {name: rock, density: 2000, shape: {ellipsoid: {semi_axes: [500, 500, 500]}}, position: [0, 0, 0], "
      "angular_velocity: [0, 0, 3e-4]}\n"
      "potential: {plugin: point-mass}\nintegrator: {plugin: lgvi, step: 1000}\n"
      "run: {t_end: 88000, output_every: 88000}\n"
      "particles: {around: rock, orbits: [{a: 1500, e: 0.2, i: 30}, {a: 2500, e: 0.1}], step: 500, check: 32}\n",
      test::source_path("examples/particles-test.yaml"));
  const auto file = std::filesystem::temp_directory_path() / ("noether-particle-verdict-" + std::to_string(::getpid()) + ".h5");
  RunOptions options;
  options.output = file;
  options.overwrite = true;
  const RunSummary s = run_scene(scene, registry(), options);
  ASSERT_FALSE(s.verdict.trustworthy);
  const io::H5Handle f(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  const io::H5Handle work(H5Gopen2(f, "/work", H5P_DEFAULT));
  EXPECT_EQ(io::read_string(work, "verdict", false), "untrustworthy");
  EXPECT_NE(io::read_string(work, "verdict_reasons", false).find("the particles are not resolved"), std::string::npos);
  std::filesystem::remove(file);
}

// What the feature keeps beside its fields (continue_from, save_into): a loaded run's particles
// stand where the file's checkpoint has them at its last frame, bit for bit; a file without that
// checkpoint is refused by load and by a continuation alike, saying what it lacks, and is left
// as it was.
TEST(ParticleFeature, AContinuationStartsFromTheirCheckpointOrIsRefused) {
  const Scene scene = rock();
  const auto file = std::filesystem::temp_directory_path() / ("noether-particle-continue-" + std::to_string(::getpid()) + ".h5");
  RunOptions options;
  options.output = file;
  options.overwrite = true;
  Eigen::Matrix3Xd where;
  {
    Simulation sim(scene, registry(), options);
    sim.integrate(scene.run.t_end);
    where = sim.particles()->positions();
    sim.finish();
  }
  {
    const auto loaded = Simulation::load(file, registry(), {});
    ASSERT_NE(loaded->particles(), nullptr);
    EXPECT_EQ(loaded->particles()->time(), scene.run.t_end);
    EXPECT_EQ(loaded->particles()->positions(), where);
  }
  {  // the checkpoint taken out of the file
    const io::H5Handle f(H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT));
    ASSERT_GE(H5Ldelete(f, "/checkpoint/particles", H5P_DEFAULT), 0);
  }
  const auto size = std::filesystem::file_size(file);
  for (const bool resume : {false, true}) {
    try {
      if (resume)
        Simulation::resume(file, registry(), {}, 400.0);
      else
        Simulation::load(file, registry(), {});
      ADD_FAILURE() << "no error";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("massless particles needs them where they stood at its last frame 2"),
                std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("the file holds none"), std::string::npos) << e.what();
    }
    EXPECT_EQ(std::filesystem::file_size(file), size);
  }
  std::filesystem::remove(file);
}
