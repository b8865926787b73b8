// The resolution check of an orbit the energy cannot certify (run/resolution_check.cpp) and the
// energy's round-off floor (run/verdict.cpp; docs/user-guide.md "Verdict", "Round-off"): the
// KW4 spacecraft of examples/kw4-alpha-orbiter.yaml (0.031 J of orbit beside Alpha's 9.2e10 J of
// spin) integrated by rkf78 — its energy error is round-off, below the floor, at every
// tolerance; the adaptive run repeated at a tenfold tighter tolerance estimates its error (against
// a run at 1e-13) and trusts it; where no rerun decides, the verdict names the floor, not the
// tolerance.
#include "test_support.hpp"

#include <noether/simulation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace noether;
using test::registry;

namespace {

Scene orbiter(double rtol, std::vector<std::string> more = {}) {
  char text[64];
  std::snprintf(text, sizeof text, "integrator.rtol=%.17g", rtol);
  more.insert(more.begin(), text);
  return load_scene(test::source_path("examples/kw4-alpha-orbiter.yaml"), more);
}

Vec3 spacecraft_about_alpha(const State& s) { return s.x.col(1) - s.x.col(0); }

}  // namespace

// The floor is ε (T0 + |U0|) (1 + √steps), and it bounds the energy error of these runs (a few
// units in the last place of 9.2e10 J): the orbit's error is below what the energy can see.
TEST(ResolutionCheck, TheEnergysRoundoffFloorBoundsItsErrorHere) {
  for (const double rtol : {1e-13, 1e-11, 1e-9}) {
    SCOPED_TRACE(rtol);
    const RunSummary s = run_scene(orbiter(rtol), registry(), {});
    const double terms = s.initial.kinetic_translational + s.initial.kinetic_rotational + std::abs(s.initial.potential);
    EXPECT_DOUBLE_EQ(s.energy_roundoff, std::numeric_limits<double>::epsilon() * terms *
                                            (1 + std::sqrt(static_cast<double>(s.work.steps))));
    EXPECT_LE(s.max_abs_energy_error, s.energy_roundoff);
    ASSERT_FALSE(s.orbits.empty());
    EXPECT_EQ(s.orbits.front().body, "spacecraft");
    EXPECT_GT(s.orbits.front().relative_roundoff, 1e-2);  // so the energy cannot certify it
    EXPECT_TRUE(s.orbits.front().uncertified);
  }
}

// Repeated at a tenfold tighter tolerance: done, the difference within a factor 3 of the run's
// true error at rtol 1e-9 (against a run at 1e-13), tiny at 1e-13 — trusted, as it should be.
TEST(ResolutionCheck, AnAdaptiveRunIsRepeatedAtATenfoldTighterTolerance) {
  const RunSummary reference = run_scene(orbiter(1e-13), registry(), {});
  const ResolutionCheck& tight = reference.resolution;
  ASSERT_TRUE(tight.done);
  EXPECT_TRUE(tight.whole_run);
  EXPECT_EQ(tight.how, "at a tenfold tighter tolerance");
  EXPECT_LT(tight.over_run, 1e-9);
  EXPECT_TRUE(reference.verdict.trustworthy) << format_summary(reference);
  const RunSummary loose = run_scene(orbiter(1e-9), registry(), {});
  ASSERT_TRUE(loose.resolution.done);
  const Vec3 r = spacecraft_about_alpha(loose.final_state);
  const double truth = (r - spacecraft_about_alpha(reference.final_state)).norm() / r.norm();
  EXPECT_GT(loose.resolution.over_run, truth / 3) << truth;
  EXPECT_LT(loose.resolution.over_run, truth * 3) << truth;
  EXPECT_NE(format_summary(loose).find("resolution check              spacecraft about alpha moves by"),
            std::string::npos);
  // A tolerance the check cannot tighten below 1e-14: repeated at a tenfold looser one, an upper bound.
  const RunSummary finest = run_scene(orbiter(5e-14), registry(), {});
  ASSERT_TRUE(finest.resolution.done);
  EXPECT_EQ(finest.resolution.how, "at a tenfold looser tolerance (an upper bound)");
  EXPECT_TRUE(finest.verdict.trustworthy);
  // A position tolerance the run does not meet fails it by name: how it was repeated, and what
  // lowers the difference.
  const RunSummary strict = run_scene(orbiter(1e-9, {"run.trust.position=1e-9"}), registry(), {});
  ASSERT_FALSE(strict.verdict.trustworthy);
  EXPECT_NE(strict.verdict.reasons.front().find("the run repeated at a tenfold tighter tolerance ends"), std::string::npos)
      << strict.verdict.reasons.front();
  EXPECT_NE(strict.verdict.reasons.front().find("(a tighter tolerance?)"), std::string::npos);
}

// Where no rerun decides (a state set from outside: the scene's trajectory is another one), the
// verdict blames the round-off floor and names the remedies, not a tighter tolerance.
TEST(ResolutionCheck, WithoutARerunTheVerdictNamesTheRoundoffFloor) {
  Simulation sim(orbiter(1e-13), registry());
  sim.set_state(sim.state());
  sim.integrate(108000.0);
  const RunSummary s = sim.finish();
  EXPECT_FALSE(s.resolution.done);
  ASSERT_FALSE(s.verdict.trustworthy);
  const std::string& why = s.verdict.reasons.front();
  EXPECT_NE(why.find("spacecraft's orbit about alpha is not certified: the round-off floor of the energy's terms"),
            std::string::npos) << why;
  EXPECT_NE(why.find("no step or tolerance changes that"), std::string::npos) << why;
  EXPECT_NE(why.find("carry spacecraft as a massless particle (particles:)"), std::string::npos) << why;
}
