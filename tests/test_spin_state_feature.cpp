// SpinStateFeature (run/spin_state_feature.cpp): the rigid bodies' spin states followed frame by
// frame, restarted with each segment, their running values carried through a saved summary.
#include "test_support.hpp"

#include <noether/simulation.hpp>

#include "run/spin_state_feature.hpp"
#include "run/summary_schema.hpp"

#include <gtest/gtest.h>

#include <cstring>

using namespace noether;
using test::registry;

namespace {

// The tumbling moon's frames every 0.05 up to t = 10.
std::vector<State> frames_of(const Scene& scene) {
  std::vector<State> out{scene.initial};
  Simulation sim(scene, registry());
  for (int k = 1; k <= 200; ++k) {
    sim.integrate(0.05 * k);
    out.push_back(sim.state());
  }
  return out;
}

void expect_same(const std::vector<SpinState>& a, const std::vector<SpinState>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].body, b[k].body);
    for (const auto member : {&SpinState::libration_amplitude, &SpinState::turns, &SpinState::max_nutation,
                              &SpinState::max_roll})  // bit for bit (a body at rest has NaN angles)
      EXPECT_EQ(std::memcmp(&(a[k].*member), &(b[k].*member), sizeof(double)), 0) << a[k].body;
  }
}

}  // namespace

// Frames 0..200 seen at once, or 0..100 then saved (save_running) and 101..200 seen by a new
// feature restored from it: the same spin states, bit for bit; a segment's first frame forgets
// what was seen before it.
TEST(SpinStateFeature, RunningValuesCarryOverASavedSummary) {
  const Scene scene = load_scene(test::source_path("examples/tumbling-moon.yaml"), {"run.t_end=10", "run.output_every=0.05"});
  const std::vector<State> frames = frames_of(scene);
  RunSummary unused;
  detail::SpinStateFeature whole(scene.system);
  for (std::size_t k = 0; k < frames.size(); ++k) whole.observe_frame(frames[k], k == 0, unused);
  RunSummary expected;
  whole.summarize(expected);
  ASSERT_EQ(expected.spin_states.size(), 2u);
  EXPECT_EQ(expected.spin_states[1].body, "moon");
  EXPECT_GT(expected.spin_states[1].max_nutation, 0.0);  // it tumbles

  detail::SpinStateFeature first(scene.system), second(scene.system);
  for (std::size_t k = 0; k <= 100; ++k) first.observe_frame(frames[k], k == 0, unused);
  detail::SavedSummary saved;
  first.save_running(saved);
  ASSERT_NE(saved.number("spin_state"), nullptr);
  second.restore_running(saved);
  for (std::size_t k = 101; k < frames.size(); ++k) second.observe_frame(frames[k], false, unused);
  RunSummary got;
  second.summarize(got);
  expect_same(got.spin_states, expected.spin_states);

  // A new segment at frame 0 after frames it must forget (the second half seen first).
  detail::SpinStateFeature restarted(scene.system);
  for (std::size_t k = 150; k < frames.size(); ++k) restarted.observe_frame(frames[k], k == 150, unused);
  for (std::size_t k = 0; k < frames.size(); ++k) restarted.observe_frame(frames[k], k == 0, unused);
  RunSummary again;
  restarted.summarize(again);
  expect_same(again.spin_states, expected.spin_states);
}
