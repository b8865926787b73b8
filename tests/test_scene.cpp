// Scenes: what a valid scene builds, and one clear message for each kind of bad scene.
#include "test_support.hpp"

#include <noether/error.hpp>

#include <gtest/gtest.h>

using namespace noether;

namespace {

const char* kTwoBodies = R"(G: 2
bodies:
  - {name: sun, mass: 1, position: [0, 0, 0]}
  - name: rock
    mass: 0.5
    inertia: [1, 2, 2.5]
    position: [1, 0, 0]
    velocity: [0, 1, 0]
    attitude: {quaternion: [0.7071067811865476, 0, 0, 0.7071067811865476]}
    angular_velocity: [0, 0, 3]
potential: {plugin: point-mass}
integrator: {plugin: lgvi, step: 0.01}
run: {t_end: 1, output_every: 0.1}
)";


}  // namespace

TEST(Scene, BuildsSystemAndInitialState) {
  const Scene s = parse_scene(kTwoBodies, "s.yaml");
  EXPECT_DOUBLE_EQ(s.system.G(), 2.0);
  ASSERT_EQ(s.system.size(), 2u);
  EXPECT_EQ(s.system.rigid_count(), 1u);
  EXPECT_EQ(s.system.rigid_index(0), -1);  // the point mass carries no attitude
  EXPECT_EQ(s.initial.R.size(), 1u);
  EXPECT_DOUBLE_EQ(s.initial.p(1, 1), 0.5);                          // γ = m v
  EXPECT_NEAR(s.initial.Pi(2, 0), 2.5 * 3.0, 1e-15);                 // Π = J Ω
  EXPECT_LT((s.initial.R[0] * Vec3(1, 0, 0) - Vec3(0, 1, 0)).norm(), 1e-15);  // 90° about z
  // Jd = ½ tr(J) I − J.
  EXPECT_NEAR(s.system.body(1).inertia_nonstandard(0, 0), 0.5 * 5.5 - 1.0, 1e-15);
  EXPECT_EQ(s.integrator.plugin, "lgvi");
  EXPECT_DOUBLE_EQ(s.run.output_every, 0.1);
}

TEST(Scene, OverridesByPathIndexAndBodyName) {
  const Scene s = parse_scene(kTwoBodies, "s.yaml",
                              {"integrator.step=0.02", "bodies.rock.mass=4", "bodies.0.mass=3"});
  EXPECT_DOUBLE_EQ(s.integrator.params.at("step").as_double(), 0.02);
  EXPECT_DOUBLE_EQ(s.system.body(1).mass, 4.0);
  EXPECT_DOUBLE_EQ(s.system.body(0).mass, 3.0);
  EXPECT_NE(test::scene_error(kTwoBodies, {"bodies.comet.mass=1"}).find("no 'comet'"), std::string::npos);
  EXPECT_NE(test::scene_error(kTwoBodies, {"integrator.step"}).find("expected key=value"),
            std::string::npos);
}

TEST(Scene, ImpossiblePhysicsIsRefusedWithFileLineAndField) {
  const std::string base = kTwoBodies;
  auto with = [&](const std::string& from, const std::string& to) {
    std::string t = base;
    t.replace(t.find(from), from.size(), to);
    return test::scene_error(t);
  };
  EXPECT_EQ(with("mass: 0.5", "mass: 0"), "s.yaml:5: body 'rock': mass must be positive, not 0");
  EXPECT_NE(with("[1, 2, 2.5]", "[1, 2, 3.5]").find("s.yaml:6: body 'rock': principal moments"),
            std::string::npos);
  EXPECT_NE(with("[1, 2, 2.5]", "[1, -2, 2.5]").find("positive definite"), std::string::npos);
  EXPECT_NE(with("[0.7071067811865476, 0, 0, 0.7071067811865476]", "[1, 0, 0, 1]")
                .find("s.yaml:9: quaternion of body 'rock' has norm"),
            std::string::npos);
  EXPECT_NE(with("position: [1, 0, 0]", "position: [0, 0, 0]").find("start at the same position"),
            std::string::npos);
  EXPECT_NE(with("{name: sun, mass: 1,", "{name: sun, mass: 1, angular_velocity: [0, 0, 1],")
                .find("is a point mass and cannot have 'angular_velocity'"),
            std::string::npos);
  EXPECT_NE(with("G: 2", "G: -1").find("G must be a positive number"), std::string::npos);
  EXPECT_NE(with("t_end: 1", "t_end: -1").find("'run.t_end' must be positive"), std::string::npos);
  EXPECT_NE(with("run:", "rnu:").find("unknown key 'rnu' in the scene (did you mean 'run'?)"),
            std::string::npos);
  EXPECT_NE(with("position: [1, 0, 0]", "position: [1, 0]").find("must have 3 components"),
            std::string::npos);
}

// The scene as run (stored in the output as /parameters/scene_as_run) is YAML that reads back
// into the same scene, overrides included.
TEST(Scene, AsRunReadsBackIntoTheSameScene) {
  const Scene scene = load_scene(test::source_path("examples/kw4-ellipsoids.yaml"),
                                 {"bodies.beta.mass=1.4e11", "integrator.step=30"});
  const std::string text = scene_as_run(scene);
  const Scene again = parse_scene(text, "as-run");
  ASSERT_EQ(again.system.size(), scene.system.size());
  for (std::size_t i = 0; i < scene.system.size(); ++i) {
    EXPECT_EQ(again.system.body(i).name, scene.system.body(i).name);
    EXPECT_EQ(again.system.body(i).mass, scene.system.body(i).mass);
    EXPECT_EQ(again.system.body(i).inertia, scene.system.body(i).inertia);
  }
  EXPECT_EQ(again.system.body(1).mass, 1.4e11);
  EXPECT_EQ(again.initial.x, scene.initial.x);
  EXPECT_EQ(again.initial.p, scene.initial.p);
  EXPECT_EQ(again.initial.R[0], scene.initial.R[0]);
  EXPECT_EQ(again.integrator.params.at("step").as_double(), 30.0);
  EXPECT_EQ(again.system.G(), scene.system.G());
}

// Relative initial states are resolved along chains without recursion: a scene where each of
// 20,000 bodies is placed relative to the previous one loads, and the last sits where the sum
// of the offsets puts it.
TEST(Scene, LongRelativeChainsLoad) {
  std::string text = "G: 1.0e-9\nbodies:\n  - {name: b0, mass: 1.0, position: [0, 0, 0], velocity: [0, 0.5, 0]}\n";
  const int n = 20000;
  for (int i = 1; i < n; ++i)
    text += "  - {name: b" + std::to_string(i) + ", mass: 1.0, relative_to: b" + std::to_string(i - 1) +
            ", position: [1, 0, 0]}\n";
  text += "potential: {plugin: point-mass}\nintegrator: {plugin: lgvi, step: 0.01}\n"
          "run: {t_end: 0.01, output_every: 0.01}\n";
  const Scene s = parse_scene(text, "chain.yaml");
  EXPECT_EQ(s.initial.x(0, n - 1), n - 1.0);
  EXPECT_EQ(s.initial.p(1, n - 1), 0.5);  // velocities add too (mass 1)
}
