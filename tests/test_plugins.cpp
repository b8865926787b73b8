// The plugin registry: loading by name, and a clear refusal for every broken plugin.
#include "test_support.hpp"

#include <noether/error.hpp>

#include <gtest/gtest.h>

using namespace noether;

namespace {
std::string plugin_error(PluginRegistry& r, const std::string& name) {
  try {
    r.info(name);
  } catch (const PluginError& e) {
    return e.what();
  }
  return "no error";
}
}  // namespace

TEST(Plugins, BundledPluginsLoadByName) {
  auto r = test::bundled_plugins();
  EXPECT_EQ(r.names(), (std::vector<std::string>{"cannonball", "central-field", "cvode", "jm-hybrid", "lgvi", "mutual-exact", "mutual-series", "point-mass", "prescribed-body", "radiation", "rk", "sphere-cluster", "spherical-harmonics", "tides"}));
  EXPECT_EQ(r.info("lgvi").kind, PluginKind::Integrator);
  EXPECT_EQ(r.info("tides").kind, PluginKind::Force);
  EXPECT_EQ(r.info("sphere-cluster").kind, PluginKind::Potential);
  EXPECT_FALSE(r.info("lgvi").params.empty());
}

TEST(Plugins, UnknownNameListsTheNamesFound) {
  auto r = test::bundled_plugins();
  const std::string e = plugin_error(r, "lgiv");
  EXPECT_NE(e.find("unknown plugin 'lgiv' (did you mean 'lgvi'?); plugins found: cannonball central-field cvode "
                   "jm-hybrid lgvi mutual-exact mutual-series point-mass prescribed-body radiation rk sphere-cluster "
                   "spherical-harmonics tides"),
            std::string::npos)
      << e;
}

TEST(Plugins, OtherApiVersionIsRefusedNamingBoth) {
  PluginRegistry r({NOETHER_FIXTURE_PLUGIN_DIR});
  const std::string e = plugin_error(r, "wrong-api");
  EXPECT_NE(e.find("plugin 'wrong-api'"), std::string::npos) << e;
  EXPECT_NE(e.find("built for plugin API version " + std::to_string(NOETHER_PLUGIN_API_VERSION + 41)),
            std::string::npos) << e;
  EXPECT_NE(e.find("this noether uses plugin API version " + std::to_string(NOETHER_PLUGIN_API_VERSION)),
            std::string::npos) << e;
}

TEST(Plugins, LibraryWithoutDescriptorIsRefusedByName) {
  PluginRegistry r({NOETHER_FIXTURE_PLUGIN_DIR});
  const std::string e = plugin_error(r, "no-descriptor");
  EXPECT_NE(e.find("plugin 'no-descriptor'"), std::string::npos) << e;
  EXPECT_NE(e.find("has no symbol 'noether_plugin_descriptor'"), std::string::npos) << e;
}

TEST(Plugins, LoadAllReportsBrokenPluginsWithoutThrowing) {
  PluginRegistry r({NOETHER_FIXTURE_PLUGIN_DIR, NOETHER_TEST_PLUGIN_DIR});
  std::vector<std::string> failures;
  const auto found = r.load_all(failures);
  EXPECT_EQ(found.size(), 18u);  // 14 bundled + 4 fixtures that load but misbehave later
  EXPECT_EQ(failures.size(), 2u);
}

TEST(Plugins, KindAndParametersAreChecked) {
  auto r = test::bundled_plugins();
  const Scene scene = test::dumbbell_scene();
  auto potential = r.make_potential("sphere-cluster", scene.system, Params());
  try {
    r.make_integrator("point-mass", scene.system, potential, Params());
    FAIL();
  } catch (const PluginError& e) {
    // The alternatives come from file names: no other library is loaded to learn its kind.
    EXPECT_NE(std::string(e.what()).find("'point-mass' is a potential, not an integrator; other plugins found: "
                                         "cannonball central-field cvode jm-hybrid lgvi mutual-exact mutual-series prescribed-body "
                                         "radiation rk spherical-harmonics tides (`noether plugins` shows the kind of each)"),
              std::string::npos) << e.what();
  }
  const Scene misspelled = test::dumbbell_scene({"integrator.stepp=0.1"});
  try {
    r.make_integrator("lgvi", misspelled.system, potential, misspelled.integrator.params);
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown key 'stepp' in integrator plugin 'lgvi' "
                                         "(did you mean 'step'?)"),
              std::string::npos) << e.what();
  }
  const Scene missing = test::dumbbell_scene({"integrator={plugin: lgvi}"});
  try {
    r.make_integrator("lgvi", missing.system, potential, missing.integrator.params);
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("needs 'step'"), std::string::npos) << e.what();
  }
}

// ParamDoc is the one place of every default: each literal default of a bundled plugin reads as
// its declared type (the host fills it in, and the plugin reads it with at()); a default the
// plugin works out itself is a description in parentheses. A plugin made with no parameters
// but the required ones therefore reads every key from its documentation.
TEST(Plugins, DocumentedDefaultsAreValuesOfTheirType) {
  auto r = test::bundled_plugins();
  int literal = 0;
  for (const auto& name : r.names()) {
    for (const auto& doc : r.info(name).params) {
      if (!doc.default_value || doc.default_value[0] == '(') continue;
      ++literal;
      const std::string type = doc.type, where = name + "." + doc.name;
      const Params value = Params::scalar(doc.default_value);
      if (type == "number") EXPECT_NO_THROW(value.as_double()) << where;
      else if (type == "integer") EXPECT_NO_THROW(value.as_int()) << where;
      else if (type == "bool") EXPECT_NO_THROW(value.as_bool()) << where;
      else if (type == "list") EXPECT_EQ(doc.default_value[0], '[') << where;
      else EXPECT_EQ(type, "string") << where;
    }
  }
  EXPECT_GE(literal, 20);
  // Every integrator made from its required keys alone (each reads its defaults with at()).
  const Scene scene = test::dumbbell_scene();
  auto potential = r.make_potential("sphere-cluster", scene.system, Params());
  for (const char* integrator : {"lgvi", "rk", "cvode"}) {
    Params params = Params::map({{"plugin", Params::scalar(integrator)}});
    if (std::string(integrator) == "lgvi") params.set("step", Params::scalar("0.001"));
    EXPECT_NO_THROW(r.make_integrator(integrator, scene.system, potential, params)) << integrator;
  }
}

// Objects made by a plugin keep its library loaded after the registry is gone.
TEST(Plugins, ObjectsOutliveTheRegistry) {
  const Scene scene = test::dumbbell_scene();
  std::shared_ptr<const Potential> potential;
  {
    auto r = test::bundled_plugins();
    potential = r.make_potential("sphere-cluster", scene.system, Params());
  }
  Forces f;
  f.resize(scene.system);
  potential->evaluate(scene.initial, f);
  EXPECT_NEAR(f.U, -1.0232, 1e-4);
}
