// The scene's schema (host/src/scene/scene_schema.hpp): one table per section, which checks a
// scene's keys, gives the readers their defaults and is docs/user-guide.md's "Scene reference".
#include "test_support.hpp"

#include "scene/scene_schema.hpp"

#include <noether/ejecta.hpp>
#include <noether/error.hpp>
#include <noether/scene.hpp>

#include <gtest/gtest.h>

#include <set>

using namespace noether;
using namespace noether::detail;

namespace {

const char* kScene = R"(G: 1
bodies:
  - {name: sun, mass: 1, position: [0, 0, 0]}
  - {name: rock, mass: 1.0e-3, radius: 1.0e-4, orbit: {around: sun, a: 1, e: 0.1}}
potential: {plugin: point-mass}
integrator: {plugin: lgvi, step: 0.01}
run: {t_end: 1, output_every: 0.1}
)";

}  // namespace

// docs/user-guide.md's reference is the tables, printed.
TEST(SceneSchema, DocumentedInUserGuide) {
  const std::string guide = test::source_text("docs/user-guide.md");
  const std::string begin = "<!-- scene reference: generated from host/src/scene/scene_schema.cpp -->\n",
                    end = "<!-- end of the scene reference -->";
  const std::size_t from = guide.find(begin), to = guide.find(end);
  ASSERT_NE(from, std::string::npos) << "docs/user-guide.md lacks the line " << begin;
  ASSERT_NE(to, std::string::npos);
  EXPECT_EQ(guide.substr(from + begin.size(), to - from - begin.size()), scene_reference_markdown())
      << "docs/user-guide.md's scene reference differs from the schema; it should read:\n"
      << scene_reference_markdown();
}

// Each section: keys unique and documented; a required key without a default; a literal default
// of its row's type; every section a key points to exists, and every section but the top level
// is pointed to by a key.
TEST(SceneSchema, TablesAreWellFormed) {
  std::set<std::string> paths, pointed;
  for (const SceneSection& s : scene_sections()) {
    EXPECT_TRUE(paths.insert(std::string(s.path)).second) << "section '" << s.path << "' twice";
    std::set<std::string_view> keys;
    for (const SceneKey& k : s.keys) {
      const std::string where = std::string(s.path) + "." + std::string(k.key);
      EXPECT_TRUE(keys.insert(k.key).second) << where << " twice";
      EXPECT_FALSE(k.doc.empty()) << where << " has no doc";
      EXPECT_FALSE(k.required && !(k.otherwise.empty() && k.absent.empty())) << where << ": required, with a default";
      EXPECT_FALSE(!k.otherwise.empty() && !k.absent.empty()) << where << ": a default and words for it";
      if (!k.section.empty()) pointed.insert(std::string(k.section));
      if (k.otherwise.empty()) continue;
      const Params value = Params::scalar(std::string(k.otherwise));
      switch (k.type) {
        case KeyType::number: EXPECT_NO_THROW((void)value.as_double()) << where; break;
        case KeyType::integer: EXPECT_NO_THROW((void)value.as_int()) << where; break;
        case KeyType::flag: EXPECT_NO_THROW((void)value.as_bool()) << where; break;
        case KeyType::text: break;
        default: ADD_FAILURE() << where << ": a literal default for a " << static_cast<int>(k.type);
      }
    }
  }
  for (const std::string& p : pointed) EXPECT_TRUE(paths.count(p)) << "no section '" << p << "'";
  for (const std::string& p : paths)
    if (!p.empty()) EXPECT_TRUE(pointed.count(p)) << "no key leads to section '" << p << "'";
}

// The readers' defaults are the tables' (one place): the settings a scene that gives none of the
// keys builds are the C++ structs' own defaults, and the tables say the same numbers.
TEST(SceneSchema, DefaultsAreTheTables) {
  const Scene scene = parse_scene(kScene, "s.yaml", {"particles={around: sun, states: [[2, 0, 0, 0, 0.7, 0]]}",
                                                     "run.escape={distance: 5}"});
  const Params none = Params::map({});
  const SceneSection& run = scene_section("run");
  EXPECT_EQ(scene.run.close_approach, run.number(none, "close_approach"));
  EXPECT_EQ(scene.run.collisions, run.flag(none, "collisions"));
  EXPECT_EQ(scene.run.stm, run.flag(none, "stm"));
  EXPECT_EQ(scene.run.chaos, run.flag(none, "chaos"));
  const SceneSection& trust = scene_section("run.trust");
  const TrustThresholds defaults;
  EXPECT_EQ(scene.run.trust.energy, trust.number(none, "energy"));
  EXPECT_EQ(defaults.energy, trust.number(none, "energy"));
  EXPECT_EQ(defaults.momentum, trust.number(none, "momentum"));
  EXPECT_EQ(defaults.orthogonality, trust.number(none, "orthogonality"));
  EXPECT_EQ(defaults.position, trust.number(none, "position"));
  EXPECT_EQ(defaults.particle_fates, trust.number(none, "particle_fates"));
  EXPECT_EQ(scene.run.trust.particle_fates, defaults.particle_fates);
  ASSERT_TRUE(scene.run.escape);
  EXPECT_EQ(scene.run.escape->unbound, scene_section("run.escape").flag(none, "unbound"));
  const SceneSection& particles = scene_section("particles");
  const ParticleSettings p;
  EXPECT_EQ(scene.particles.step, particles.number(none, "step"));
  EXPECT_EQ(p.step, particles.number(none, "step"));
  EXPECT_EQ(p.degree, particles.integer(none, "degree"));
  EXPECT_EQ(scene.particles.degree, p.degree);
  EXPECT_EQ(p.tolerance, particles.number(none, "tolerance"));
  EXPECT_EQ(scene.particles.tolerance, p.tolerance);
  EXPECT_EQ(p.escape, particles.number(none, "escape"));
  EXPECT_EQ(static_cast<long>(p.record), particles.integer(none, "record"));
  EXPECT_EQ(static_cast<long>(p.check), particles.integer(none, "check"));
  const EjectaSettings cloud;
  const SceneSection& ejecta = scene_section("particles.ejecta");
  EXPECT_EQ(cloud.exponent, ejecta.number(none, "exponent"));
  EXPECT_EQ(cloud.cone, ejecta.number(none, "cone"));
  EXPECT_EQ(cloud.height, ejecta.number(none, "height"));
  // A key the table gives no default has none to read: its reader must decide.
  EXPECT_THROW((void)run.number(none, "t_end"), std::logic_error);
  EXPECT_THROW((void)run.number(none, "no_such_key"), std::logic_error);
}

// An unknown key, in any section, is named with its line, the closest known key and, when
// another section has it, that section.
TEST(SceneSchema, UnknownKeysAreNamedWithTheClosestAndTheirSection) {
  struct Case {
    std::string set, expected;
  };
  const Case cases[] = {
      {"run.trust={enrgy: 1}", "unknown key 'enrgy' in 'run.trust' (did you mean 'energy'?)"},
      {"run.escape={distanse: 3}", "unknown key 'distanse' in 'run.escape' (did you mean 'distance'?)"},
      {"bodies.rock.orbit.omgea=3", "unknown key 'omgea' in the orbit of body 'rock' (did you mean 'omega'?)"},
      {"bodies.rock.velocty=[0, 1, 0]", "unknown key 'velocty' in body 'rock' (did you mean 'velocity'?)"},
      {"units={lenght: km}", "unknown key 'lenght' in 'units' (did you mean 'length'?)"},
      {"t_end=3", "unknown key 't_end' in the scene"},
      {"impulses=[{body: rock, time: 0.5, delta_v: [0, 0.1, 0], frme: rtn}]",
       "unknown key 'frme' in 'impulses.0' (did you mean 'frame'?)"},
      {"particles={around: sun, states: [[2, 0, 0, 0, 0.7, 0]], chek: 3}",
       "unknown key 'chek' in 'particles' (did you mean 'check'?)"},
  };
  for (const Case& c : cases) {
    const std::string error = test::scene_error(kScene, {c.set});
    EXPECT_NE(error.find(c.expected), std::string::npos) << c.set << ": " << error;
  }
  // A key of another section says which.
  EXPECT_NE(test::scene_error(kScene, {"t_end=3"}).find("; 't_end' is a key of 'run'"), std::string::npos);
  EXPECT_NE(test::scene_error(kScene, {"bodies.rock.a=2"}).find("'a' is a key of 'bodies[].orbit', 'particles.orbits[]'"),
            std::string::npos)
      << test::scene_error(kScene, {"bodies.rock.a=2"});
}

// A value of the wrong form is refused at its own line, before anything reads it; a missing
// required key is named with what it is.
TEST(SceneSchema, TypesAndRequiredKeysAreChecked) {
  auto with = [](const std::string& from, const std::string& to) {
    std::string text = kScene;
    text.replace(text.find(from), from.size(), to);
    return test::scene_error(text);
  };
  EXPECT_NE(with("t_end: 1,", "t_end: 1, collisions: maybe,").find("s.yaml:7: 'run.collisions' must be true or false"),
            std::string::npos);
  EXPECT_NE(with("e: 0.1", "e: small").find("s.yaml:4: 'bodies.1.orbit.e' must be a finite number"), std::string::npos);
  EXPECT_NE(with("radius: 1.0e-4,", "radius: 1.0e-4, velocity: [1, 2],").find("s.yaml:4: 'bodies.1.velocity' must have 3 "
                                                                            "components, not 2"),
            std::string::npos);
  EXPECT_NE(with("{t_end: 1, ", "{").find("'run' needs 't_end' (final time"), std::string::npos);
  EXPECT_NE(with("around: sun, a: 1,", "around: sun,").find("the orbit of body 'rock' needs 'a' (semi-major axis"),
            std::string::npos);
  EXPECT_NE(test::scene_error(kScene, {"bodies.rock.orbit.around=~"}).find("needs 'around'"), std::string::npos);
}

// The scene fuzzer's dictionary (tests/fuzz/scene.dict) knows every key, so that fuzzing reaches
// every section's reader.
TEST(SceneSchema, FuzzDictionaryHasEveryKey) {
  const std::string dictionary = test::source_text("tests/fuzz/scene.dict");
  for (const SceneSection& s : scene_sections())
    for (const SceneKey& k : s.keys)
      EXPECT_NE(dictionary.find("\"" + std::string(k.key) + ":\""), std::string::npos)
          << "tests/fuzz/scene.dict lacks \"" << k.key << ":\" (" << s.path << ")";
}
