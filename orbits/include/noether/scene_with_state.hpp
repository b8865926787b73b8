#pragma once
// A scene's text with another state: the scene's bodies (masses, shapes, inertia), units,
// potential and integrator as it was run, each body's initial state replaced by `state`
// (position, velocity, attitude as a matrix, body-frame angular velocity), and a run of
// `t_end` with `frames` output frames (a fixed integrator step is shortened so that every frame
// is a whole number of steps). What `noether orbit equilibrium -o` and `orbit refine` write.
#include <noether/scene.hpp>
#include <noether/state.hpp>

#include <string>

namespace noether {

std::string scene_with_state(const Scene& scene, const State& state, double t_end, int frames,
                             const std::string& description);

// The frames to write a run of `t_end` with: about the scene's own count (t_end / output_every)
// and, for a fixed step h with t_end = N h, a divisor of N, so that scene_with_state keeps h (a
// discrete periodic orbit of the LGVI is one of the map with that step).
int frames_keeping_step(const Scene& scene, double t_end);

}  // namespace noether
