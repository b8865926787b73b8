#pragma once
// Values a scene may give but that look like slips of units (issue 63, item 4): each warning
// gives the numbers, the key with its file:line, and what the value would be in the unit that
// was probably meant. Nothing is changed: a warning, not an error (a monolith may spin past
// breakup; a scene may mean what it says).
#include <noether/scene.hpp>

#include <string>
#include <vector>

namespace noether::detail {

// The scene's input warnings (Scene::warnings), from its resolved tree, bodies and initial state:
// - a natural body (heavier than 1e6 kg, or any body in a scene of its own units) spinning more
//   than 10 times its breakup rate √(G M / R³) (R its bounding radius): an angular velocity in
//   deg/day or deg/s typed for rad/<time>;
// - a fixed step longer than half the shortest period the scene starts with (a bound pair's
//   Kepler period, a rigid body's spin period 2π/|Ω|): fewer than two steps a period;
// - a shaped body given a mass whose density (mass over the shape's volume) is outside
//   50–25000 kg/m³ (comets to osmium): a mesh in m read as km, or semi-axes in the wrong unit.
std::vector<std::string> input_warnings(const Scene& scene);

}  // namespace noether::detail
