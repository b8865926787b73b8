// The core parameter tree: typed access, errors naming file, line and field.
#include <noether/error.hpp>
#include <noether/params.hpp>

#include <gtest/gtest.h>

using namespace noether;

TEST(Params, TypedAccessAndErrors) {
  Params p = Params::map({{"step", Params::scalar("1e-3", "s.yaml:4")},
                          {"name", Params::scalar("lgvi", "s.yaml:5")}},
                         "s.yaml:3");
  p.set_path("integrator");
  EXPECT_DOUBLE_EQ(p.get("step", 0.0), 1e-3);
  EXPECT_DOUBLE_EQ(p.get("missing", 7.0), 7.0);
  try {
    p.at("name").as_double();
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_STREQ(e.what(), "s.yaml:5: 'integrator.name' must be a finite number, not 'lgvi'");
  }
  try {
    p.check_keys({"step", "nme"}, "integrator 'lgvi'");
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("s.yaml:5: unknown key 'name' in integrator 'lgvi' "
                                         "(did you mean 'nme'?)"),
              std::string::npos)
        << e.what();
  }
}

TEST(Params, EditDistanceSuggestsOnlyCloseWords) {
  EXPECT_EQ(edit_distance("intertia", "inertia"), 1u);
  EXPECT_EQ(closest_match("intertia", {"mass", "inertia", "position"}), "inertia");
  EXPECT_EQ(closest_match("xyz", {"mass", "inertia", "position"}), "");
}
