// StmFeature (run/stm_feature.cpp): the tangent's first N columns start at the identity or at the
// matrix a set state carries, a state whose tangent does not fit is refused, and a recorded
// frame's /derivatives/stm is read back; in a run, an STM set mid-way carries on as the product
// of the two segments' maps (M(t, t0) = M(t, t1) M(t1, t0)).
#include "test_support.hpp"

#include <noether/error.hpp>
#include <noether/simulation.hpp>

#include "io/frame_schema.hpp"
#include "run/stm_feature.hpp"

#include <gtest/gtest.h>

#include <limits>

using namespace noether;
using test::registry;

TEST(StmFeature, StartsAtTheIdentityOrTheGivenMatrixAndRefusesOneThatDoesNotFit) {
  const Scene scene = test::dumbbell_scene();
  const Eigen::Index N = State::tangent_rows(scene.system);
  detail::StmFeature feature(N);
  EXPECT_EQ(feature.tangent_columns(), N);
  Eigen::MatrixXd V = Eigen::MatrixXd::Constant(N, N, 7.0);
  State s = scene.initial;
  feature.start(s, V);
  EXPECT_TRUE(V.isIdentity(0.0));
  s.tangent = Eigen::MatrixXd::Random(N, N);
  feature.start(s, V);
  EXPECT_EQ(V, s.tangent);
  EXPECT_NO_THROW(feature.refuse_state(s));
  s.tangent = Eigen::MatrixXd::Identity(N, N + 1);
  EXPECT_THROW(feature.refuse_state(s), Error);
  s.tangent = Eigen::MatrixXd::Identity(N, N);
  s.tangent(0, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(feature.refuse_state(s), Error);
  io::RecordedFrame frame;
  frame.stm = Eigen::MatrixXd::Random(N, N);
  feature.read_frame(frame, V);
  EXPECT_EQ(V, frame.stm);
  frame.stm.resize(0, 0);  // a file without the STM
  EXPECT_THROW(feature.read_frame(frame, V), Error);
}

// The dumbbells' STM to t = 0.4 in one segment, and in two: the second started at t1 = 0.2 from
// the first's matrix (set_state with it) ends at the same matrix up to the products' round-off;
// started at the identity instead, it is M(t, t1) alone, and M(t, t1) M(t1, t0) is the whole.
TEST(StmFeature, ASetMatrixCarriesOnAsTheProductOfTheSegmentsMaps) {
  const Scene scene = test::dumbbell_scene({"integrator={plugin: lgvi, step: 0.002}", "run.t_end=0.4", "run.stm=true"});
  Simulation whole(scene, registry());
  whole.integrate(0.4);
  const Eigen::MatrixXd M = whole.state().tangent;

  Simulation split(scene, registry());
  split.integrate(0.2);
  const State at_t1 = split.state();
  split.set_state(at_t1);  // carries its STM: M(t1, t0)
  split.integrate(0.4);
  const double scale = M.norm();
  EXPECT_LT((split.state().tangent - M).norm(), 1e-12 * scale);

  Simulation second(scene, registry());
  State fresh = at_t1;
  fresh.tangent.resize(0, 0);  // the identity at t1
  second.set_state(fresh);
  EXPECT_TRUE(second.state().tangent.isIdentity(0.0));
  second.integrate(0.4);
  EXPECT_LT((second.state().tangent * at_t1.tangent - M).norm(), 1e-12 * scale);
  EXPECT_GT((second.state().tangent - M).norm(), 1e-3 * scale);  // the two segments' maps differ
}
