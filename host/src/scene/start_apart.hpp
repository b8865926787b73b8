#pragma once
// Bodies apart where a run starts: no two at the same position (their mutual force is infinite),
// and, when the run stops at collisions, no body inside another's surface (the event could not
// be located). The scene's initial state and Simulation::set_state are held to the same rule.
#include <noether/state.hpp>
#include <noether/system.hpp>

#include <optional>
#include <string>

namespace noether::detail {

struct StartConflict {
  std::size_t body = 0;  // the later body of the pair: its scene entry is where the error points
  std::string what;      // "bodies 'a' and 'b' start at the same position", with the numbers
};

// The first pair that breaks the rule, if any. Coincident positions are found in O(N log N)
// (equal positions are neighbours in lexicographic order); overlaps are looked for when
// `collisions` and N ≤ 64 (O(N²) pairs of surfaces). An overlap's message gives the depth, the
// centres' distance and the bodies' sizes, and names the units of a mesh file (a mesh read in
// the wrong units is 1000 times too large or too small).
std::optional<StartConflict> start_conflict(const System& system, const State& state, bool collisions);

}  // namespace noether::detail
