#pragma once
// State: what changes during a run (docs/equations.md §1), stored as contiguous arrays. Positions and
// linear momenta for every body; attitudes R and body angular momenta Π for rigid bodies only,
// indexed by System::rigid_index().
#include <noether/lie.hpp>
#include <noether/system.hpp>

#include <vector>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

struct State {
  double t = 0.0;
  Eigen::Matrix3Xd x;      // x_i, inertial positions
  Eigen::Matrix3Xd p;      // γ_i = m_i v_i, inertial linear momenta
  std::vector<Mat3> R;     // R_k ∈ SO(3), body → inertial, rigid bodies only
  Eigen::Matrix3Xd Pi;     // Π_k = J_k Ω_k, body frame, rigid bodies only

  // A state of the right shape for `system`: zeros, identity attitudes.
  static State zeros(const System& system);
};

}  // namespace noether

#pragma GCC visibility pop
