// ForceBalanceFeature (run/force_balance_feature.cpp): each force's work and momenta read from
// the state's balance into the summary at every frame, started at zero with each new segment.
#include "test_support.hpp"

#include <noether/force_model.hpp>
#include <noether/simulation.hpp>

#include "run/force_balance_feature.hpp"

#include <gtest/gtest.h>

using namespace noether;
using test::registry;

namespace {

// The tidal spin-down with a dissipative tide only (no static bulge): W < 0 grows.
Scene tidal_scene() { return test::tidal_scene({"forces.0.static_bulge=false", "run.t_end=20"}); }

}  // namespace

// Column j of the balance is force j's (W, ΔP, ΔL) in the summary; a new segment zeroes it.
TEST(ForceBalanceFeature, ReadsEachForcesColumnAndStartsAtZero) {
  detail::ForceBalanceFeature feature(2);
  State s;
  s.force_balance = Eigen::MatrixXd::Zero(kBalanceRows, 2);
  for (Eigen::Index r = 0; r < kBalanceRows; ++r) s.force_balance(r, 0) = 1.0 + static_cast<double>(r), s.force_balance(r, 1) = -10.0 * static_cast<double>(r);
  RunSummary summary;
  summary.forces = {{"tides a"}, {"tides b"}};
  feature.observe_frame(s, true, summary);
  EXPECT_EQ(summary.forces[0].work, 1.0);
  EXPECT_EQ(summary.forces[0].linear_momentum, Vec3(2, 3, 4));
  EXPECT_EQ(summary.forces[0].angular_momentum, Vec3(5, 6, 7));
  EXPECT_EQ(summary.forces[1].work, 0.0);
  EXPECT_EQ(summary.forces[1].angular_momentum, Vec3(-40, -50, -60));
  feature.begin_segment(s);
  ASSERT_EQ(s.force_balance.rows(), kBalanceRows);
  ASSERT_EQ(s.force_balance.cols(), 2);
  EXPECT_TRUE(s.force_balance.isZero(0.0));
}

// In a run: the summary's work is the balance the integrator carried to the last frame; a state
// set from outside starts it again at zero, and the work after it is the tide's from there.
TEST(ForceBalanceFeature, ARunsSummaryIsItsBalanceFromEachSegmentsStart) {
  const Scene scene = tidal_scene();
  Simulation sim(scene, registry());
  sim.integrate(10.0);
  const double W_first = sim.summary().forces.at(0).work;
  EXPECT_EQ(W_first, sim.state().force_balance(0, 0));
  EXPECT_LT(W_first, 0.0);
  sim.set_state(sim.state());
  EXPECT_EQ(sim.summary().forces.at(0).work, 0.0);
  EXPECT_TRUE(sim.state().force_balance.isZero(0.0));
  sim.integrate(20.0);
  const double W_second = sim.summary().forces.at(0).work;
  EXPECT_EQ(W_second, sim.state().force_balance(0, 0));
  EXPECT_LT(W_second, 0.0);
  // The same tide over the second half, from the same state, without the break: the same work.
  Simulation whole(scene, registry());
  whole.integrate(20.0);
  EXPECT_NEAR(W_first + W_second, whole.summary().forces.at(0).work, 1e-12 * std::abs(W_first + W_second));
}
