#pragma once
// Conjunctions on the sky: when a target passes closest to a center as a distant observer sees
// them — the middle of a mutual event of a binary (an occultation or transit when the target is
// nearer the observer, an eclipse of it or its passage behind when farther). The observable
// conjunction.time (docs/fitting.md, "Mutual-event times"; docs/equations.md §30).
#include <noether/trajectory.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace noether {

struct Conjunction {
  double t = 0.0;                // when g(t) = 0 (30.1), rising
  double separation = 0.0;       // |P r| then: the least projected distance
  bool target_in_front = false;  // r · ℓ < 0: the target is nearer the observer
  // dt/dp = −(∂g/∂p)/ġ (30.2), one entry per parameter of the trajectory's derivatives (empty
  // when it has none).
  Eigen::RowVectorXd dt_dp;
};

// Every conjunction of `target` and `center` seen along ℓ (unit, from the observer towards the
// bodies) in the run: the rising roots of g(t) = (P r)·(P u), P = I − ℓℓᵀ, found between
// consecutive frames and refined to 1e-9 of the frames' spacing on the interpolant (16.2). A
// conjunction closer to a frame interval's ends than its own is found once; two within one frame
// interval are missed — write 20 or more frames an orbit.
std::vector<Conjunction> conjunctions(const Trajectory& trajectory, std::size_t target, std::size_t center,
                                      const Eigen::Vector3d& line_of_sight);

// The conjunction nearest to t. SceneError when the run has none, or when the run ends (or
// starts) nearer to t than the nearest conjunction found is — one beyond the run could be nearer.
Conjunction nearest_conjunction(const Trajectory& trajectory, std::size_t target, std::size_t center,
                                const Eigen::Vector3d& line_of_sight, double t);
// The same from conjunctions() already found (`all`, of target and center in that trajectory):
// for many rows of one pair and line of sight, the search is done once.
Conjunction nearest_conjunction(const std::vector<Conjunction>& all, const Trajectory& trajectory, std::size_t target,
                                std::size_t center, double t);

}  // namespace noether
